#pragma once
// Squared distance from a point to the infinite line through e0 and e1, with its gradient and
// Hessian with respect to (p, e0, e1) (9 dofs). With r = p - e0, e = e1 - e0, t = r.e / |e|^2:
//
//   d = |r|^2 - (r.e)^2 / |e|^2 = |r - t e|^2.
//
// Smooth wherever e != 0; the point-edge distance (point_edge.hpp) uses it when p projects
// inside the edge.

#include <Eigen/Core>

#include "rbaa/contact/fixed_size.hpp"

namespace rbaa::contact {

/// |r - t e|^2 (see above). Requires e1 != e0.
double point_line_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& e0,
                           const Eigen::Vector3d& e1);
/// Gradient with respect to (p, e0, e1): with u = r - t e, dd/dr = 2u, dd/de = -2t u.
Vector9d point_line_distance_gradient(const Eigen::Vector3d& p, const Eigen::Vector3d& e0,
                                      const Eigen::Vector3d& e1);
/// Hessian with respect to (p, e0, e1), exact (indefinite in general).
Matrix9d point_line_distance_hessian(const Eigen::Vector3d& p, const Eigen::Vector3d& e0,
                                     const Eigen::Vector3d& e1);

}  // namespace rbaa::contact
