#pragma once
// Squared distance between two points, d = |p0 - p1|^2, with its gradient and Hessian with
// respect to (p0, p1) (6 dofs).

#include <Eigen/Core>

#include "rbaa/contact/fixed_size.hpp"

namespace rbaa::contact {

/// |p0 - p1|^2.
double point_point_distance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1);
/// (2 (p0 - p1), -2 (p0 - p1)).
Vector6d point_point_distance_gradient(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1);
/// [2I -2I; -2I 2I] (constant).
Matrix6d point_point_distance_hessian(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1);

}  // namespace rbaa::contact
