#pragma once
// The Pareto front of (cost, error) pairs: the points no other point beats in both.

#include <vector>

namespace rbaa {

struct CostError {
  double cost = 0;   ///< e.g. wall time (s)
  double error = 0;  ///< e.g. centre-of-mass error (m)
};

/// Indices of the non-dominated points, by increasing cost (ties: the smaller error first). A
/// point is dominated when another has cost <= and error <= with at least one strictly smaller;
/// of exact duplicates the first is kept. Points with a non-finite coordinate are left out.
std::vector<int> pareto_front(const std::vector<CostError>& points);

}  // namespace rbaa
