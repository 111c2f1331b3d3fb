#include "normal_projection.hpp"

#include <Eigen/Geometry>

namespace rbaa::contact::detail {

double normal_projection(const Eigen::Vector3d& r, const Eigen::Vector3d& a,
                         const Eigen::Vector3d& b) {
  const Eigen::Vector3d n = a.cross(b);
  const double s = r.dot(n);
  return s * s / n.squaredNorm();
}

Vector9d normal_projection_gradient(const Eigen::Vector3d& r, const Eigen::Vector3d& a,
                                    const Eigen::Vector3d& b) {
  const Eigen::Vector3d n = a.cross(b);
  const double q = n.squaredNorm(), s = r.dot(n);
  const Eigen::Vector3d g_n = (2 * s / q) * (r - (s / q) * n);
  Vector9d g;
  g.segment<3>(0) = (2 * s / q) * n;
  // dn/da = -[b]x, so (dn/da)^T g_n = [b]x g_n = b x g_n; dn/db = [a]x gives g_n x a.
  g.segment<3>(3) = b.cross(g_n);
  g.segment<3>(6) = g_n.cross(a);
  return g;
}

Matrix9d normal_projection_hessian(const Eigen::Vector3d& r, const Eigen::Vector3d& a,
                                   const Eigen::Vector3d& b) {
  const Eigen::Vector3d n = a.cross(b);
  const double q = n.squaredNorm(), s = r.dot(n);
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d nnT = n * n.transpose();

  // Hessian of f(r, n) with respect to (r, n).
  Eigen::Matrix<double, 6, 6> F;
  F.block<3, 3>(0, 0) = (2 / q) * nnT;
  F.block<3, 3>(0, 3) = (2 / q) * (n * r.transpose() + s * I) - (4 * s / (q * q)) * nnT;
  F.block<3, 3>(3, 0) = F.block<3, 3>(0, 3).transpose();
  F.block<3, 3>(3, 3) = (2 / q) * r * r.transpose() -
                        (4 * s / (q * q)) * (r * n.transpose() + n * r.transpose()) -
                        (2 * s * s / (q * q)) * I + (8 * s * s / (q * q * q)) * nnT;

  // (r, a, b) -> (r, n) to first order.
  Eigen::Matrix<double, 6, 9> D = Eigen::Matrix<double, 6, 9>::Zero();
  D.block<3, 3>(0, 0) = I;
  D.block<3, 3>(3, 3) = -cross_matrix(b);
  D.block<3, 3>(3, 6) = cross_matrix(a);

  Matrix9d H = D.transpose() * F * D;
  // Second-order term of the bilinear n(a, b): sum_k g_n,k eps_kij = -[g_n]x_ij.
  const Eigen::Vector3d g_n = (2 * s / q) * (r - (s / q) * n);
  const Eigen::Matrix3d G = cross_matrix(g_n);
  H.block<3, 3>(3, 6) -= G;
  H.block<3, 3>(6, 3) += G;  // (-[g]x)^T = [g]x
  return H;
}

Eigen::Matrix3d cross_matrix(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

Eigen::Matrix<double, 9, 12> difference_map(int r_plus, int r_minus, int a_plus, int a_minus,
                                            int b_plus, int b_minus) {
  Eigen::Matrix<double, 9, 12> M = Eigen::Matrix<double, 9, 12>::Zero();
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const int plus[3] = {r_plus, a_plus, b_plus}, minus[3] = {r_minus, a_minus, b_minus};
  for (int k = 0; k < 3; ++k) {
    M.block<3, 3>(3 * k, 3 * plus[k]) += I;
    M.block<3, 3>(3 * k, 3 * minus[k]) -= I;
  }
  return M;
}

}  // namespace rbaa::contact::detail
