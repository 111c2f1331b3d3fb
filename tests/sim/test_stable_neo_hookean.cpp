// The stable Neo-Hookean density on single deformation gradients: stress and Hessian against
// central finite differences, the analytic eigensystem against the closed-form Hessian, and the
// cancellation-free energy difference.

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <random>

#include "finite_differences.hpp"
#include "rbaa/material/lame.hpp"
#include "rbaa/sim/stable_neo_hookean.hpp"

namespace rbaa {
namespace {

using Vec9 = Eigen::Matrix<double, 9, 1>;

Eigen::Matrix3d unvec(const Eigen::VectorXd& f) { return Eigen::Map<const Eigen::Matrix3d>(f.data()); }
Eigen::VectorXd vec(const Eigen::Matrix3d& F) { return Eigen::Map<const Vec9>(F.data()); }

std::vector<Eigen::Matrix3d> sample_gradients() {
  std::vector<Eigen::Matrix3d> Fs = {Eigen::Matrix3d::Identity()};
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double amp : {0.05, 0.3}) {
    for (int s = 0; s < 4; ++s) {
      Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
      for (int i = 0; i < 9; ++i) F.data()[i] += amp * u(rng);
      // rotate it too
      Eigen::Quaterniond q(u(rng), u(rng), u(rng), u(rng));
      Fs.push_back(q.normalized().toRotationMatrix() * F);
    }
  }
  Eigen::Matrix3d compressed = Eigen::Vector3d(0.7, 0.9, 0.95).asDiagonal();
  Fs.push_back(compressed);
  Eigen::Matrix3d inverted = Eigen::Vector3d(0.5, 0.8, -0.2).asDiagonal();
  Fs.push_back(inverted);
  return Fs;
}

TEST(StableNeoHookean, StressAndHessianMatchFiniteDifferences) {
  for (double nu : {0.2, 0.28, 0.4}) {
    const LameParameters lame = lame_from_young_poisson(1.0, nu);  // energies scale with Y
    for (const Eigen::Matrix3d& F : sample_gradients()) {
      auto psi = [&](const Eigen::VectorXd& f) {
        const snh::EnergyParts p = snh::energy_parts(unvec(f));
        return lame.mu * p.mu + lame.lambda * p.lambda;
      };
      auto P = [&](const Eigen::VectorXd& f) { return vec(snh::stress(unvec(f), lame.mu, lame.lambda)); };
      const Eigen::VectorXd fd_P = test::fd_gradient(psi, vec(F), 1e-6);
      const Eigen::VectorXd an_P = vec(snh::stress(F, lame.mu, lame.lambda));
      if (an_P.norm() > 1e-12) EXPECT_LT(test::relative_error(an_P, fd_P), 1e-6) << F;
      else EXPECT_LT(fd_P.norm(), 1e-9);
      const Eigen::MatrixXd fd_H = test::fd_jacobian(P, vec(F), 1e-6);
      const Eigen::MatrixXd H = snh::hessian(F, lame.mu, lame.lambda);
      EXPECT_LT(test::relative_error(H, fd_H), 1e-6) << F;
    }
  }
}

TEST(StableNeoHookean, EigensystemReproducesHessianAndProjectionIsPsd) {
  const LameParameters lame = lame_from_young_poisson(1e13, 0.28);
  for (const Eigen::Matrix3d& F : sample_gradients()) {
    const snh::Eigensystem es = snh::hessian_eigensystem(F, lame.mu, lame.lambda);
    Eigen::Matrix<double, 9, 9> H = Eigen::Matrix<double, 9, 9>::Zero(), Hp = H;
    Eigen::Matrix<double, 9, 9> Q;
    for (int m = 0; m < 9; ++m) {
      const Vec9 v = Eigen::Map<const Vec9>(es.modes[m].data());
      Q.col(m) = v;
      H += es.values[m] * v * v.transpose();
      Hp += std::max(es.values[m], 0.0) * v * v.transpose();
    }
    EXPECT_LT((Q.transpose() * Q - Eigen::Matrix<double, 9, 9>::Identity()).norm(), 1e-12);
    const Eigen::Matrix<double, 9, 9> Hc = snh::hessian(F, lame.mu, lame.lambda);
    EXPECT_LT(test::relative_error(H, Hc), 1e-12) << F;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> eig(Hp);
    EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-12 * Hc.norm());
    // The projection only removes the negative part of the exact spectrum.
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> exact(Hc);
    double negative = 0;
    for (int i = 0; i < 9; ++i) negative += std::min(0.0, exact.eigenvalues()[i]) * std::min(0.0, exact.eigenvalues()[i]);
    EXPECT_NEAR((Hp - Hc).norm(), std::sqrt(negative), 1e-10 * Hc.norm());
  }
}

// Deformation gradients a step of a stiff object meets: strains from 1e-12 to 1e-3 around a
// rotation, with repeated singular values (pure rotation, uniaxial and planar strain).
std::vector<Eigen::Matrix3d> small_strain_gradients() {
  std::vector<Eigen::Matrix3d> Fs;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double amp : {0.0, 1e-12, 1e-9, 1e-6, 1e-3}) {
    for (int s = 0; s < 3; ++s) {
      Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
      for (int i = 0; i < 9; ++i) F.data()[i] += amp * u(rng);
      const Eigen::Quaterniond q(u(rng), u(rng), u(rng), u(rng));
      Fs.push_back(q.normalized().toRotationMatrix() * F);
    }
    const Eigen::Matrix3d uniaxial = Eigen::Vector3d(1.0 - amp, 1.0, 1.0).asDiagonal();
    const Eigen::Matrix3d planar = Eigen::Vector3d(1.0 + amp, 1.0 + amp, 1.0 - 2 * amp).asDiagonal();
    Fs.push_back(uniaxial);
    Fs.push_back(planar);
  }
  return Fs;
}

TEST(StableNeoHookean, RotationVariantSvdReproducesF) {
  std::vector<Eigen::Matrix3d> Fs = sample_gradients();
  for (const Eigen::Matrix3d& F : small_strain_gradients()) Fs.push_back(F);
  Fs.push_back(Eigen::Vector3d(1.0, 1e-9, 1e-9).asDiagonal());  // falls back to JacobiSVD
  for (const Eigen::Matrix3d& F : Fs) {
    const snh::RotationVariantSvd svd = snh::rotation_variant_svd(F);
    EXPECT_LT((svd.U * svd.s.asDiagonal() * svd.V.transpose() - F).norm(), 1e-13 * F.norm()) << F;
    EXPECT_LT((svd.U.transpose() * svd.U - Eigen::Matrix3d::Identity()).norm(), 1e-13);
    EXPECT_LT((svd.V.transpose() * svd.V - Eigen::Matrix3d::Identity()).norm(), 1e-13);
    EXPECT_NEAR(svd.U.determinant(), 1.0, 1e-13);
    EXPECT_NEAR(svd.V.determinant(), 1.0, 1e-13);
    EXPECT_GE(svd.s[0], svd.s[1] - 1e-15 * svd.s[0]);
    EXPECT_GE(svd.s[1], std::abs(svd.s[2]) - 1e-15 * svd.s[0]);
    EXPECT_EQ(svd.s[2] < 0, F.determinant() < 0) << F;
  }
}

TEST(StableNeoHookean, ProjectedHessianRemovesExactlyTheNegativeSpectrum) {
  std::vector<Eigen::Matrix3d> Fs = sample_gradients();
  for (const Eigen::Matrix3d& F : small_strain_gradients()) Fs.push_back(F);
  int projected = 0;
  for (double nu : {0.2, 0.28, 0.4}) {
    const LameParameters lame = lame_from_young_poisson(1e13, nu);
    for (const Eigen::Matrix3d& F : Fs) {
      Eigen::Matrix<double, 9, 9> Hp;
      const double removed = snh::projected_hessian(F, lame.mu, lame.lambda, Hp);
      const Eigen::Matrix<double, 9, 9> Hc = snh::hessian(F, lame.mu, lame.lambda);
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> exact(Hc);
      const Eigen::Matrix<double, 9, 9> clamped = exact.eigenvectors() *
                                                  exact.eigenvalues().cwiseMax(0.0).asDiagonal() *
                                                  exact.eigenvectors().transpose();
      // Eigenvalues within 1e-12 (mu + lambda) of zero may stay (round-off and near-zero modes).
      EXPECT_LT((Hp - clamped).norm(), 1e-12 * Hc.norm()) << F;
      EXPECT_NEAR(removed, std::min(0.0, exact.eigenvalues().minCoeff()), 1e-12 * Hc.norm()) << F;
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> after(Hp);
      EXPECT_GE(after.eigenvalues().minCoeff(), -1e-12 * (lame.mu + lame.lambda) - 1e-14 * Hc.norm()) << F;
      if (removed < 0) ++projected;
    }
  }
  EXPECT_GT(projected, 10);  // the check saw real projections, not only PD Hessians
}

TEST(StableNeoHookean, CompressionHasNegativeEigenvalueMinusLambdaTimesOneMinusJ) {
  // SPEC: under compression the Hessian has a negative eigenvalue -lambda (1 - J) (at the
  // uniformly compressed state, in the twist modes: mu + (lambda (J - 1) - mu) s).
  const LameParameters lame = lame_from_young_poisson(1e9, 0.3);
  const double s = 0.99;
  const Eigen::Matrix3d F = s * Eigen::Matrix3d::Identity();
  const snh::Eigensystem es = snh::hessian_eigensystem(F, lame.mu, lame.lambda);
  const double J = s * s * s;
  const double expected = lame.mu + (lame.lambda * (J - 1) - lame.mu) * s;
  double min_value = 1e300;
  for (double v : es.values) min_value = std::min(min_value, v);
  EXPECT_LT(min_value, 0);
  EXPECT_NEAR(min_value, expected, 1e-9 * lame.lambda);
}

TEST(StableNeoHookean, EnergyDifferenceIsExactAndCancellationFree) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const Eigen::Matrix3d& F0 : sample_gradients()) {
    Eigen::Matrix3d D;
    for (int i = 0; i < 9; ++i) D.data()[i] = 0.1 * u(rng);
    const snh::EnergyParts a = snh::energy_parts(F0), b = snh::energy_parts(F0 + D);
    const snh::EnergyParts d = snh::energy_parts_difference(F0, D);
    EXPECT_NEAR(d.mu, b.mu - a.mu, 1e-13);
    EXPECT_NEAR(d.lambda, b.lambda - a.lambda, 1e-13);
  }
  // A 1e-12 perturbation: the subtraction of energies loses most digits, the difference keeps
  // them. Reference: the first-order term <P, D> (second order is 1e-24).
  const Eigen::Matrix3d F0 = Eigen::Vector3d(1.001, 0.999, 1.0005).asDiagonal();
  Eigen::Matrix3d D = Eigen::Matrix3d::Zero();
  D(0, 0) = 1e-12;
  const snh::EnergyParts d = snh::energy_parts_difference(F0, D);
  const double first_order_mu = snh::stress_mu(F0).cwiseProduct(D).sum();
  EXPECT_NEAR(d.mu, first_order_mu, 1e-9 * std::abs(first_order_mu));
}

}  // namespace
}  // namespace rbaa
