#include "rbaa/sim/threads.hpp"

#include <omp.h>

namespace rbaa {

int simulation_threads() { return omp_get_max_threads(); }

void set_simulation_threads(int n) { omp_set_num_threads(n < 1 ? 1 : n); }

}  // namespace rbaa
