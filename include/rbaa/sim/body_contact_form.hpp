#pragma once
// Contact potential between the bodies of one stacked mesh (IPC, Li et al. 2020): several bodies'
// tet meshes stacked into one TetMesh (disjoint vertex and element ranges), with
//
//   B(q) = sum over pairs closer than d_hat of  m_k(q) b(d_k(q)),
//
// over two pair kinds between surfaces of different bodies: surface vertex of body i - surface
// triangle of body j != i, and surface edge - surface edge. b is the log barrier (barrier.hpp),
// d_k = sqrt(s_k) with s_k the squared distance of the pair's closest features
// (contact/distance_type.hpp), m_k IPC's mollifier for edge-edge pairs with eps_x = 1e-3
// |ea_rest|^2 |eb_rest|^2 from both edges' rest lengths (contact/edge_edge_mollifier.hpp), and 1
// for vertex-triangle pairs; per-pair derivatives in contact_pair.hpp. As for the obstacle meshes
// (mesh_obstacle_form.hpp) the sum runs over primitive pairs, not closest points; kappa and the
// h^2 weight as for the plane form (contact_form.hpp).
//
// All four points of a pair are degrees of freedom (12 dofs), and the Hessian couples vertices of
// different bodies, which share no tet: those blocks extend the Hessian's pattern
// (sparse_hessian.hpp), which then changes with the active pairs.
//
// The active pairs at q are found by the broad phase (contact/broad_phase.hpp, one BVH per body:
// pairs within one body are never considered) and narrow phase each time the form sees a new q
// (kept for the last two, which is what a line search alternates between), so the form stays a
// pure function of q. max_step_size runs additive CCD on every pair whose swept boxes come within
// d_hat over the step, with both sides moving.

#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "rbaa/contact/additive_ccd.hpp"
#include "rbaa/contact/broad_phase.hpp"
#include "rbaa/mesh/tet_mesh.hpp"
#include "rbaa/contact/barrier.hpp"
#include "rbaa/sim/contact_pair.hpp"
#include "rbaa/sim/form.hpp"

namespace rbaa {

enum class BodyPairKind { kVertexTriangle, kEdgeEdge };

/// One active pair: (mesh vertex, surface triangle row) or (surface edge row, surface edge row)
/// with a < b, of different bodies.
struct BodyPair {
  BodyPairKind kind;
  int a;
  int b;
  double squared_distance;  ///< at the configuration the set was built at
};

/// Where two bodies are closest, for start checks and tests.
struct BodyClearance {
  double distance = std::numeric_limits<double>::infinity();  ///< m, over pairs within `within`
  bool intersecting = false;     ///< an edge of one body's surface crosses another's triangle
  int body_a = -1, body_b = -1;  ///< the bodies of the closest (or crossing) pair
  std::string pair;              ///< e.g. "vertex 12 of body 0 - surface triangle 3 of body 1"
};

class BodyContactForm : public Form {
 public:
  /// `rest`: the stacked rest mesh (surfaces and rest edge lengths); `body_of_vertex`: #V body
  /// ids (the vertices of one body share an id; every tet lies in one body).
  BodyContactForm(const TetMesh& rest, std::vector<int> body_of_vertex, double d_hat, double kappa);

  const char* name() const override { return "body contact"; }
  double value(const Eigen::VectorXd& q) const override;
  double value_difference(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const override;
  void add_gradient(const Eigen::VectorXd& q, double scale, Eigen::VectorXd& grad) const override;
  /// kExact: the exact Hessian; kProjected: each pair's 12x12 block projected to PSD (eigenvalues
  /// below zero clamped; flagged when one was below -1e-12 of the block's largest).
  void add_hessian(const Eigen::VectorXd& q, double scale, HessianKind kind,
                   SparseHessian& hessian) const override;
  /// Additive CCD (contact/additive_ccd.hpp; no pair closes more than 90 % of its gap).
  double max_step_size(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const override;
  /// Every pair within d_hat at q1 at a positive distance, and no pair closing below 1e-3 of its
  /// gap along the straight segment q0 -> q1 (as MeshObstacleForm::is_step_valid).
  bool is_step_valid(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const override;
  long ccd_caps() const override { return ccd_caps_; }
  void solution_changed(const Eigen::VectorXd& q) override { active(q); }

  /// Pairs closer than d_hat at q, sorted by (kind, a, b).
  const std::vector<BodyPair>& active_pairs(const Eigen::VectorXd& q) const { return active(q); }
  int num_active_pairs(const Eigen::VectorXd& q) const {
    return static_cast<int>(active(q).size());
  }
  /// Smallest distance over pairs closer than d_hat at q (+infinity if none).
  double min_distance(const Eigen::VectorXd& q) const;
  /// Smallest distance over every pair closer than `within`, and whether two bodies overlap (an
  /// edge of one surface crosses a triangle of another, or one body lies inside another).
  BodyClearance clearance(const Eigen::VectorXd& q, double within) const;
  /// Throws rbaa::InputError naming both bodies when two bodies overlap or touch at q.
  void check_separated(const Eigen::VectorXd& q) const;

  double kappa() const { return kappa_; }
  const contact::Barrier& barrier() const { return barrier_; }
  int num_bodies() const { return static_cast<int>(body_ids_.size()); }
  /// The id of body i (ascending), as given in body_of_vertex.
  int body_id(int i) const { return body_ids_[i]; }
  int body_of_vertex(int v) const { return body_of_vertex_[v]; }
  /// Surface triangles and edges (rows of mesh vertex ids).
  const contact::Triangles& surface_triangles() const { return F_; }
  const contact::Edges& surface_edges() const { return E_; }
  /// Squared rest length of surface edge e (the mollifier's eps_x uses it).
  double edge_rest_squared_length(int e) const { return edge_rest_squared_length_[e]; }
  /// The pair's four points at q in the order the distance functions take them (the vertex of
  /// the first primitive's body first), with the mollifier's eps_x for edge-edge pairs.
  ContactPairPoints points(const BodyPair& p, const Eigen::VectorXd& q) const;

 private:
  struct Cache {
    Eigen::VectorXd q;
    std::vector<BodyPair> pairs;
    bool valid = false;
  };
  const std::vector<BodyPair>& active(const Eigen::VectorXd& q) const;
  std::vector<BodyPair> build(const Eigen::VectorXd& q) const;
  // Candidates of the surfaces swept over q0 -> q1 within `inflation`, as body pairs (distance 0).
  std::vector<BodyPair> candidates(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1,
                                   double inflation) const;
  // Smallest CCD step fraction over pairs whose boxes swept over q0 -> q1 come within inflation.
  double ccd(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1, double inflation,
             const contact::AdditiveCcdSettings& settings) const;
  // Surface vertex positions at q, one row per surface vertex (the broad phase's indexing).
  contact::Positions surface_positions(const Eigen::VectorXd& q) const;
  std::string describe(const BodyPair& p) const;

  std::vector<int> body_of_vertex_;    // #V body ids
  std::vector<int> body_ids_;          // distinct ids, ascending
  std::vector<int> surface_vertices_;  // mesh vertex ids, ascending
  contact::Triangles F_;               // surface triangles (mesh vertex ids)
  contact::Edges E_;                   // surface edges (mesh vertex ids)
  contact::Triangles local_F_;         // the same, indexing surface_vertices_
  contact::Edges local_E_;
  std::vector<int> local_groups_;           // body id per surface vertex
  std::vector<contact::Triangles> body_F_;  // per body (index into body_ids_): its surface
  std::vector<double> edge_rest_squared_length_;
  contact::Barrier barrier_;
  double kappa_;
  mutable Cache cache_[2];
  mutable int next_slot_ = 0;
  mutable long ccd_caps_ = 0;  ///< see Form::ccd_caps
};

}  // namespace rbaa
