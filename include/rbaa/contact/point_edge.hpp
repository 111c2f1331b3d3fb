#pragma once
// Squared distance from a point to a segment, with gradient and Hessian with respect to
// (p, e0, e1) (9 dofs): the point-point distance to e0 or e1, or the point-line distance,
// whichever feature point_edge_distance_type names.

#include <Eigen/Core>

#include "rbaa/contact/distance_type.hpp"
#include "rbaa/contact/fixed_size.hpp"

namespace rbaa::contact {

/// Squared point-segment distance, classifying the closest feature first.
double point_edge_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& e0,
                           const Eigen::Vector3d& e1);
/// The same for a given feature pair (the caller classified, e.g. once per Newton iteration).
double point_edge_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& e0,
                           const Eigen::Vector3d& e1, PointEdgeDistanceType type);
Vector9d point_edge_distance_gradient(const Eigen::Vector3d& p, const Eigen::Vector3d& e0,
                                      const Eigen::Vector3d& e1, PointEdgeDistanceType type);
Vector9d point_edge_distance_gradient(const Eigen::Vector3d& p, const Eigen::Vector3d& e0,
                                      const Eigen::Vector3d& e1);
Matrix9d point_edge_distance_hessian(const Eigen::Vector3d& p, const Eigen::Vector3d& e0,
                                     const Eigen::Vector3d& e1, PointEdgeDistanceType type);
Matrix9d point_edge_distance_hessian(const Eigen::Vector3d& p, const Eigen::Vector3d& e0,
                                     const Eigen::Vector3d& e1);

}  // namespace rbaa::contact
