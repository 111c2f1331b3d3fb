#pragma once
// Elastic energy of linear tets with the stable Neo-Hookean density and per-element materials:
//
//   Psi(q) = sum_e alpha_e^3 V_e (mu_e Psi_mu(F_e) + lambda_e Psi_lambda(F_e)),  F_e = Ds Dm^-1,
//
// mu, lambda from (Y, nu) with lambda = lambda_L + mu (material/lame.hpp). Linear in mu_e and
// lambda_e per element, so d(grad Psi)/d mu_e is element e's gradient of Psi_mu scaled by
// alpha^3 V (element_gradient_parts), which the adjoint will use.

#include <Eigen/Core>

#include <vector>

#include "rbaa/material/material_field.hpp"
#include "rbaa/mesh/tet_mesh.hpp"
#include "rbaa/sim/form.hpp"

namespace rbaa {

class ElasticForm : public Form {
 public:
  /// Precomputes the rest shape (Dm^-1 and volumes of `rest`) and the materials.
  ElasticForm(const TetMesh& rest, const MaterialField& materials);

  /// Replaces the materials (same element count; validated by the caller).
  void set_materials(const MaterialField& materials);

  const char* name() const override { return "elastic"; }
  double value(const Eigen::VectorXd& q) const override;
  double value_difference(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const override;
  void add_gradient(const Eigen::VectorXd& q, double scale, Eigen::VectorXd& grad) const override;
  void add_hessian(const Eigen::VectorXd& q, double scale, HessianKind kind,
                   SparseHessian& hessian) const override;
  bool writes_element_blocks() const override { return true; }
  /// G's term scale grad Psi through mu(Y, nu), lambda(Y, nu) and the factor alpha^3.
  void add_material_adjoint(const Eigen::VectorXd& x, const Eigen::VectorXd& a, double scale,
                            const MaterialField& materials, MaterialGradient& g) const override;
  void add_material_tangent(const Eigen::VectorXd& x, const MaterialGradient& direction, double scale,
                            const MaterialField& materials, Eigen::VectorXd& out) const override;

  int num_elements() const { return static_cast<int>(tets_.rows()); }
  /// F of element e at q.
  Eigen::Matrix3d deformation_gradient(const Eigen::VectorXd& q, int e) const;
  /// 3 x 4 shape-function gradients: F = sum_a x_a b_a^T, column a = b_a.
  const Eigen::Matrix<double, 3, 4>& shape_gradients(int e) const { return B_[e]; }
  double rest_volume(int e) const { return volume_[e]; }
  /// alpha_e^3 V_e, the factor in front of the density.
  double stiffness_weight(int e) const { return weight_[e]; }
  double mu(int e) const { return mu_[e]; }
  double lambda(int e) const { return lambda_[e]; }
  /// d(grad Psi)/d mu_e and d(grad Psi)/d lambda_e as element-local 12-vectors (3 a + i).
  void element_gradient_parts(const Eigen::VectorXd& q, int e, Eigen::Matrix<double, 12, 1>& g_mu,
                              Eigen::Matrix<double, 12, 1>& g_lambda) const;

 private:
  Tets tets_;
  std::vector<Eigen::Matrix<double, 3, 4>> B_;
  Eigen::VectorXd volume_, weight_, mu_, lambda_;
  mutable std::vector<double> element_buffer_;  // per-element energies or 12-gradients
  mutable Eigen::VectorXd vertex_buffer_;        // the gathered gradient before its net force and torque go
  std::vector<int> incidence_start_, incidence_;
};

}  // namespace rbaa
