#pragma once
// What a sweep's rows ran on besides their arguments: the base config's contents. A row's
// arguments name the config by its path (--config=FILE), so an edit of FILE, of a file it builds
// on (`base:`) or of a mesh it reads would leave a finished row looking like the grid's row;
// each row's marker (sweep_row.json) keeps this fingerprint and resume compares it
// (read_sweep_outcomes).
//
// Unlike scene_fingerprint, which leaves out the settings that do not change an attack's result
// (for `rbaa attack --resume`), every setting counts here: a row can be any verb, `rbaa evaluate`
// reads evaluation.*, and results.csv reports attack.iterations. Comments and layout do not count.

#include <string>

#include "rbaa/sweep/sweep_grid.hpp"

namespace rbaa {

/// 16 hex digits (FNV-1a, 64 bit) over config_fingerprint_text.
std::string config_fingerprint(const SweepGrid& grid);

/// The text hashed: one line per YAML document of grid.config and its `base:` chain, each as
/// yaml-cpp re-emits it (comments dropped; the raw bytes if it is not YAML), then the
/// scene_fingerprint of the scene that config and the grid's set: make (mesh, surface, obstacle
/// and materials files by content), or "unloadable" when it does not load (its rows then fail
/// with the scene's error). Files a row's own overrides name enter only by their path, through
/// the row's arguments.
std::string config_fingerprint_text(const SweepGrid& grid);

}  // namespace rbaa
