#pragma once
// Mass matrices of linear tets (SPEC section 2). Consistent: per element
// (m_e / 20)(1 + delta_ab) I_3 with m_e = rho_e alpha_e V_e. Lumped (for the speed/accuracy study
// only): m_e / 4 on each of the element's vertices. Both have the same row sums, so the centre of
// mass, momentum and gravity force are the same under either.

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "rbaa/mesh/tet_mesh.hpp"
#include "rbaa/sim/world.hpp"
#include "rbaa/sim/sparse_hessian.hpp"

namespace rbaa {

/// Per-element masses m_e = density_e V_e (#T), density = rho alpha (kg/m^3), V from `rest`.
Eigen::VectorXd element_masses(const TetMesh& rest, const Eigen::VectorXd& density);

/// The 3#V x 3#V mass matrix in `pattern`'s layout (lower triangle).
Eigen::SparseMatrix<double> mass_matrix(const TetMesh& rest, const Eigen::VectorXd& density,
                                        MassModel model, SparseHessian& pattern);

/// #V vertex masses: the row sums of either mass matrix, sum of m_e / 4 over incident elements.
Eigen::VectorXd vertex_masses(const TetMesh& rest, const Eigen::VectorXd& density);

}  // namespace rbaa
