#pragma once
// Exact mass moments of a linear-tet mesh with per-element density (SPEC section 4):
// m0 = int rho dV, m1 = int rho x dV, m2 = int rho (x.x I - x x^T) dV about the origin, stored
// as (xx, yy, zz, xy, xz, yz) with the off-diagonals minus the products.

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <array>

#include "rbaa/mesh/tet_mesh.hpp"

namespace rbaa {

/// The 10 moments, ordered m0, m1 (x, y, z), m2 (xx, yy, zz, xy, xz, yz).
using MomentVector = Eigen::Matrix<double, 10, 1>;

struct Moments {
  double m0 = 0;
  Eigen::Vector3d m1 = Eigen::Vector3d::Zero();
  Eigen::Matrix<double, 6, 1> m2 = Eigen::Matrix<double, 6, 1>::Zero();

  MomentVector as_vector() const;
  static Moments from_vector(const MomentVector& v);
  /// Centre of mass m1 / m0.
  Eigen::Vector3d centre_of_mass() const { return m1 / m0; }
  /// The 3x3 inertia tensor about the origin built from m2.
  Eigen::Matrix3d inertia_about_origin() const;
  /// The inertia tensor about the centre of mass (parallel-axis shift).
  Eigen::Matrix3d inertia_about_centre() const;
};

/// The moment operator S (10 by #T): moments = S * density, with density the per-element mass
/// density rho alpha (kg/m^3). Column e holds element e's exact integrals of 1, x and the m2
/// integrands over its volume.
Eigen::Matrix<double, 10, Eigen::Dynamic> moment_operator(const TetMesh& mesh);

/// Moments of the mesh with per-element density (#T).
Moments compute_moments(const TetMesh& mesh, const Eigen::VectorXd& density);

/// Moments of the mesh at uniform density.
Moments compute_moments(const TetMesh& mesh, double density);

/// Radius of gyration L = sqrt(trace(I_centre) / (2 m0)), the length that normalises moments.
double radius_of_gyration(const Moments& m);

/// Per-row scale of the normalised moment residual: m0 by m0_ref, m1 by m0_ref L,
/// m2 by m0_ref L^2 (SPEC section 4).
MomentVector moment_normalisation(const Moments& reference);

}  // namespace rbaa
