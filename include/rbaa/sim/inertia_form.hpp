#pragma once
// The inertial term of the incremental potential, 1/2 (q - q_hat)^T M (q - q_hat), with q_hat the
// integrator's predictor (set before every step).

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "rbaa/sim/form.hpp"
#include "rbaa/sim/mass_matrix.hpp"

namespace rbaa {

class InertiaForm : public Form {
 public:
  /// M: the mass matrix, lower triangle, in the Hessian's pattern (mass_matrix()); `unit` its
  /// derivative per element mass (the material hooks).
  InertiaForm(Eigen::SparseMatrix<double> M, UnitElementMass unit)
      : M_(std::move(M)), unit_(std::move(unit)) {}

  void set_predictor(const Eigen::VectorXd& q_hat) { q_hat_ = q_hat; }
  const Eigen::VectorXd& predictor() const { return q_hat_; }
  const Eigen::SparseMatrix<double>& mass_matrix() const { return M_; }
  /// M x (the stored lower triangle read as the symmetric matrix).
  Eigen::VectorXd multiply(const Eigen::VectorXd& x) const;

  const char* name() const override { return "inertia"; }
  double value(const Eigen::VectorXd& q) const override;
  /// (q1 - q0)^T M (q0 - q_hat) + 1/2 (q1 - q0)^T M (q1 - q0).
  double value_difference(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const override;
  void add_gradient(const Eigen::VectorXd& q, double scale, Eigen::VectorXd& grad) const override;
  void add_hessian(const Eigen::VectorXd& q, double scale, HessianKind kind,
                   SparseHessian& hessian) const override;
  /// G's term M (x - q_hat) through the element masses.
  void add_material_adjoint(const Eigen::VectorXd& x, const Eigen::VectorXd& a, double scale,
                            const MaterialField& materials, MaterialGradient& g) const override;
  void add_material_tangent(const Eigen::VectorXd& x, const MaterialGradient& direction, double scale,
                            const MaterialField& materials, Eigen::VectorXd& out) const override;

 private:
  Eigen::SparseMatrix<double> M_;
  UnitElementMass unit_;
  Eigen::VectorXd q_hat_;
};

}  // namespace rbaa
