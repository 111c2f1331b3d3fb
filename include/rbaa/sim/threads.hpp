#pragma once
// The simulator's OpenMP thread count, settable without including omp.h (tests and the command
// line fix it; results do not depend on it, the assembly sums in a fixed order).

#include <string>

namespace rbaa {

/// Threads the element loops use.
int simulation_threads();
/// Sets the threads for subsequent element loops (n >= 1).
void set_simulation_threads(int n);

/// What the command line does once at start, measured on 2 shared cores (README, "Threads"):
/// * OpenMP teams sized dynamically (omp_set_dynamic) unless OMP_DYNAMIC is set: CHOLMOD's
///   supernodal factorisation opens teams of 4 threads whatever OMP_NUM_THREADS says, and on 2
///   cores they spun in futex calls: the main job's system time was 58 % of its user time;
/// * OpenBLAS on 1 thread unless OPENBLAS_NUM_THREADS is set (its pthread
///   build with 2 threads beside our OpenMP made the main job 25 % slower).
/// Results do not depend on either (Simulator.ResultsDoNotDependOnTheThreadCount). Returns a
/// one-line description of what it set, empty if nothing.
/// Dynamic teams are left off under OpenBLAS's OpenMP build (dynamic_teams_allowed).
std::string tune_threads_for_shared_cores();

/// What openblas_get_parallel() returns for OpenBLAS's OpenMP build (0 sequential, 1 pthread).
constexpr int kOpenblasOpenmp = 2;
/// Whether tune_threads_for_shared_cores() may size OpenMP teams dynamically, given whether the
/// user set OMP_DYNAMIC and OpenBLAS's threading model (openblas_get_parallel(), -1 when the BLAS
/// is not OpenBLAS). Not under OpenBLAS's OpenMP build: its threaded kernels hand work to every
/// thread of the team they ask for and wait for it, and a dynamic team may have fewer threads.
/// With Debian's libopenblas0-openmp, OMP_NUM_THREADS=2 and OPENBLAS_NUM_THREADS set (so that
/// rbaa leaves OpenBLAS's threads alone), `rbaa simulate --config=configs/ball.yaml` spun in
/// CHOLMOD's dgemm_ (sched_yield in exec_blas) until killed; without dynamic teams it finishes.
bool dynamic_teams_allowed(bool omp_dynamic_set, int openblas_parallel);
/// What tune_threads_for_shared_cores() set in this process ("" if it was not called or set
/// nothing); report.json's timing.thread_setup.
const std::string& thread_setup();

}  // namespace rbaa
