#pragma once
// Mass matrices of linear tets (SPEC section 2). Consistent: per element
// (m_e / 20)(1 + delta_ab) I_3 with m_e = rho_e alpha_e V_e. Lumped (for the speed/accuracy study
// only): m_e / 4 on each of the element's vertices. Both have the same row sums, so the centre of
// mass, momentum and gravity force are the same under either.

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "rbaa/material/material_field.hpp"
#include "rbaa/mesh/tet_mesh.hpp"
#include "rbaa/sim/world.hpp"
#include "rbaa/sim/sparse_hessian.hpp"

namespace rbaa {

/// Per-element masses m_e = density_e V_e (#T), density = rho alpha (kg/m^3), V from `rest`.
Eigen::VectorXd element_masses(const TetMesh& rest, const Eigen::VectorXd& density);

/// The 3#V x 3#V mass matrix in `pattern`'s layout (lower triangle).
Eigen::SparseMatrix<double> mass_matrix(const TetMesh& rest, const Eigen::VectorXd& density,
                                        MassModel model, SparseHessian& pattern);

/// dM/dm_e, element e's mass matrix per unit of its mass m_e = rho_e alpha_e V_e: consistent
/// (1 + delta_ab) / 20 I_3, lumped delta_ab / 4 I_3 over the element's vertices. What the inertia
/// and gravity forms' material hooks differentiate M with.
class UnitElementMass {
 public:
  UnitElementMass(const TetMesh& rest, MassModel model);

  /// a_e^T (dM/dm_e) u_e over the element's four vertices (a, u: 3 #V).
  double product(int e, const Eigen::VectorXd& a, const Eigen::VectorXd& u) const;
  /// out += dm (dM/dm_e) u_e.
  void add_times(int e, double dm, const Eigen::VectorXd& u, Eigen::VectorXd& out) const;
  /// dm_e = V_e (alpha_e drho_e + rho_e dalpha_e) along a material direction (empty: zero).
  double mass_change(int e, const MaterialField& materials, const MaterialGradient& d) const;
  /// g.rho[e] += c alpha_e V_e, g.alpha[e] += c rho_e V_e: a term c dm_e spread over the fields.
  void add_mass_gradient(int e, double c, const MaterialField& materials, MaterialGradient& g) const;

  int num_elements() const { return static_cast<int>(T_.rows()); }

 private:
  Tets T_;
  Eigen::VectorXd volume_;
  MassModel model_;
};

/// #V vertex masses: the row sums of either mass matrix, sum of m_e / 4 over incident elements.
Eigen::VectorXd vertex_masses(const TetMesh& rest, const Eigen::VectorXd& density);

}  // namespace rbaa
