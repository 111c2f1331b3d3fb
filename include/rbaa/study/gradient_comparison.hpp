#pragma once
// Comparing material gradients of the same object computed at different settings, possibly on
// different meshes (the speed/accuracy study, SPEC section 10).
//
// A per-element gradient dC/dx_e is extensive (it scales with the element's volume), so it is
// first turned into a density: g_e = dC/dx_e * s_x / V_e per field x, s_x the half-width of the
// field's design range (dx/dtheta at theta = 0, which also puts Y in Pa and rho in kg/m^3 on one
// scale). Two densities on one mesh are compared by the volume-weighted cosine
//
//   cos = sum_e V_e <a_e, b_e> / sqrt(sum_e V_e |a_e|^2 * sum_e V_e |b_e|^2),
//
// and densities on different meshes after carrying one to the other's elements by centroid
// lookup (material_transfer.hpp). The cosine of a gradient with itself is 1.

#include <Eigen/Core>

#include <string>
#include <vector>

#include "rbaa/material/design_space.hpp"
#include "rbaa/mesh/tet_mesh.hpp"

namespace rbaa {

/// #T by 4 gradient density (columns Y, nu, rho, alpha; a column of a field not in `fields` or
/// given empty is zero). `half_ranges`: s_Y, s_nu, s_rho, s_alpha.
Eigen::MatrixXd gradient_density(const TetMesh& mesh, const MaterialGradient& gradient,
                                 const Eigen::Vector4d& half_ranges,
                                 const std::vector<std::string>& fields);

/// Volume-weighted cosine of two #T by k densities on one mesh (volumes #T). 0 when either is 0.
double gradient_cosine(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b,
                       const Eigen::VectorXd& volumes);

/// The cosine of density `a` on mesh `mesh_a` with density `b` on `mesh_b`, compared on mesh_b
/// (a carried over by centroid lookup; no transfer when the meshes are the same object).
double gradient_cosine_across(const TetMesh& mesh_a, const Eigen::MatrixXd& a,
                              const TetMesh& mesh_b, const Eigen::MatrixXd& b);

}  // namespace rbaa
