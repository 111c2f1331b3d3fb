#pragma once
// Runs a sweep's rows on this machine: a pool of at most `jobs` child processes of the rbaa
// program, one per row, each in its own folder (sweep_row.hpp). Finished rows are skipped
// (resume); a failed row is recorded and the others go on, and an attack row that was interrupted
// or failed continues from its checkpoint. Progress goes through a callback.

#include <functional>
#include <string>
#include <vector>

#include "rbaa/sweep/sweep_grid.hpp"
#include "rbaa/sweep/sweep_row.hpp"
#include "rbaa/sweep/thread_split.hpp"

namespace rbaa {

struct SweepOptions {
  std::string executable;  ///< the rbaa program the rows run
  std::string out_dir;     ///< DIR: rows in DIR/row-NNN, DIR/results.csv
  ThreadSplit split;       ///< jobs at once and OpenMP threads per row
  int only_row = -1;       ///< >= 0: run this row alone and leave results.csv alone (Slurm tasks)
};

/// What the sweep has done so far, after a row started or ended.
struct SweepProgress {
  int total = 0;    ///< rows in this run (1 with only_row)
  int done = 0;     ///< finished, including skipped
  int skipped = 0;  ///< finished before this run
  int failed = 0;
  int running = 0;
  double eta_seconds = -1;            ///< estimate from this run's rows; < 0 before one ends
  const RowOutcome* ended = nullptr;  ///< the row that just ended, or nullptr
  int started = -1;                   ///< the row that just started, or -1
  bool resumed = false;               ///< the started row continues its checkpoint (--resume)
};

struct SweepSummary {
  int total = 0, ok = 0, skipped = 0, failed = 0;
  double seconds = 0;
};

/// The command line of a row's process: its `arguments` (row_arguments), and --resume when the
/// verb is attack and row_dir holds the attack's checkpoint.json (the row was interrupted or
/// failed after some iterations: without it the attack would start over and overwrite them),
/// unless the grid's flags set --resume themselves. The marker keeps `arguments` alone, so resume
/// compares the same settings.
std::vector<std::string> row_process_arguments(const SweepGrid& grid,
                                               const std::vector<std::string>& arguments,
                                               const std::string& row_dir);

/// Runs the rows (all, or only_row) and, for a whole sweep, rewrites DIR/results.csv after every
/// row that ends. Throws InputError when DIR holds rows of another grid (read_sweep_outcomes).
/// A row that fails after the sweep gave it --resume says so in its error, with how to start it
/// over (remove its checkpoint.json).
SweepSummary run_sweep(const SweepGrid& grid, const SweepOptions& options,
                       const std::function<void(const SweepProgress&)>& on_progress = {});

}  // namespace rbaa
