#pragma once
// A Newton step of a near-rigid body moves its vertices along the tangents of its rotation, which
// stretches the body by theta^2 / 2 for a rotation theta; at Y = 1e13 Pa that stretch costs more
// than the step gains, and Newton creeps through a rotating contact step in tiny increments.
// Splitting the step into its best-fit rigid motion (translation t, infinitesimal rotation w,
// mass-weighted) and the rest, and applying the rotation as the finite rotation exp([w]x), removes
// the spurious stretch:
//
//   dq_i' = t + (exp([w]x) - I) r_i + (dq_i - t - w x r_i),   r_i = x_i - c.
//
// dq' = dq + O(|w|^2 |r|), so it stays a descent direction for the small rotations of one step
// (the Newton solver checks and falls back to dq otherwise).
//
// The correction acts per stiff cluster: the vertices of stiff elements, grouped by shared
// vertices. A uniform object is one cluster. An attack's continuous design can hold stiff islands
// (a dense tet, alpha ~ 1) floating in near-void elements (alpha^3 ~ 1e-8); an island rotates on
// its own during an impact, and without its own finite rotation Newton crept at ~1e-2 m/s for 100
// iterations (the ball's design at Adam iteration 83). Vertices of soft elements only move
// linearly: their elements barely resist the stretch.

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <vector>

#include "rbaa/material/material_field.hpp"
#include "rbaa/mesh/tet_mesh.hpp"

namespace rbaa {

/// Vertices grouped into rigid clusters: cluster[v] in [0, count) or -1 (no correction).
struct RigidClusters {
  std::vector<int> cluster;
  int count = 0;

  /// One cluster holding every vertex.
  static RigidClusters whole(int num_vertices);
};

/// Clusters of the elements whose stiffness alpha^3 Y is at least `ratio` times the largest,
/// connected through shared vertices; vertices of other elements only get -1.
RigidClusters stiff_clusters(const TetMesh& mesh, const MaterialField& materials, double ratio = 1e-3);

/// The corrected step dq' for positions x (3 #V), step dq and vertex masses (#V), each cluster
/// rotated by its own best-fit finite rotation.
Eigen::VectorXd rigid_rotation_correction(const Eigen::VectorXd& x, const Eigen::VectorXd& dq,
                                          const Eigen::VectorXd& vertex_masses,
                                          const RigidClusters& clusters);

/// The shape of `from` moved rigidly onto `to`: its mass-weighted centre to that of `to` and
/// rotated by the best-fit (mass-weighted Kabsch) rotation from `from` to `to`. A time step's
/// initial guess for a stiff spinning body: the extrapolated positions `to` rotate its vertices
/// along chords, which stretches the body by theta^2 / 2 and, at Y = 1e13, loads the Hessian's
/// rotations with a geometric stiffness ~1e6 times their inertia.
Eigen::VectorXd rigid_predictor(const Eigen::VectorXd& from, const Eigen::VectorXd& to,
                                const Eigen::VectorXd& vertex_masses);

/// A Newton step restricted to the rigid motions of the whole body (mass-weighted centre c,
/// translations and rotations about c): with G the 3 #V x 6 basis, solves (G^T H G) d = -G^T g for
/// the lower triangle H of a Hessian and returns the step with its rotation applied as a finite
/// rotation, t + (exp([w]x) - I) r_i. Empty if G^T H G is not positive definite.
Eigen::VectorXd rigid_newton_step(const Eigen::VectorXd& x, const Eigen::VectorXd& g,
                                  const Eigen::SparseMatrix<double>& H_lower,
                                  const Eigen::VectorXd& vertex_masses);

}  // namespace rbaa
