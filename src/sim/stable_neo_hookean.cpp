#include "rbaa/sim/stable_neo_hookean.hpp"

#include <Eigen/Dense>
#include <Eigen/SVD>

#include <cmath>

namespace rbaa::snh {

namespace {

Eigen::Matrix3d cross_matrix(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

}  // namespace

Eigen::Matrix3d cofactor(const Eigen::Matrix3d& F) {
  Eigen::Matrix3d c;
  c.col(0) = F.col(1).cross(F.col(2));
  c.col(1) = F.col(2).cross(F.col(0));
  c.col(2) = F.col(0).cross(F.col(1));
  return c;
}

EnergyParts energy_parts(const Eigen::Matrix3d& F) {
  const double J = F.determinant();
  return {0.5 * (F.squaredNorm() - 3.0) - (J - 1.0), 0.5 * (J - 1.0) * (J - 1.0)};
}

EnergyParts energy_parts_difference(const Eigen::Matrix3d& F0, const Eigen::Matrix3d& D) {
  const double dJ = cofactor(F0).cwiseProduct(D).sum() + F0.cwiseProduct(cofactor(D)).sum() +
                    D.determinant();
  const double J0m1 = F0.determinant() - 1.0;
  // 1/2 |F0 + D|^2 - 1/2 |F0|^2 = <D, F0 + D / 2>
  const double dI = D.cwiseProduct(F0 + 0.5 * D).sum();
  return {dI - dJ, dJ * (J0m1 + 0.5 * dJ)};
}

Eigen::Matrix3d stress_mu(const Eigen::Matrix3d& F) { return F - cofactor(F); }

Eigen::Matrix3d stress_lambda(const Eigen::Matrix3d& F) {
  return (F.determinant() - 1.0) * cofactor(F);
}

Eigen::Matrix3d stress(const Eigen::Matrix3d& F, double mu, double lambda) {
  const Eigen::Matrix3d C = cofactor(F);
  const double J = F.determinant();
  return mu * (F - C) + lambda * (J - 1.0) * C;
}

Eigen::Matrix<double, 9, 9> hessian(const Eigen::Matrix3d& F, double mu, double lambda) {
  const Eigen::Matrix3d C = cofactor(F);
  const double J = F.determinant();
  Eigen::Matrix<double, 9, 1> g = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(C.data());
  // d2J/dF2 in 3x3 blocks (a, b) over columns f_a, f_b: block (0, 1) = -[f2]x, (0, 2) = [f1]x,
  // (1, 2) = -[f0]x, transposes below the diagonal, zero diagonal blocks.
  Eigen::Matrix<double, 9, 9> HJ = Eigen::Matrix<double, 9, 9>::Zero();
  const Eigen::Matrix3d x0 = cross_matrix(F.col(0)), x1 = cross_matrix(F.col(1)),
                        x2 = cross_matrix(F.col(2));
  HJ.block<3, 3>(0, 3) = -x2;
  HJ.block<3, 3>(0, 6) = x1;
  HJ.block<3, 3>(3, 6) = -x0;
  HJ.block<3, 3>(3, 0) = x2;
  HJ.block<3, 3>(6, 0) = -x1;
  HJ.block<3, 3>(6, 3) = x0;
  return mu * Eigen::Matrix<double, 9, 9>::Identity() + lambda * g * g.transpose() +
         (lambda * (J - 1.0) - mu) * HJ;
}

Eigensystem hessian_eigensystem(const Eigen::Matrix3d& F, double mu, double lambda) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = svd.matrixU(), V = svd.matrixV();
  Eigen::Vector3d s = svd.singularValues();
  // Rotation-variant SVD: U and V proper rotations, the sign of det F carried by s2.
  if (U.determinant() < 0) {
    U.col(2) *= -1.0;
    s[2] *= -1.0;
  }
  if (V.determinant() < 0) {
    V.col(2) *= -1.0;
    s[2] *= -1.0;
  }
  const double J = s[0] * s[1] * s[2];
  const double t = lambda * (J - 1.0) - mu;

  Eigensystem es;
  const double r = std::sqrt(0.5);
  const int pairs[3][3] = {{0, 1, 2}, {0, 2, 1}, {1, 2, 0}};
  for (int p = 0; p < 3; ++p) {
    const int i = pairs[p][0], j = pairs[p][1], k = pairs[p][2];
    // Within span{U e_i e_j^T V^T, U e_j e_i^T V^T}, d2J/dF2 = [[0, -s_k], [-s_k, 0]].
    const Eigen::Matrix3d a = U.col(i) * V.col(j).transpose(), b = U.col(j) * V.col(i).transpose();
    es.modes[2 * p] = r * (a + b);
    es.values[2 * p] = mu - t * s[k];
    es.modes[2 * p + 1] = r * (a - b);
    es.values[2 * p + 1] = mu + t * s[k];
  }
  const Eigen::Vector3d g(s[1] * s[2], s[0] * s[2], s[0] * s[1]);
  Eigen::Matrix3d H;
  H << 0, s[2], s[1], s[2], 0, s[0], s[1], s[0], 0;
  const Eigen::Matrix3d K = mu * Eigen::Matrix3d::Identity() + lambda * g * g.transpose() + t * H;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(K);
  for (int m = 0; m < 3; ++m) {
    const Eigen::Vector3d c = eig.eigenvectors().col(m);
    es.modes[6 + m] = U * c.asDiagonal() * V.transpose();
    es.values[6 + m] = eig.eigenvalues()[m];
  }
  return es;
}

}  // namespace rbaa::snh
