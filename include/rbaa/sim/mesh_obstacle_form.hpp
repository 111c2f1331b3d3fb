#pragma once
// Contact potential of the body against static triangle-mesh obstacles (IPC, Li et al. 2020):
//
//   B(q) = sum over pairs closer than d_hat of  m_k(q) b(d_k(q)),
//
// b the same log barrier on unsigned distances as against planes (barrier.hpp), d_k = sqrt(s_k)
// with s_k the squared distance of the pair's closest features (contact/distance_type.hpp), over
// three pair kinds: body surface vertex - obstacle triangle, obstacle vertex - body surface
// triangle, body surface edge - obstacle edge. m_k is IPC's mollifier for edge-edge pairs
// (contact/edge_edge_mollifier.hpp, eps_x from the body edge's rest length) and 1 otherwise. As
// in IPC's original formulation, a vertex near an obstacle edge counts once per triangle and once
// more through edge-edge pairs: the potential is a sum over primitive pairs, not over closest
// points. kappa and the h^2 weight as for the plane form (contact_form.hpp).
//
// Obstacle vertices are not degrees of freedom: a pair's derivatives are those with respect to
// its body vertices only (3, 6 or 9 dofs), and its Hessian blocks couple vertices of one body
// surface triangle or edge, which always share a tet, so the Hessian pattern does not change.
//
// The active pairs at q are found by the broad phase (contact/static_mesh_broad_phase.hpp) and
// narrow phase each time the form sees a new q (kept for the last two, which is what a line
// search alternates between), so the form stays a pure function of q. max_step_size runs additive
// CCD on every pair whose swept boxes come within d_hat over the step.

#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "rbaa/contact/additive_ccd.hpp"
#include "rbaa/contact/broad_phase.hpp"
#include "rbaa/contact/static_mesh_broad_phase.hpp"
#include "rbaa/mesh/tet_mesh.hpp"
#include "rbaa/sim/world.hpp"
#include "rbaa/contact/barrier.hpp"
#include "rbaa/sim/contact_pair.hpp"
#include "rbaa/sim/form.hpp"

namespace rbaa {

enum class ObstaclePairKind { kVertexTriangle, kTriangleVertex, kEdgeEdge };

/// One active pair: body primitive (surface vertex id, surface triangle row or surface edge row)
/// against obstacle primitive (stacked obstacle triangle, vertex or edge row).
struct ObstaclePair {
  ObstaclePairKind kind;
  int body;
  int obstacle;
  double squared_distance;  ///< at the configuration the set was built at
};

/// Where the body is closest to the obstacles, for start checks and tests.
struct ObstacleClearance {
  double distance = std::numeric_limits<double>::infinity();  ///< m, over pairs within `within`
  bool intersecting = false;  ///< an edge of one surface crosses a triangle of the other
  int mesh = -1;              ///< obstacle mesh index of the closest (or crossing) pair
  std::string pair;           ///< e.g. "body vertex 12 - obstacle triangle 3"
};

class MeshObstacleForm : public Form {
 public:
  /// `rest`: the body's rest mesh (surface and rest edge lengths); `obstacles`: placed meshes.
  MeshObstacleForm(const TetMesh& rest, const std::vector<ObstacleMesh>& obstacles, double d_hat,
                   double kappa);

  const char* name() const override { return "mesh obstacle contact"; }
  double value(const Eigen::VectorXd& q) const override;
  double value_difference(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const override;
  void add_gradient(const Eigen::VectorXd& q, double scale, Eigen::VectorXd& grad) const override;
  /// kExact: the exact Hessian; kProjected: each pair's body block projected to PSD (eigenvalues
  /// below zero clamped; flagged when one was below -1e-12 of the block's largest).
  void add_hessian(const Eigen::VectorXd& q, double scale, HessianKind kind,
                   SparseHessian& hessian) const override;
  /// Additive CCD (contact/additive_ccd.hpp; no pair closes more than 90 % of its gap).
  double max_step_size(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const override;
  /// Every pair within d_hat at q1 at a positive distance, and no pair closing below 1e-3 of its
  /// gap along the straight segment q0 -> q1 (CCD again: the trial a line search tries need not
  /// lie on the segment max_step_size was asked about, and a triangle can be tunnelled through).
  bool is_step_valid(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const override;
  long ccd_caps() const override { return ccd_caps_; }
  void solution_changed(const Eigen::VectorXd& q) override { active(q); }

  /// Pairs closer than d_hat at q, sorted by (kind, body, obstacle).
  const std::vector<ObstaclePair>& active_pairs(const Eigen::VectorXd& q) const {
    return active(q);
  }
  int num_active_pairs(const Eigen::VectorXd& q) const {
    return static_cast<int>(active(q).size());
  }
  /// Smallest distance over pairs closer than d_hat at q (+infinity if none).
  double min_distance(const Eigen::VectorXd& q) const;
  /// Smallest distance over every pair closer than `within` and whether the surfaces cross.
  ObstacleClearance clearance(const Eigen::VectorXd& q, double within) const;

  double kappa() const { return kappa_; }
  const contact::Barrier& barrier() const { return barrier_; }
  const contact::Triangles& surface_triangles() const { return body_F_; }
  const contact::Edges& surface_edges() const { return body_E_; }
  const contact::StaticMeshBroadPhase& obstacles() const { return broad_; }
  /// Squared rest length of surface edge e (the mollifier's eps_x uses it).
  double edge_rest_squared_length(int e) const { return edge_rest_squared_length_[e]; }
  /// "obstacles.meshes[i] (FILE)".
  const std::string& mesh_name(int mesh) const { return mesh_names_[mesh]; }
  /// Obstacle mesh index of a stacked obstacle vertex.
  int mesh_of_obstacle_vertex(int v) const { return mesh_of_vertex_[v]; }
  int num_meshes() const { return static_cast<int>(mesh_names_.size()); }
  /// Obstacle mesh index of a pair's obstacle primitive.
  int mesh_of_pair(const ObstaclePair& p) const;
  /// The pair's four points at q in the order the distance functions take them (fixed obstacle
  /// points with vertex -1), with the mollifier's eps_x for edge-edge pairs.
  ContactPairPoints points(const ObstaclePair& p, const Eigen::VectorXd& q) const;

 private:
  struct Cache {
    Eigen::VectorXd q;
    std::vector<ObstaclePair> pairs;
    bool valid = false;
  };
  const std::vector<ObstaclePair>& active(const Eigen::VectorXd& q) const;
  std::vector<ObstaclePair> build(const Eigen::VectorXd& q) const;
  // Smallest CCD step fraction over pairs whose boxes swept over q0 -> q1 come within inflation.
  double ccd(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1, double inflation,
             const contact::AdditiveCcdSettings& settings) const;

  std::vector<int> body_vertices_;  // surface vertices
  contact::Triangles body_F_;       // surface triangles (body vertex ids)
  contact::Edges body_E_;           // surface edges (body vertex ids)
  std::vector<double> edge_rest_squared_length_;
  contact::StaticMeshBroadPhase broad_;
  std::vector<int> mesh_of_vertex_;
  std::vector<std::string> mesh_names_;
  contact::Barrier barrier_;
  double kappa_;
  mutable Cache cache_[2];
  mutable int next_slot_ = 0;
  mutable long ccd_caps_ = 0;  ///< see Form::ccd_caps
};

}  // namespace rbaa
