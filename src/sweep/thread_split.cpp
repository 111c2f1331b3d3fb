#include "rbaa/sweep/thread_split.hpp"

#include <sched.h>

#include <algorithm>
#include <cstdlib>
#include <thread>

#include "rbaa/error.hpp"

namespace rbaa {

ThreadSplit split_threads(int jobs, int requested_threads, int cores) {
  if (jobs < 1) throw InputError("--jobs must be >= 1, got " + std::to_string(jobs));
  if (requested_threads < 0) {
    throw InputError("--threads must be >= 0 (0: cores / jobs), got " +
                     std::to_string(requested_threads));
  }
  ThreadSplit s;
  s.jobs = jobs;
  s.cores = std::max(1, cores);
  s.threads = requested_threads > 0 ? requested_threads : std::max(1, s.cores / jobs);
  s.oversubscribed = static_cast<long>(s.jobs) * s.threads > s.cores;
  return s;
}

int available_cores() {
  for (const char* name : {"SLURM_CPUS_PER_TASK", "SLURM_CPUS_ON_NODE"}) {
    if (const char* v = std::getenv(name)) {
      const int n = std::atoi(v);
      if (n > 0) return n;
    }
  }
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof(set), &set) == 0) return std::max(1, CPU_COUNT(&set));
  return std::max(1u, std::thread::hardware_concurrency());
}

std::string describe(const ThreadSplit& s) {
  return std::to_string(s.jobs) + (s.jobs == 1 ? " job x " : " jobs x ") +
         std::to_string(s.threads) + (s.threads == 1 ? " thread on " : " threads on ") +
         std::to_string(s.cores) + (s.cores == 1 ? " core" : " cores") +
         (s.oversubscribed ? ", oversubscribed" : "");
}

}  // namespace rbaa
