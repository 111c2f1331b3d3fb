#pragma once
// Squared distance from a point to the plane through t0, t1, t2, with its gradient and Hessian
// with respect to (p, t0, t1, t2) (12 dofs):
//
//   d = ((p - t0).n)^2 / |n|^2,   n = (t1 - t0) x (t2 - t0).
//
// Smooth wherever the triangle has nonzero area; the point-triangle distance
// (point_triangle.hpp) uses it when p projects inside the triangle.

#include <Eigen/Core>

#include "rbaa/contact/fixed_size.hpp"

namespace rbaa::contact {

/// ((p - t0).n)^2 / |n|^2 (see above). Requires a triangle of nonzero area.
double point_plane_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                            const Eigen::Vector3d& t1, const Eigen::Vector3d& t2);
/// Gradient with respect to (p, t0, t1, t2).
Vector12d point_plane_distance_gradient(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                                        const Eigen::Vector3d& t1, const Eigen::Vector3d& t2);
/// Hessian with respect to (p, t0, t1, t2), exact (indefinite in general).
Matrix12d point_plane_distance_hessian(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                                       const Eigen::Vector3d& t1, const Eigen::Vector3d& t2);

}  // namespace rbaa::contact
