#pragma once
// Gravitational potential Phi_g = -g^T M q with g the stacked gravity vector. M g only needs the
// mass matrix's row sums (the vertex masses), so Phi_g = -sum_i m_i g . x_i for either mass model.

#include <Eigen/Core>

#include "rbaa/sim/form.hpp"
#include "rbaa/sim/mass_matrix.hpp"

namespace rbaa {

class GravityForm : public Form {
 public:
  /// vertex_masses: #V (mass_matrix.hpp); gravity in m/s^2; `unit` the mass matrix's derivative
  /// per element mass (the material hooks).
  GravityForm(const Eigen::VectorXd& vertex_masses, const Eigen::Vector3d& gravity,
              UnitElementMass unit);

  const char* name() const override { return "gravity"; }
  double value(const Eigen::VectorXd& q) const override { return -force_.dot(q); }
  double value_difference(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const override {
    return -force_.dot(q1 - q0);
  }
  void add_gradient(const Eigen::VectorXd& q, double scale, Eigen::VectorXd& grad) const override {
    grad -= scale * force_;
  }
  void add_hessian(const Eigen::VectorXd&, double, HessianKind, SparseHessian&) const override {}

  /// G's term -M g through the element masses.
  void add_material_adjoint(const Eigen::VectorXd& x, const Eigen::VectorXd& a, double scale,
                            const MaterialField& materials, MaterialGradient& g) const override;
  void add_material_tangent(const Eigen::VectorXd& x, const MaterialGradient& direction, double scale,
                            const MaterialField& materials, Eigen::VectorXd& out) const override;

  /// The stacked force M g (3 #V).
  const Eigen::VectorXd& force() const { return force_; }

 private:
  Eigen::VectorXd force_;
  Eigen::VectorXd gravity_;  // g on every vertex (3 #V)
  UnitElementMass unit_;
};

}  // namespace rbaa
