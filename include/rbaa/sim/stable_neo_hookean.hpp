#pragma once
// The stable Neo-Hookean energy density of one deformation gradient F (SPEC section 2), split so
// that it is linear in the Lame parameters:
//
//   Psi(F) = mu Psi_mu(F) + lambda Psi_lambda(F),
//   Psi_mu = 1/2 (|F|_F^2 - 3) - (J - 1),   Psi_lambda = 1/2 (J - 1)^2,   J = det F.
//
// The adjoint needs d(grad Psi)/d mu and d(grad Psi)/d lambda; with this split they are the
// stresses of the two parts (stress_mu, stress_lambda), no extra derivation.

#include <Eigen/Core>

#include <array>

namespace rbaa::snh {

/// Psi_mu and Psi_lambda at F.
struct EnergyParts {
  double mu = 0;
  double lambda = 0;
};

EnergyParts energy_parts(const Eigen::Matrix3d& F);

/// Psi(F0 + D) - Psi(F0) for both parts, computed from D without the cancellation of subtracting
/// two nearly equal energies (det(F0 + D) - det F0 = <cof F0, D> + <F0, cof D> + det D). The line
/// search of a 1e13 Pa object compares energies that differ in their 12th digit.
EnergyParts energy_parts_difference(const Eigen::Matrix3d& F0, const Eigen::Matrix3d& D);

/// Cofactor matrix dJ/dF = J F^-T, columns f1 x f2, f2 x f0, f0 x f1.
Eigen::Matrix3d cofactor(const Eigen::Matrix3d& F);

/// First Piola-Kirchhoff stress of the parts: dPsi_mu/dF = F - cof F, dPsi_lambda/dF = (J - 1) cof F.
Eigen::Matrix3d stress_mu(const Eigen::Matrix3d& F);
Eigen::Matrix3d stress_lambda(const Eigen::Matrix3d& F);

/// dPsi/dF = mu stress_mu + lambda stress_lambda.
Eigen::Matrix3d stress(const Eigen::Matrix3d& F, double mu, double lambda);

/// d2Psi/dF2 (9 x 9, F vectorised column by column) assembled from the closed form
/// mu I + lambda g g^T + (lambda (J - 1) - mu) d2J/dF2, g = vec(cof F). Used by the tests.
Eigen::Matrix<double, 9, 9> hessian(const Eigen::Matrix3d& F, double mu, double lambda);

/// The analytic eigensystem of d2Psi/dF2: d2Psi/dF2 = sum_m values[m] vec(modes[m]) vec(modes[m])^T
/// with orthonormal modes (|modes[m]|_F = 1). With the rotation-variant SVD F = U diag(s) V^T
/// (U, V rotations, s2 carrying the sign of J): three twist and three flip modes
/// U (e_i e_j^T -+ e_j e_i^T) V^T / sqrt 2 with eigenvalues mu +- (lambda (J - 1) - mu) s_k, and
/// three scaling modes U diag(c) V^T from the 3 x 3 matrix mu I + lambda g g^T + (lambda (J - 1) - mu) H
/// with g = (s1 s2, s0 s2, s0 s1) and H_ij = s_k (i != j != k). Clamping the values at zero gives
/// the PSD projection (Smith et al., Stable Neo-Hookean Flesh Simulation, 2018).
struct Eigensystem {
  std::array<double, 9> values;
  std::array<Eigen::Matrix3d, 9> modes;
};

Eigensystem hessian_eigensystem(const Eigen::Matrix3d& F, double mu, double lambda);

/// F = U diag(s) V^T with U and V proper rotations and s2 carrying the sign of det F, s sorted
/// by magnitude. V comes from the closed-form eigenvectors of F^T F and U from F V (about 5x faster
/// than Eigen's JacobiSVD); a nearly rank-deficient F, or a result that does not reproduce F to
/// 1e-13, falls back to JacobiSVD.
struct RotationVariantSvd {
  Eigen::Matrix3d U, V;
  Eigen::Vector3d s;
};

RotationVariantSvd rotation_variant_svd(const Eigen::Matrix3d& F);

/// H = d2Psi/dF2 with its eigenvalues below -1e-12 (mu + lambda) set to zero (the PSD projection
/// up to near-zero modes, see the source), computed as the closed-form Hessian minus those modes: an element with
/// none keeps the exact closed form, and only the others pay for eigenvectors. Returns the most
/// negative eigenvalue removed, 0 if none.
double projected_hessian(const Eigen::Matrix3d& F, double mu, double lambda,
                         Eigen::Matrix<double, 9, 9>& H);

}  // namespace rbaa::snh
