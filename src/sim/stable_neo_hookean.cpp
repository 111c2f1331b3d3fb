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

namespace {

// Nearly rank-deficient F (never met by a simulated element): Eigen's Jacobi SVD, made
// rotation-variant. Kept out of line: inlined, GCC 12 warns about Eigen's own internals.
[[gnu::noinline]] RotationVariantSvd jacobi_svd(const Eigen::Matrix3d& F) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  RotationVariantSvd r{svd.matrixU(), svd.matrixV(), svd.singularValues()};
  if (r.U.determinant() < 0) {
    r.U.col(2) *= -1.0;
    r.s[2] *= -1.0;
  }
  if (r.V.determinant() < 0) {
    r.V.col(2) *= -1.0;
    r.s[2] *= -1.0;
  }
  return r;
}

}  // namespace

RotationVariantSvd rotation_variant_svd(const Eigen::Matrix3d& F) {
  RotationVariantSvd r;
  // Fast path: V from the closed-form eigenvectors of F^T F, U from F V. Within a cluster of equal
  // singular values V is arbitrary, and U = F V / s stays consistent with it, so F = U S V^T holds
  // to round-off even where the eigenvectors of F^T F are ill-determined.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(F.transpose() * F);
  Eigen::Matrix3d V = eig.eigenvectors().rowwise().reverse();  // descending singular values
  if (V.determinant() < 0) V.col(2) *= -1.0;
  const Eigen::Vector3d f0 = F * V.col(0), f1 = F * V.col(1), f2 = F * V.col(2);
  const double s0 = f0.norm();
  Eigen::Vector3d u1 = f1;
  bool ok = s0 > 0;
  if (ok) {
    const Eigen::Vector3d u0 = f0 / s0;
    u1 -= u0.dot(u1) * u0;
    const double s1 = u1.norm();
    ok = s1 > 1e-6 * s0;
    if (ok) {
      u1 /= s1;
      r.U.col(0) = u0;
      r.U.col(1) = u1;
      r.U.col(2) = u0.cross(u1);
      r.V = V;
      r.s = Eigen::Vector3d(s0, f1.dot(u1), f2.dot(r.U.col(2)));
      const Eigen::Matrix3d residual = r.U * r.s.asDiagonal() * r.V.transpose() - F;
      ok = residual.norm() <= 1e-13 * s0;
    }
  }
  return ok ? r : jacobi_svd(F);
}

namespace {

// The 3 x 3 block of d2Psi/dF2 in the scaling modes U diag(c) V^T.
Eigen::Matrix3d scaling_block(const Eigen::Vector3d& s, double mu, double lambda) {
  const double t = lambda * (s[0] * s[1] * s[2] - 1.0) - mu;
  const Eigen::Vector3d g(s[1] * s[2], s[0] * s[2], s[0] * s[1]);
  Eigen::Matrix3d H;
  H << 0, s[2], s[1], s[2], 0, s[0], s[1], s[0], 0;
  return mu * Eigen::Matrix3d::Identity() + lambda * g * g.transpose() + t * H;
}

constexpr int kPairs[3][3] = {{0, 1, 2}, {0, 2, 1}, {1, 2, 0}};

}  // namespace

Eigensystem hessian_eigensystem(const Eigen::Matrix3d& F, double mu, double lambda) {
  const RotationVariantSvd svd = rotation_variant_svd(F);
  const Eigen::Matrix3d& U = svd.U;
  const Eigen::Matrix3d& V = svd.V;
  const Eigen::Vector3d& s = svd.s;
  const double t = lambda * (s[0] * s[1] * s[2] - 1.0) - mu;

  Eigensystem es;
  const double r = std::sqrt(0.5);
  for (int p = 0; p < 3; ++p) {
    const int i = kPairs[p][0], j = kPairs[p][1], k = kPairs[p][2];
    // Within span{U e_i e_j^T V^T, U e_j e_i^T V^T}, d2J/dF2 = [[0, -s_k], [-s_k, 0]].
    const Eigen::Matrix3d a = U.col(i) * V.col(j).transpose(), b = U.col(j) * V.col(i).transpose();
    es.modes[2 * p] = r * (a + b);
    es.values[2 * p] = mu - t * s[k];
    es.modes[2 * p + 1] = r * (a - b);
    es.values[2 * p + 1] = mu + t * s[k];
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(scaling_block(s, mu, lambda));
  for (int m = 0; m < 3; ++m) {
    const Eigen::Vector3d c = eig.eigenvectors().col(m);
    es.modes[6 + m] = U * c.asDiagonal() * V.transpose();
    es.values[6 + m] = eig.eigenvalues()[m];
  }
  return es;
}

double projected_hessian(const Eigen::Matrix3d& F, double mu, double lambda,
                         Eigen::Matrix<double, 9, 9>& H) {
  H = hessian(F, mu, lambda);
  // One rotation-variant SVD gives the nine eigenvalues. Those above -1e-12 (mu + lambda) stay:
  // round-off zeros (the rotation modes of a resting element) and the near-zero rotation modes of
  // a barely stressed one, whose negative curvature is far below any element's mass term in a
  // step, so the global Hessian stays positive definite. Most elements of a body at rest or in
  // flight have no other and keep the exact closed form, so Newton's factor is the exact Hessian
  // that the adjoint reuses (at -1e-14 the cube's free-flight steps lost it to such modes and its
  // gradient cost 1.50 forward runs instead of 1.02). The others lose their negative modes (at
  // most five of nine), built only for those.
  const double zero = -1e-12 * (mu + lambda);
  const RotationVariantSvd svd = rotation_variant_svd(F);
  const Eigen::Vector3d& sv = svd.s;
  const double t = lambda * (sv[0] * sv[1] * sv[2] - 1.0) - mu;
  const bool twist_or_flip = mu - std::abs(t * sv[0]) < zero;  // |s0| is the largest
  const Eigen::Matrix3d K = scaling_block(sv, mu, lambda);
  // K - zero I positive definite (leading minors) <=> no scaling eigenvalue below zero.
  const Eigen::Matrix3d Kz = K - zero * Eigen::Matrix3d::Identity();
  const bool scaling = !(Kz(0, 0) > 0 && Kz(0, 0) * Kz(1, 1) - Kz(0, 1) * Kz(0, 1) > 0 &&
                         Kz.determinant() > 0);
  double most_negative = 0.0;
  auto remove = [&](double value, const Eigen::Matrix3d& mode) {
    const Eigen::Map<const Eigen::Matrix<double, 9, 1>> v(mode.data());
    H.noalias() -= value * v * v.transpose();
    most_negative = std::min(most_negative, value);
  };
  if (twist_or_flip) {
    const double r = std::sqrt(0.5);
    for (int p = 0; p < 3; ++p) {
      const int i = kPairs[p][0], j = kPairs[p][1], k = kPairs[p][2];
      const double twist = mu - t * sv[k], flip = mu + t * sv[k];
      if (twist >= zero && flip >= zero) continue;
      const Eigen::Matrix3d a = svd.U.col(i) * svd.V.col(j).transpose();
      const Eigen::Matrix3d b = svd.U.col(j) * svd.V.col(i).transpose();
      if (twist < zero) remove(twist, r * (a + b));
      if (flip < zero) remove(flip, r * (a - b));
    }
  }
  if (scaling) {
    // The iterative solver: accurate vectors for clustered values.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(K);
    for (int m = 0; m < 3 && eig.eigenvalues()[m] < zero; ++m) {
      remove(eig.eigenvalues()[m], svd.U * eig.eigenvectors().col(m).asDiagonal() * svd.V.transpose());
    }
  }
  return most_negative;
}

}  // namespace rbaa::snh
