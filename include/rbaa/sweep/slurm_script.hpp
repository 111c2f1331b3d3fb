#pragma once
// A sweep as a Slurm job array: one array task per row, each running
// `rbaa sweep --grid=FILE --out=DIR --row=$SLURM_ARRAY_TASK_ID`, and a merge job that starts
// after the whole array has ended (afterany: failed rows are merged too) and writes
// DIR/results.csv with `rbaa sweep --grid=FILE --out=DIR --merge`.

#include <string>

#include "rbaa/sweep/sweep_grid.hpp"

namespace rbaa {

struct SlurmJob {
  std::string grid;        ///< grid file, absolute
  std::string out_dir;     ///< DIR, absolute
  std::string executable;  ///< the rbaa program, absolute
  std::string workdir;     ///< where the tasks run (--chdir): relative flag paths resolve here
  int max_parallel = 0;    ///< > 0: at most this many tasks at once (--array=...%N)
};

struct SlurmScripts {
  std::string array;   ///< the array job's batch script
  std::string merge;   ///< the merge job's batch script
  std::string submit;  ///< shell script: sbatch the array, then the merge depending on it
};

/// The three scripts' text; the grid's slurm: options become #SBATCH --name=value lines of both
/// jobs (cpus-per-task defaults to 1).
SlurmScripts slurm_scripts(const SweepGrid& grid, const SlurmJob& job);

/// Writes DIR/slurm/{array.sbatch, merge.sbatch, submit.sh}; returns the submit script's path.
std::string write_slurm_scripts(const SweepGrid& grid, const SlurmJob& job);

}  // namespace rbaa
