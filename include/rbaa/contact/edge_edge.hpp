#pragma once
// Squared distance between two segments, with gradient and Hessian with respect to
// (ea0, ea1, eb0, eb1) (12 dofs): the point-point, point-line or line-line distance of the
// closest feature pair that edge_edge_distance_type names. The entries of dofs that the feature
// does not involve are zero. Near-parallel pairs need the mollifier (edge_edge_mollifier.hpp) on
// top of the barrier, since the line-line derivatives blow up as the edges turn parallel.

#include <Eigen/Core>

#include "rbaa/contact/distance_type.hpp"
#include "rbaa/contact/fixed_size.hpp"

namespace rbaa::contact {

/// Squared segment-segment distance, classifying the closest features first.
double edge_edge_distance(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                          const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1);
/// The same for a given feature pair.
double edge_edge_distance(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                          const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1,
                          EdgeEdgeDistanceType type);
Vector12d edge_edge_distance_gradient(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                                      const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1);
Vector12d edge_edge_distance_gradient(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                                      const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1,
                                      EdgeEdgeDistanceType type);
Matrix12d edge_edge_distance_hessian(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                                     const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1);
Matrix12d edge_edge_distance_hessian(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                                     const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1,
                                     EdgeEdgeDistanceType type);

}  // namespace rbaa::contact
