#pragma once
// DIR/results.csv: one line per row of a sweep, gathered from the rows' markers and report.json.

#include <string>
#include <vector>

#include "rbaa/sweep/sweep_grid.hpp"
#include "rbaa/sweep/sweep_row.hpp"

namespace rbaa {

/// Every row's outcome under `out_dir` (kPending for rows never started), each with the grid's
/// arguments and config_fingerprint. Throws InputError when a row's folder holds a run with other
/// arguments (the grid changed) or a finished (ok) run of another config fingerprint (the config,
/// a base, a mesh file or a file the row's values or flags name changed: row_config_fingerprint):
/// use another --out. A failed or interrupted row of another fingerprint is returned as it is, to
/// run again.
std::vector<RowOutcome> read_sweep_outcomes(const SweepGrid& grid, const std::string& out_dir);

/// The results table: header "row,status,<swept keys>,<grid.report_columns>,seconds,error,folder",
/// then one line per row. A swept key's cell is the row's value, else the grid's set: value (empty
/// where the config's stood). Report figures come from the row's report.json (dotted paths; empty
/// where absent or the row did not finish); text fields are quoted when they need it.
std::string sweep_results_csv(const SweepGrid& grid, const std::string& out_dir,
                              const std::vector<RowOutcome>& outcomes);

/// Writes sweep_results_csv to out_dir/results.csv atomically.
void write_sweep_results(const SweepGrid& grid, const std::string& out_dir,
                         const std::vector<RowOutcome>& outcomes);

}  // namespace rbaa
