#include "rbaa/contact/point_line.hpp"

#include <Eigen/Geometry>

// With r = p - e0, e = e1 - e0, q = |e|^2, t = r.e / q, u = r - t e (dt/dr = e / q,
// dt/de = (r - 2 t e) / q):
//
//   d = |r|^2 - (r.e)^2 / q,  dd/dr = 2 u,  dd/de = -2 t u,
//   d2d/dr2 = 2 (I - e e^T / q),
//   d2d/dr de = -2 (e (r - 2 t e)^T / q + t I),
//   d2d/de2 = -2 (r - 2 t e) (r - 2 t e)^T / q + 2 t^2 I,
//
// mapped to (p, e0, e1) by r = p - e0, e = e1 - e0.

namespace rbaa::contact {
namespace {

// Derivatives with respect to (r, e) -> (p, e0, e1): p contributes to r, e0 to -r - e, e1 to e.
Vector9d to_points(const Eigen::Vector3d& g_r, const Eigen::Vector3d& g_e) {
  Vector9d g;
  g << g_r, -g_r - g_e, g_e;
  return g;
}

}  // namespace

double point_line_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& e0,
                           const Eigen::Vector3d& e1) {
  const Eigen::Vector3d r = p - e0, e = e1 - e0;
  // |r x e|^2 / |e|^2 has no cancellation between two nearly equal terms, unlike |r|^2 - ...
  return r.cross(e).squaredNorm() / e.squaredNorm();
}

Vector9d point_line_distance_gradient(const Eigen::Vector3d& p, const Eigen::Vector3d& e0,
                                      const Eigen::Vector3d& e1) {
  const Eigen::Vector3d r = p - e0, e = e1 - e0;
  const double t = r.dot(e) / e.squaredNorm();
  const Eigen::Vector3d u = r - t * e;
  return to_points(2 * u, -2 * t * u);
}

Matrix9d point_line_distance_hessian(const Eigen::Vector3d& p, const Eigen::Vector3d& e0,
                                     const Eigen::Vector3d& e1) {
  const Eigen::Vector3d r = p - e0, e = e1 - e0;
  const double q = e.squaredNorm(), t = r.dot(e) / q;
  const Eigen::Vector3d w = r - 2 * t * e;
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d H_rr = 2 * (I - e * e.transpose() / q);
  const Eigen::Matrix3d H_re = -2 * (e * w.transpose() / q + t * I);
  const Eigen::Matrix3d H_ee = -2 * w * w.transpose() / q + 2 * t * t * I;

  // x = (p, e0, e1), (r, e) = M x with M = [I -I 0; 0 -I I]: H_x = M^T H_re M.
  Eigen::Matrix<double, 6, 6> H_local;
  H_local << H_rr, H_re, H_re.transpose(), H_ee;
  Eigen::Matrix<double, 6, 9> M = Eigen::Matrix<double, 6, 9>::Zero();
  M.block<3, 3>(0, 0) = I;
  M.block<3, 3>(0, 3) = -I;
  M.block<3, 3>(3, 3) = -I;
  M.block<3, 3>(3, 6) = I;
  return M.transpose() * H_local * M;
}

}  // namespace rbaa::contact
