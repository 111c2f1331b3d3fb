#include "rbaa/contact/edge_edge_mollifier.hpp"

#include <Eigen/Geometry>

#include "normal_projection.hpp"

// c = |n|^2 with n = a x b, a = ea1 - ea0, b = eb1 - eb0. dc/dn = 2n, d2c/dn2 = 2I; through
// dn = -[b]x da + [a]x db: dc/da = 2 b x n, dc/db = 2 n x a, and the Hessian with respect to
// (a, b) is D^T (2I) D plus the bilinear term -[2n]x in the (a, b) block (see
// normal_projection.hpp). (ea0, ea1, eb0, eb1) -> (a, b) is linear: ea0 -> -a, ea1 -> a,
// eb0 -> -b, eb1 -> b.

namespace rbaa::contact {
namespace {

constexpr double kThresholdScale = 1e-3;

Vector12d to_points(const Eigen::Vector3d& g_a, const Eigen::Vector3d& g_b) {
  Vector12d g;
  g << -g_a, g_a, -g_b, g_b;
  return g;
}

}  // namespace

double edge_edge_cross_squarednorm(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                                   const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1) {
  return (ea1 - ea0).cross(eb1 - eb0).squaredNorm();
}

Vector12d edge_edge_cross_squarednorm_gradient(const Eigen::Vector3d& ea0,
                                               const Eigen::Vector3d& ea1,
                                               const Eigen::Vector3d& eb0,
                                               const Eigen::Vector3d& eb1) {
  const Eigen::Vector3d a = ea1 - ea0, b = eb1 - eb0, n = a.cross(b);
  return to_points(2 * b.cross(n), 2 * n.cross(a));
}

Matrix12d edge_edge_cross_squarednorm_hessian(const Eigen::Vector3d& ea0,
                                              const Eigen::Vector3d& ea1,
                                              const Eigen::Vector3d& eb0,
                                              const Eigen::Vector3d& eb1) {
  const Eigen::Vector3d a = ea1 - ea0, b = eb1 - eb0, n = a.cross(b);
  Eigen::Matrix<double, 3, 6> D;
  D << -detail::cross_matrix(b), detail::cross_matrix(a);
  Eigen::Matrix<double, 6, 6> H_ab = 2 * D.transpose() * D;
  const Eigen::Matrix3d G = detail::cross_matrix(2 * n);
  H_ab.block<3, 3>(0, 3) -= G;
  H_ab.block<3, 3>(3, 0) += G;
  // (a, b) = M x with M = [-I I 0 0; 0 0 -I I].
  Eigen::Matrix<double, 6, 12> M = Eigen::Matrix<double, 6, 12>::Zero();
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  M.block<3, 3>(0, 0) = -I;
  M.block<3, 3>(0, 3) = I;
  M.block<3, 3>(3, 6) = -I;
  M.block<3, 3>(3, 9) = I;
  return M.transpose() * H_ab * M;
}

double mollifier(double c, double eps_x) {
  if (c >= eps_x) return 1.0;
  const double x = c / eps_x;
  return (2 - x) * x;
}

double mollifier_derivative(double c, double eps_x) {
  if (c >= eps_x) return 0.0;
  return 2 / eps_x * (1 - c / eps_x);
}

double mollifier_second_derivative(double c, double eps_x) {
  if (c >= eps_x) return 0.0;
  return -2 / (eps_x * eps_x);
}

double mollifier_derivative_wrt_eps_x(double c, double eps_x) {
  if (c >= eps_x) return 0.0;
  // m = 2 c / eps - c^2 / eps^2.
  return 2 * c / (eps_x * eps_x) * (c / eps_x - 1);
}

double edge_edge_mollifier_threshold(const Eigen::Vector3d& ea0_rest,
                                     const Eigen::Vector3d& ea1_rest,
                                     const Eigen::Vector3d& eb0_rest,
                                     const Eigen::Vector3d& eb1_rest) {
  return kThresholdScale * (ea0_rest - ea1_rest).squaredNorm() *
         (eb0_rest - eb1_rest).squaredNorm();
}

Vector12d edge_edge_mollifier_threshold_gradient(const Eigen::Vector3d& ea0_rest,
                                                 const Eigen::Vector3d& ea1_rest,
                                                 const Eigen::Vector3d& eb0_rest,
                                                 const Eigen::Vector3d& eb1_rest) {
  const Eigen::Vector3d a = ea1_rest - ea0_rest, b = eb1_rest - eb0_rest;
  return to_points(kThresholdScale * 2 * b.squaredNorm() * a,
                   kThresholdScale * 2 * a.squaredNorm() * b);
}

double edge_edge_mollifier(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                           const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1, double eps_x) {
  return mollifier(edge_edge_cross_squarednorm(ea0, ea1, eb0, eb1), eps_x);
}

Vector12d edge_edge_mollifier_gradient(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                                       const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1,
                                       double eps_x) {
  const double c = edge_edge_cross_squarednorm(ea0, ea1, eb0, eb1);
  if (c >= eps_x) return Vector12d::Zero();
  return mollifier_derivative(c, eps_x) * edge_edge_cross_squarednorm_gradient(ea0, ea1, eb0, eb1);
}

Matrix12d edge_edge_mollifier_hessian(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                                      const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1,
                                      double eps_x) {
  const double c = edge_edge_cross_squarednorm(ea0, ea1, eb0, eb1);
  if (c >= eps_x) return Matrix12d::Zero();
  const Vector12d g = edge_edge_cross_squarednorm_gradient(ea0, ea1, eb0, eb1);
  return mollifier_second_derivative(c, eps_x) * g * g.transpose() +
         mollifier_derivative(c, eps_x) * edge_edge_cross_squarednorm_hessian(ea0, ea1, eb0, eb1);
}

Vector12d edge_edge_mollifier_gradient_wrt_rest(
    const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1, const Eigen::Vector3d& eb0,
    const Eigen::Vector3d& eb1, const Eigen::Vector3d& ea0_rest, const Eigen::Vector3d& ea1_rest,
    const Eigen::Vector3d& eb0_rest, const Eigen::Vector3d& eb1_rest) {
  const double eps_x = edge_edge_mollifier_threshold(ea0_rest, ea1_rest, eb0_rest, eb1_rest);
  const double c = edge_edge_cross_squarednorm(ea0, ea1, eb0, eb1);
  if (c >= eps_x) return Vector12d::Zero();
  return mollifier_derivative_wrt_eps_x(c, eps_x) *
         edge_edge_mollifier_threshold_gradient(ea0_rest, ea1_rest, eb0_rest, eb1_rest);
}

}  // namespace rbaa::contact
