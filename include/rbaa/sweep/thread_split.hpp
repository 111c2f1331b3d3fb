#pragma once
// How many OpenMP threads each row of a sweep gets, so that N rows running at once do not
// oversubscribe the machine: jobs x threads <= cores unless the user asks for more.

#include <string>

namespace rbaa {

struct ThreadSplit {
  int jobs = 1;     ///< rows running at once
  int threads = 1;  ///< OMP_NUM_THREADS of each row
  int cores = 1;    ///< cores the split was made for
  /// jobs x threads > cores: the user asked for it (--threads, or more jobs than cores).
  bool oversubscribed = false;
};

/// threads = requested_threads if > 0 (the user's choice, even past the cores), else
/// max(1, cores / jobs). jobs and cores must be >= 1.
ThreadSplit split_threads(int jobs, int requested_threads, int cores);

/// The cores this process may use: under Slurm the task's allocation (SLURM_CPUS_PER_TASK, else
/// SLURM_CPUS_ON_NODE), otherwise the CPUs in this process's affinity mask.
int available_cores();

/// One line for the log: "2 jobs x 1 thread on 2 cores" (+ ", oversubscribed").
std::string describe(const ThreadSplit& split);

}  // namespace rbaa
