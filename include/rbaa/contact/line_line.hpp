#pragma once
// Squared distance between the infinite lines through (ea0, ea1) and (eb0, eb1), with its
// gradient and Hessian with respect to (ea0, ea1, eb0, eb1) (12 dofs):
//
//   d = ((ea0 - eb0).n)^2 / |n|^2,   n = (ea1 - ea0) x (eb1 - eb0).
//
// Smooth wherever the lines are not parallel; as they approach parallel |n| -> 0 and the
// derivatives grow like 1/|n|, which is why edge-edge barriers carry the mollifier
// (edge_edge_mollifier.hpp) and the distance type switches to endpoint cases when parallel.

#include <Eigen/Core>

#include "rbaa/contact/fixed_size.hpp"

namespace rbaa::contact {

/// ((ea0 - eb0).n)^2 / |n|^2 (see above). Requires non-parallel lines.
double line_line_distance(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                          const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1);
/// Gradient with respect to (ea0, ea1, eb0, eb1).
Vector12d line_line_distance_gradient(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                                      const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1);
/// Hessian with respect to (ea0, ea1, eb0, eb1), exact (indefinite in general).
Matrix12d line_line_distance_hessian(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                                     const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1);

}  // namespace rbaa::contact
