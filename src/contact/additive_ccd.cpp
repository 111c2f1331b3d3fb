#include "rbaa/contact/additive_ccd.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>

#include "rbaa/contact/edge_edge.hpp"
#include "rbaa/contact/point_triangle.hpp"

namespace rbaa::contact {
namespace {

using Points = std::array<Eigen::Vector3d, 4>;

// The additive iteration for a pair whose four points move x0 -> x0 + dx; `distance` is the
// squared distance of four points, `speed_bound` L (m per unit t).
CcdResult additive_ccd(const Points& x0, const Points& dx,
                       const std::function<double(const Points&)>& distance, double speed_bound,
                       const AdditiveCcdSettings& s) {
  CcdResult result;
  const auto at = [&](double t) {
    Points x;
    for (int i = 0; i < 4; ++i) x[i] = x0[i] + t * dx[i];
    return x;
  };
  const double d0 = std::sqrt(distance(x0));
  if (!(d0 > s.min_distance)) {
    result.toi = 0.0;
    return result;
  }
  if (speed_bound <= 0) return result;  // no relative motion: the distance stays d0
  const double gap0 = d0 - s.min_distance;
  const double delta = s.min_distance + s.min_gap_ratio * gap0;
  const double stop_gap = s.tolerance * gap0;

  double t = 0.0, d = d0;
  for (result.iterations = 1; result.iterations <= s.max_iterations; ++result.iterations) {
    const double t_next = t + (d - delta) / speed_bound;
    if (t_next >= 1.0) return result;  // d > delta over the rest of the step
    const double d_next = std::sqrt(distance(at(t_next)));
    // In exact arithmetic d_next >= delta; rounding can put it a little below, never below xi
    // unless delta is within rounding of xi, in which case t, not t_next, is the safe answer.
    if (!(d_next > s.min_distance)) {
      result.toi = t;
      return result;
    }
    t = t_next;
    d = d_next;
    if (d - delta <= stop_gap) {
      result.toi = t;
      return result;
    }
  }
  result.toi = t;
  result.converged = false;
  return result;
}

// Removes the mean displacement; returns the displacements relative to it.
Points relative(const Points& dx) {
  const Eigen::Vector3d mean = (dx[0] + dx[1] + dx[2] + dx[3]) / 4;
  Points out;
  for (int i = 0; i < 4; ++i) out[i] = dx[i] - mean;
  return out;
}

}  // namespace

CcdResult point_triangle_ccd(const Eigen::Vector3d& p_t0, const Eigen::Vector3d& t0_t0,
                             const Eigen::Vector3d& t1_t0, const Eigen::Vector3d& t2_t0,
                             const Eigen::Vector3d& p_t1, const Eigen::Vector3d& t0_t1,
                             const Eigen::Vector3d& t1_t1, const Eigen::Vector3d& t2_t1,
                             const AdditiveCcdSettings& settings) {
  const Points x0 = {p_t0, t0_t0, t1_t0, t2_t0};
  const Points dx = {p_t1 - p_t0, t0_t1 - t0_t0, t1_t1 - t1_t0, t2_t1 - t2_t0};
  const Points r = relative(dx);
  // Any point of the triangle moves by a convex combination of its corners' displacements.
  const double L = r[0].norm() + std::max({r[1].norm(), r[2].norm(), r[3].norm()});
  return additive_ccd(
      x0, dx, [](const Points& x) { return point_triangle_distance(x[0], x[1], x[2], x[3]); }, L,
      settings);
}

CcdResult edge_edge_ccd(const Eigen::Vector3d& ea0_t0, const Eigen::Vector3d& ea1_t0,
                        const Eigen::Vector3d& eb0_t0, const Eigen::Vector3d& eb1_t0,
                        const Eigen::Vector3d& ea0_t1, const Eigen::Vector3d& ea1_t1,
                        const Eigen::Vector3d& eb0_t1, const Eigen::Vector3d& eb1_t1,
                        const AdditiveCcdSettings& settings) {
  const Points x0 = {ea0_t0, ea1_t0, eb0_t0, eb1_t0};
  const Points dx = {ea0_t1 - ea0_t0, ea1_t1 - ea1_t0, eb0_t1 - eb0_t0, eb1_t1 - eb1_t0};
  const Points r = relative(dx);
  const double L = std::max(r[0].norm(), r[1].norm()) + std::max(r[2].norm(), r[3].norm());
  return additive_ccd(
      x0, dx, [](const Points& x) { return edge_edge_distance(x[0], x[1], x[2], x[3]); }, L,
      settings);
}

}  // namespace rbaa::contact
