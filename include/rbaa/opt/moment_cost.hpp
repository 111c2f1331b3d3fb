#pragma once
// The moment-matching term of the attack objective as a Ceres cost function (SPEC section 4):
// 10 residuals r = (S (rho o alpha) - m_ref) ./ scale, with S the 10 by #T moment operator and
// scale = moment_normalisation(reference) (m0 by m0_ref, m1 by m0_ref L, m2 by m0_ref L^2).
// One parameter block: the whole design vector theta (DesignSpace::size()). The analytic Jacobian
// is dr/dtheta_rho = diag(1/scale) S diag(alpha rho'(theta_rho)) on the rho block and
// diag(1/scale) S diag(rho alpha'(theta_alpha)) on the interior elements' alpha block; zero on the
// Y and nu blocks. With an element mask (DesignSpace) S keeps only the designed elements' columns:
// the moments are the attacked body's alone, and `reference` must be that body's.

#include <ceres/dynamic_cost_function.h>

#include <Eigen/Core>

#include "rbaa/geometry/moments.hpp"
#include "rbaa/material/design_space.hpp"
#include "rbaa/mesh/tet_mesh.hpp"

namespace rbaa {

class MomentCostFunction : public ceres::DynamicCostFunction {
 public:
  /// `design` is copied; `reference` gives m_ref and the normalisation.
  MomentCostFunction(const TetMesh& mesh, const DesignSpace& design, const Moments& reference);
  ~MomentCostFunction() override;

  /// Ceres' interface: parameters[0] is theta; jacobians[0], if requested, is 10 by size()
  /// row-major. Returns false (Ceres then rejects the point) only on non-finite residuals.
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  /// The 10 normalised residuals at theta.
  MomentVector residuals(const Eigen::VectorXd& theta) const;
  /// The 10 by size() Jacobian dr/dtheta.
  Eigen::Matrix<double, 10, Eigen::Dynamic> jacobian(const Eigen::VectorXd& theta) const;
  /// The objective's moment term beta ||r||^2 and, if gradient is given, 2 beta J^T r (size()).
  double penalty(const Eigen::VectorXd& theta, double beta, Eigen::VectorXd* gradient) const;

  const MomentVector& reference() const { return reference_; }
  const MomentVector& scale() const { return scale_; }
  const DesignSpace& design() const { return design_; }

 private:
  DesignSpace design_;
  Eigen::Matrix<double, 10, Eigen::Dynamic> S_;
  MomentVector reference_, scale_;
};

}  // namespace rbaa
