#pragma once
// Broad phase of one moving surface against a static one (triangle-mesh obstacles): the static
// surface's vertices, edges and triangles each get a BVH (bvh.hpp) built once, since obstacles
// never move; every query then boxes the moving primitives over the step and walks those trees,
// so no tree is rebuilt per Newton iterate and a body far from every obstacle costs one box test
// (its overall swept box against the obstacles' bounds). broad_phase.hpp's functions rebuild both
// sides' trees per call, which suits two moving bodies but not this.
//
// Shapes as in broad_phase.hpp: V #V by 3 row-major, F #F by 3, E #E by 2. The moving surface's
// primitives index rows of the positions passed to the query (e.g. all of a body's vertices).

#include <Eigen/Core>
#include <vector>

#include "rbaa/contact/aabb.hpp"
#include "rbaa/contact/broad_phase.hpp"
#include "rbaa/contact/bvh.hpp"

namespace rbaa::contact {

/// Candidate pairs of a query; every list sorted by (moving primitive, static primitive).
struct StaticMeshCandidates {
  std::vector<std::pair<int, int>> vertex_triangle;  ///< (moving vertex, static triangle)
  std::vector<std::pair<int, int>> triangle_vertex;  ///< (moving triangle, static vertex)
  std::vector<std::pair<int, int>> edge_edge;        ///< (moving edge, static edge)
  bool empty() const {
    return vertex_triangle.empty() && triangle_vertex.empty() && edge_edge.empty();
  }
};

class StaticMeshBroadPhase {
 public:
  StaticMeshBroadPhase() = default;
  /// The static surface: V, its triangles F and edges E (rows of V).
  StaticMeshBroadPhase(Positions V, Triangles F, Edges E);

  /// Pairs of the moving surface (vertices `vertices`, triangles F, edges E, indexing rows of
  /// V0 / V1) and the static one whose boxes, swept over V0 -> V1 and inflated by `inflation`
  /// (m), overlap: every pair that comes within `inflation` during the linear step is reported.
  StaticMeshCandidates query(const Eigen::Ref<const Positions>& V0,
                             const Eigen::Ref<const Positions>& V1,
                             const std::vector<int>& vertices, const Eigen::Ref<const Triangles>& F,
                             const Eigen::Ref<const Edges>& E, double inflation) const;
  /// (moving edge, static triangle) and (static edge, moving triangle) pairs whose static boxes
  /// at V overlap: the pairs to test for crossings (an intersection of two triangle surfaces
  /// always has an edge of one crossing a triangle of the other).
  void crossing_candidates(const Eigen::Ref<const Positions>& V,
                           const Eigen::Ref<const Triangles>& F, const Eigen::Ref<const Edges>& E,
                           std::vector<std::pair<int, int>>& edge_triangle,
                           std::vector<std::pair<int, int>>& triangle_edge) const;

  const Positions& V() const { return V_; }
  const Triangles& F() const { return F_; }
  const Edges& E() const { return E_; }
  const Aabb& bounds() const { return bounds_; }

 private:
  Positions V_;
  Triangles F_;
  Edges E_;
  Aabb bounds_;
  Bvh vertex_tree_, edge_tree_, triangle_tree_;
};

/// Unique edges of triangles F (#E by 2, each (i, j) with i < j), sorted.
Edges unique_edges(const Eigen::Ref<const Triangles>& F);

/// Whether segment (p, q) and triangle (a, b, c) intersect (touching counts), from the signs of
/// orientation determinants in double precision.
bool segment_triangle_intersect(const Eigen::Vector3d& p, const Eigen::Vector3d& q,
                                const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                const Eigen::Vector3d& c);

}  // namespace rbaa::contact
