#include "rbaa/contact/point_edge.hpp"

#include "rbaa/contact/point_line.hpp"
#include "rbaa/contact/point_point.hpp"
#include "scatter.hpp"

namespace rbaa::contact {

using detail::scatter;

double point_edge_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& e0,
                           const Eigen::Vector3d& e1, PointEdgeDistanceType type) {
  switch (type) {
    case PointEdgeDistanceType::P_E0:
      return point_point_distance(p, e0);
    case PointEdgeDistanceType::P_E1:
      return point_point_distance(p, e1);
    case PointEdgeDistanceType::P_E:
      return point_line_distance(p, e0, e1);
  }
  return point_line_distance(p, e0, e1);
}

double point_edge_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& e0,
                           const Eigen::Vector3d& e1) {
  return point_edge_distance(p, e0, e1, point_edge_distance_type(p, e0, e1));
}

Vector9d point_edge_distance_gradient(const Eigen::Vector3d& p, const Eigen::Vector3d& e0,
                                      const Eigen::Vector3d& e1, PointEdgeDistanceType type) {
  switch (type) {
    case PointEdgeDistanceType::P_E0:
      return scatter<2, 3>(point_point_distance_gradient(p, e0), {0, 1});
    case PointEdgeDistanceType::P_E1:
      return scatter<2, 3>(point_point_distance_gradient(p, e1), {0, 2});
    case PointEdgeDistanceType::P_E:
      break;
  }
  return point_line_distance_gradient(p, e0, e1);
}

Vector9d point_edge_distance_gradient(const Eigen::Vector3d& p, const Eigen::Vector3d& e0,
                                      const Eigen::Vector3d& e1) {
  return point_edge_distance_gradient(p, e0, e1, point_edge_distance_type(p, e0, e1));
}

Matrix9d point_edge_distance_hessian(const Eigen::Vector3d& p, const Eigen::Vector3d& e0,
                                     const Eigen::Vector3d& e1, PointEdgeDistanceType type) {
  switch (type) {
    case PointEdgeDistanceType::P_E0:
      return scatter<2, 3>(point_point_distance_hessian(p, e0), {0, 1});
    case PointEdgeDistanceType::P_E1:
      return scatter<2, 3>(point_point_distance_hessian(p, e1), {0, 2});
    case PointEdgeDistanceType::P_E:
      break;
  }
  return point_line_distance_hessian(p, e0, e1);
}

Matrix9d point_edge_distance_hessian(const Eigen::Vector3d& p, const Eigen::Vector3d& e0,
                                     const Eigen::Vector3d& e1) {
  return point_edge_distance_hessian(p, e0, e1, point_edge_distance_type(p, e0, e1));
}

}  // namespace rbaa::contact
