#pragma once
// Sizes below which the simulator's loops run on one thread: on small meshes an OpenMP region
// costs more than its work, and on a shared, loaded machine a spinning team slows everyone down.
// Results do not depend on this (every sum runs in a fixed order).

namespace rbaa {

// The element Hessians (an SVD, a 3x3 eigensystem and nine rank-one 12x12 updates per element,
// ~2 us) are worth a team from a few thousand elements on.
constexpr int kParallelElements = 2000;
// Loops that cost ~0.1 us per item (energies, gradients, the gradient gather, the adjoint's
// parameter derivatives, zeroing and summing the Hessian buffers) take ~1 ms serially on the
// paper's largest meshes. A fork/join costs more than that whenever one of the two threads is
// descheduled (measured on a loaded 2-core machine: ~3 ms per region, which made the gradient
// 20x slower with two threads than with one), so they run in parallel only on far larger meshes.
constexpr int kParallelCheapElements = 200000;
constexpr int kParallelVertices = 200000;
constexpr long kParallelEntries = 4000000;

}  // namespace rbaa
