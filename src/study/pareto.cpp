#include "rbaa/study/pareto.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace rbaa {

std::vector<int> pareto_front(const std::vector<CostError>& points) {
  std::vector<int> order;
  for (int i = 0; i < static_cast<int>(points.size()); ++i) {
    if (std::isfinite(points[i].cost) && std::isfinite(points[i].error)) order.push_back(i);
  }
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    if (points[a].cost != points[b].cost) return points[a].cost < points[b].cost;
    return points[a].error < points[b].error;
  });
  // Sweep by increasing cost: a point is on the front when its error beats every cheaper one's.
  std::vector<int> front;
  double best = std::numeric_limits<double>::infinity();
  for (int i : order) {
    if (points[i].error < best) {
      front.push_back(i);
      best = points[i].error;
    }
  }
  return front;
}

}  // namespace rbaa
