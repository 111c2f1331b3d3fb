#include "rbaa/contact/point_point.hpp"

namespace rbaa::contact {

double point_point_distance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1) {
  return (p0 - p1).squaredNorm();
}

Vector6d point_point_distance_gradient(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1) {
  Vector6d g;
  g.head<3>() = 2 * (p0 - p1);
  g.tail<3>() = -g.head<3>();
  return g;
}

Matrix6d point_point_distance_hessian(const Eigen::Vector3d&, const Eigen::Vector3d&) {
  const Eigen::Matrix3d I2 = 2 * Eigen::Matrix3d::Identity();
  Matrix6d H;
  H << I2, -I2, -I2, I2;
  return H;
}

}  // namespace rbaa::contact
