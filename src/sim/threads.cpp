#include "rbaa/sim/threads.hpp"

#include <dlfcn.h>
#include <omp.h>

#include <cstdlib>

namespace rbaa {

int simulation_threads() { return omp_get_max_threads(); }

void set_simulation_threads(int n) { omp_set_num_threads(n < 1 ? 1 : n); }

namespace {
std::string& setup_text() {
  static std::string text;
  return text;
}
}  // namespace

const std::string& thread_setup() { return setup_text(); }

bool dynamic_teams_allowed(bool omp_dynamic_set, int openblas_parallel) {
  return !omp_dynamic_set && openblas_parallel != kOpenblasOpenmp;
}

std::string tune_threads_for_shared_cores() {
  std::string& said = setup_text();
  said.clear();
  using GetParallel = int (*)();
  const auto get_parallel = reinterpret_cast<GetParallel>(dlsym(RTLD_DEFAULT, "openblas_get_parallel"));
  const int openblas_parallel = get_parallel ? get_parallel() : -1;
  const bool omp_dynamic_set = std::getenv("OMP_DYNAMIC") != nullptr;
  if (dynamic_teams_allowed(omp_dynamic_set, openblas_parallel)) {
    omp_set_dynamic(1);
    said += "OpenMP dynamic teams";
  } else if (!omp_dynamic_set) {
    said += "OpenMP dynamic teams left off (OpenBLAS's OpenMP build waits for whole teams)";
  } else if (openblas_parallel == kOpenblasOpenmp && omp_get_dynamic()) {
    // The user's choice stands, but it is the one that livelocked.
    said += "warning: OMP_DYNAMIC turns dynamic teams on, in which OpenBLAS's OpenMP build can wait for ever";
  }
  if (!std::getenv("OPENBLAS_NUM_THREADS")) {
    // Only OpenBLAS has this entry point; another BLAS is left alone.
    using SetThreads = void (*)(int);
    if (auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"))) {
      set(1);
      // The OpenMP build's openblas_set_num_threads is omp_set_num_threads: rbaa's element loops
      // go to 1 thread with it. Kept: measured on configs/ball.yaml with 2 cores, 1.9 s so against
      // 17 s with OpenMP on 2 threads (OpenBLAS's teams nested in CHOLMOD's).
      said += std::string(said.empty() ? "" : ", ") + "OpenBLAS on 1 thread" +
              (openblas_parallel == kOpenblasOpenmp ? " (its OpenMP build: rbaa's OpenMP loops too)" : "");
    }
  }
  return said;
}

}  // namespace rbaa
