#pragma once
// The simulator's OpenMP thread count, settable without including omp.h (tests and the command
// line fix it; results do not depend on it, the assembly sums in a fixed order).

namespace rbaa {

/// Threads the element loops use.
int simulation_threads();
/// Sets the threads for subsequent element loops (n >= 1).
void set_simulation_threads(int n);

}  // namespace rbaa
