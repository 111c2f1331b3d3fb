#include "rbaa/contact/additive_ccd.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>

#include "rbaa/contact/edge_edge.hpp"
#include "rbaa/contact/point_triangle.hpp"

namespace rbaa::contact {
namespace {

using Points = std::array<Eigen::Vector3d, 4>;

// A separating-plane certificate that the pair stays farther apart than `bound` over the whole
// step. Every point pair of the two primitives is at least as far apart as the plane through one
// primitive parallel to both directions e1(t), e2(t) (the triangle's edges, or the two edges)
// is from the other primitive's point w(t) (relative to the plane's origin): d(t) >= |N(t)| /
// |n(t)|, n = e1 x e2 (quadratic in t), N = w . n (cubic). In the Bernstein basis on [0, 1] a
// polynomial lies between its smallest and largest coefficient and a vector polynomial's norm
// below its largest control point's, so if N's four coefficients share a sign and the smallest
// magnitude m satisfies m >= bound max_j |c_j| (c_j: n's control points), then d(t) >= bound on
// all of [0, 1]. The margin covers the rounding of the coefficients. O(1) work; it fails (and the
// additive iteration runs) when the directions are near parallel or the pair does approach.
// The plane's motion: its two directions p, q and the other primitive's point w relative to the
// plane's origin, each at t = 0 and t = 1 (linear in between).
struct PlaneMotion {
  Eigen::Vector3d w0, w1, p0, p1, q0, q1;
};

bool separated_over_the_step(const PlaneMotion& m, double bound) {
  const Eigen::Vector3d &w0 = m.w0, &w1 = m.w1, &p0 = m.p0, &p1 = m.p1, &q0 = m.q0, &q1 = m.q1;
  const Eigen::Vector3d c0 = p0.cross(q0), c1 = 0.5 * (p0.cross(q1) + p1.cross(q0)),
                        c2 = p1.cross(q1);
  const double h[4] = {w0.dot(c0), (2 * w0.dot(c1) + w1.dot(c0)) / 3,
                       (w0.dot(c2) + 2 * w1.dot(c1)) / 3, w1.dot(c2)};
  const double c_max = std::max({c0.norm(), c1.norm(), c2.norm()});
  if (!(c_max > 0)) return false;
  const double sign = h[0] > 0 ? 1.0 : -1.0;
  const double margin = 64 * std::numeric_limits<double>::epsilon() * std::max(w0.norm(), w1.norm()) *
                        std::max(p0.norm(), p1.norm()) * std::max(q0.norm(), q1.norm());
  // Each coefficient compared itself, so that a NaN (a non-finite position) certifies nothing.
  for (double hk : h) {
    if (!(sign * hk > bound * c_max + margin)) return false;
  }
  return true;
}

// The additive iteration for a pair whose four points move x0 -> x0 + dx; `distance` is the
// squared distance of four points, `speed_bound` L (m per unit t), `plane` the motion the
// separating-plane certificate reads.
CcdResult additive_ccd(const Points& x0, const Points& dx,
                       const std::function<double(const Points&)>& distance, double speed_bound,
                       const PlaneMotion& plane, const AdditiveCcdSettings& s) {
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
  // A pair sliding past at a distance d0 far below its speed per step (a vertex 1e-8 m above a
  // triangle, 5 mm of slide) needs ~L / (0.9 d0) iterations: 1e5 of them (4.6 ms) ended at
  // t = 0.18, not converged, and Newton crept through the step in such fractions until its
  // iteration limit (a pressed, sliding cube on a mesh floor). Where the plane certificate holds
  // above delta + stop_gap the iteration below would neither stop nor find d <= xi before t = 1,
  // so the certificate's 1 is the answer the iteration gives when no cap stops it. The margin
  // covers the rounding of the iteration's own distances, computed from coordinates up to X in
  // magnitude (differences good to ~eps X).
  if (s.plane_certificate) {
    double X = 0;
    for (int i = 0; i < 4; ++i) {
      X = std::max({X, x0[i].cwiseAbs().maxCoeff(), (x0[i] + dx[i]).cwiseAbs().maxCoeff()});
    }
    const double rounding = 16 * std::numeric_limits<double>::epsilon() * X;
    if (separated_over_the_step(plane, (delta + stop_gap) * (1 + 1e-9) + rounding)) return result;
  }

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
  // The triangle's plane: origin t0, directions t1 - t0 and t2 - t0; w = p - t0.
  const PlaneMotion plane{p_t0 - t0_t0, p_t1 - t0_t1, t1_t0 - t0_t0,
                          t1_t1 - t0_t1, t2_t0 - t0_t0, t2_t1 - t0_t1};
  return additive_ccd(
      x0, dx, [](const Points& x) { return point_triangle_distance(x[0], x[1], x[2], x[3]); }, L,
      plane, settings);
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
  // The plane through edge a parallel to both edges: w = eb0 - ea0.
  const PlaneMotion plane{eb0_t0 - ea0_t0, eb0_t1 - ea0_t1, ea1_t0 - ea0_t0,
                          ea1_t1 - ea0_t1, eb1_t0 - eb0_t0, eb1_t1 - eb0_t1};
  return additive_ccd(
      x0, dx, [](const Points& x) { return edge_edge_distance(x[0], x[1], x[2], x[3]); }, L,
      plane, settings);
}

}  // namespace rbaa::contact
