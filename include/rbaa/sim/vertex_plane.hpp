#pragma once
// The vertex vs analytic half-space pair {x : n . x >= c}: distance, its derivatives and the
// continuous collision detection of a linear vertex trajectory (exact: d is linear in time).

#include <Eigen/Core>

#include "rbaa/sim/world.hpp"

namespace rbaa {

/// Distance n . x - c of point x to the plane's boundary (negative beyond it).
inline double vertex_plane_distance(const Eigen::Vector3d& x, const Plane& plane) {
  return plane.normal.dot(x) - plane.offset;
}

/// Gradient of the distance with respect to x: the normal. Its Hessian is zero.
inline const Eigen::Vector3d& vertex_plane_distance_gradient(const Plane& plane) {
  return plane.normal;
}

/// Largest t in [0, 1] such that the vertex moving x0 -> x1 keeps d(t) >= min_ratio d(0):
/// 1 if it does the whole way, else (1 - min_ratio) d0 / (d0 - d1). Requires d(0) > 0. Stopping
/// short of the plane by a fraction of the current gap keeps every iterate strictly feasible.
double vertex_plane_ccd(const Eigen::Vector3d& x0, const Eigen::Vector3d& x1, const Plane& plane,
                        double min_ratio = 0.1);

}  // namespace rbaa
