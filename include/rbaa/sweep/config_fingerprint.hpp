#pragma once
// What a sweep's rows ran on besides their arguments: the base config's contents and the files
// the row names. A row's arguments name the config by its path (--config=FILE), so an edit of
// FILE, of a file it builds on (`base:`), of a mesh it reads or of a file a row's value or flag
// names (--adversarial=FILE) would leave a finished row looking like the grid's row; each row's
// marker (sweep_row.json) keeps this fingerprint and resume compares it (read_sweep_outcomes).
//
// Unlike scene_fingerprint, which leaves out the settings that do not change an attack's result
// (for `rbaa attack --resume`), every setting counts here: a row can be any verb, `rbaa evaluate`
// reads evaluation.*, and results.csv reports attack.iterations. Comments and layout do not count.

#include <string>

#include "rbaa/sweep/sweep_grid.hpp"

namespace rbaa {

/// 16 hex digits (FNV-1a, 64 bit) over config_fingerprint_text.
std::string config_fingerprint(const SweepGrid& grid);

/// The text hashed: grid.config with its `base:` chain merged (merged_config_text: comments and
/// layout dropped; "unloadable" when it does not load), then the
/// scene_fingerprint of the scene that config and the grid's set: make (mesh, surface, obstacle
/// and materials files by content), or "unloadable" when it does not load (its rows then fail
/// with the scene's error). Files a row's own overrides or the grid's flags name are the row's:
/// row_config_fingerprint.
std::string config_fingerprint_text(const SweepGrid& grid);

/// The fingerprint a row's marker keeps: `config_fingerprint` (of `grid`) when the row's own
/// overrides and the grid's flags name no existing file, else 16 hex digits over it and
/// row_files_text, so that an edit of such a file (rows: [{mesh.file: b2.msh}], flags:
/// {adversarial: a.msh}) counts as one of the config's.
std::string row_config_fingerprint(const std::string& config_fingerprint, const SweepGrid& grid,
                                   const SweepRow& row);

/// One line per existing regular file named by a value of the row's overrides (a scalar or an item
/// of a flat list, relative to the config's folder, as --set paths are) or of the grid's flags
/// (relative to the current folder, where the rows run), with its bytes' fingerprint; "" when
/// none names one.
std::string row_files_text(const SweepGrid& grid, const SweepRow& row);

}  // namespace rbaa
