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
// The correction acts per stiff cluster: stiff elements joined through shared faces. A uniform
// object is one cluster. An attack's continuous design can hold stiff islands (a dense tet,
// alpha ~ 1) floating in near-void elements (alpha^3 ~ 1e-8), and stiff flaps that touch the
// rest of the stiff material only at an edge or a vertex (a hinge). Each turns on its own during
// an impact: without its own finite rotation Newton crept at ~1e-2 m/s for 100 iterations (an
// island, the ball's design at Adam iteration 83), and a flap hinged on an edge crept at ~1e-3 m/s
// (the ball's design at iteration 154) while it was part of its neighbour's rotation. A flap turns
// about its hinge: the hinge's vertices move with their heavier cluster, and the flap's own
// rotation is fitted and applied about the hinge's centre. Vertices of soft elements only move
// linearly: their elements barely resist the stretch.

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <vector>

#include "rbaa/material/material_field.hpp"
#include "rbaa/mesh/tet_mesh.hpp"
#include "rbaa/sim/world.hpp"

namespace rbaa {

/// Vertices grouped into rigid clusters, numbered heaviest first.
struct RigidClusters {
  /// The heaviest cluster holding each vertex, in [0, count), or -1 (no correction).
  std::vector<int> cluster;
  int count = 0;
  /// Per cluster, its vertices that belong to a heavier cluster too (its hinge); empty for a
  /// cluster that touches no heavier one.
  std::vector<std::vector<int>> hinge;

  /// One cluster holding every vertex.
  static RigidClusters whole(int num_vertices);
};

/// Clusters of the elements whose stiffness alpha^3 Y is at least `ratio` times the largest,
/// connected through shared faces and ordered by mass (rho alpha V, heaviest first; ties by first
/// element); vertices of other elements only get -1.
RigidClusters stiff_clusters(const TetMesh& mesh, const MaterialField& materials, double ratio = 1e-3);

/// The corrected step dq' for positions x (3 #V), step dq and vertex masses (#V), each cluster
/// rotated by its own best-fit finite rotation: about its centre of mass, or, for a cluster with a
/// hinge, about the hinge's centre, which moves as its heavier clusters move it.
Eigen::VectorXd rigid_rotation_correction(const Eigen::VectorXd& x, const Eigen::VectorXd& dq,
                                          const Eigen::VectorXd& vertex_masses,
                                          const RigidClusters& clusters);

/// The shape of `from` moved rigidly onto `to`: its mass-weighted centre to that of `to` and
/// rotated by the best-fit (mass-weighted Kabsch) rotation from `from` to `to`. A time step's
/// initial guess for a stiff spinning body: the extrapolated positions `to` rotate its vertices
/// along chords, which stretches the body by theta^2 / 2 and, at Y = 1e13, loads the Hessian's
/// rotations with a geometric stiffness ~1e6 times their inertia.
/// With `bodies`, each body is moved by its own fit; vertices outside every body take `to`.
Eigen::VectorXd rigid_predictor(const Eigen::VectorXd& from, const Eigen::VectorXd& to,
                                const Eigen::VectorXd& vertex_masses,
                                const std::vector<Body>& bodies = {});

/// A Newton step restricted to the rigid motions of the whole body (mass-weighted centre c,
/// translations and rotations about c): with G the 3 #V x 6 basis, solves (G^T H G) d = -G^T g for
/// the lower triangle H of a Hessian and returns the step with its rotation applied as a finite
/// rotation, t + (exp([w]x) - I) r_i. Empty if G^T H G is not positive definite. With `bodies`,
/// each body has its own six rigid motions (G is 3 #V x 6 #bodies; contact couples them in H);
/// vertices outside every body do not move.
Eigen::VectorXd rigid_newton_step(const Eigen::VectorXd& x, const Eigen::VectorXd& g,
                                  const Eigen::SparseMatrix<double>& H_lower,
                                  const Eigen::VectorXd& vertex_masses,
                                  const std::vector<Body>& bodies = {});

}  // namespace rbaa
