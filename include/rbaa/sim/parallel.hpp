#pragma once
// Sizes below which the simulator's loops run on one thread: on small meshes an OpenMP region
// costs more than its work, and on a shared, loaded machine a spinning team slows everyone down.
// Results do not depend on this (every sum runs in a fixed order).

namespace rbaa {

constexpr int kParallelElements = 2000;
constexpr int kParallelVertices = 2000;
constexpr long kParallelEntries = 100000;

}  // namespace rbaa
