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

}  // namespace rbaa
