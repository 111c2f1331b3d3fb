#pragma once
// Squared distance from a point to a triangle, with gradient and Hessian with respect to
// (p, t0, t1, t2) (12 dofs): the point-point, point-line or point-plane distance of the closest
// feature pair that point_triangle_distance_type names. The entries of dofs that the feature does
// not involve (e.g. t2 for P_E0) are zero.

#include <Eigen/Core>

#include "rbaa/contact/distance_type.hpp"
#include "rbaa/contact/fixed_size.hpp"

namespace rbaa::contact {

/// Squared point-triangle distance, classifying the closest feature first.
double point_triangle_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                               const Eigen::Vector3d& t1, const Eigen::Vector3d& t2);
/// The same for a given feature pair.
double point_triangle_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                               const Eigen::Vector3d& t1, const Eigen::Vector3d& t2,
                               PointTriangleDistanceType type);
Vector12d point_triangle_distance_gradient(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                                           const Eigen::Vector3d& t1, const Eigen::Vector3d& t2);
Vector12d point_triangle_distance_gradient(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                                           const Eigen::Vector3d& t1, const Eigen::Vector3d& t2,
                                           PointTriangleDistanceType type);
Matrix12d point_triangle_distance_hessian(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                                          const Eigen::Vector3d& t1, const Eigen::Vector3d& t2);
Matrix12d point_triangle_distance_hessian(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                                          const Eigen::Vector3d& t1, const Eigen::Vector3d& t2,
                                          PointTriangleDistanceType type);

}  // namespace rbaa::contact
