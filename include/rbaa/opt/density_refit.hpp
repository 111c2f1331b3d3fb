#pragma once
// Density re-fit after occupancy rounding (SPEC section 5.3): a Ceres least-squares problem in the
// span of the moment rows. With theta0 = the tanh-map inverse of the current densities and
// phi_k(e) the element averages of the 10 moment integrands (a basis of the quadratic polynomials,
// here taken in the centred, scaled coordinates (x - c_ref) / L, which span the same space and
// keep the 10 by 10 system well conditioned; the basis is further multiplied by the inverse of the
// starting Jacobian, which keeps the span and makes that Jacobian the identity),
//     theta_rho,e = theta0_e + sum_k c_k phi_k(e),   rho_e = rho_map(theta_rho,e),
// Ceres (DENSE_QR, analytic Jacobian) solves for the 10 unknowns c so that the 10 normalised
// moment residuals (S (rho o alpha) - m_ref) ./ scale vanish. Only occupied elements (alpha > 0)
// change.

#include <Eigen/Core>

#include <string>

#include "rbaa/geometry/moments.hpp"
#include "rbaa/material/tanh_box_map.hpp"
#include "rbaa/mesh/tet_mesh.hpp"

namespace rbaa {

struct DensityRefitOptions {
  double tolerance = 1e-10;  ///< required max |normalised residual|
  int max_iterations = 50;
  /// Compare the analytic Jacobian (through the tanh map and the preconditioned basis) with
  /// central differences before solving; the normwise error goes to jacobian_check_error.
  bool check_jacobian = false;
};

struct DensityRefitResult {
  Eigen::VectorXd rho;             ///< #T re-fitted densities (kg/m^3)
  Eigen::Matrix<double, 10, 1> c;  ///< coefficients of the correction (preconditioned basis)
  MomentVector residual;           ///< normalised residuals at the result
  double initial_max_residual = 0.0;
  double max_residual = 0.0;
  int iterations = 0;              ///< Ceres iterations (successful + unsuccessful steps)
  std::string ceres_report;        ///< Ceres' brief report
  /// ||J - J_fd||_F / ||J||_F, worst of two points (with options.check_jacobian; else 0)
  double jacobian_check_error = 0.0;
};

/// Re-fits rho (#T, each strictly inside rho_map's range; values on a bound are moved inside by
/// 1e-12 of the range) so that the moments of rho o alpha (#T occupancies) equal `reference`.
/// Throws rbaa::InputError when no density field within the bounds can match m0 (the occupied
/// volume times rho_min exceeds m0_ref, or times rho_max falls short: too much void), and
/// rbaa::SolverError when Ceres stops above the tolerance.
DensityRefitResult refit_density(const TetMesh& mesh, const Eigen::VectorXd& alpha,
                                 const Eigen::VectorXd& rho, const Moments& reference,
                                 const TanhBoxMap& rho_map, const DensityRefitOptions& options = {});

}  // namespace rbaa
