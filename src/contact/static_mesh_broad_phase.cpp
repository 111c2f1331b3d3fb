#include "rbaa/contact/static_mesh_broad_phase.hpp"

#include <Eigen/Geometry>
#include <algorithm>

namespace rbaa::contact {
namespace {

Eigen::Vector3d row(const Eigen::Ref<const Positions>& V, int v) {
  return Eigen::Vector3d(V(v, 0), V(v, 1), V(v, 2));
}

template <class Elements>
Aabb element_box(const Eigen::Ref<const Positions>& V0, const Eigen::Ref<const Positions>& V1,
                 const Elements& elements, Eigen::Index i, double inflation) {
  Aabb box;
  for (Eigen::Index k = 0; k < elements.cols(); ++k) {
    box.extend(row(V0, elements(i, k)));
    box.extend(row(V1, elements(i, k)));
  }
  box.inflate(inflation);
  return box;
}

template <class Elements>
std::vector<Aabb> static_boxes(const Positions& V, const Elements& elements) {
  std::vector<Aabb> boxes(elements.rows());
  for (Eigen::Index i = 0; i < elements.rows(); ++i) boxes[i] = element_box(V, V, elements, i, 0.0);
  return boxes;
}

// Appends (i, j) for every static box j the query box overlaps, j ascending.
void collect(const Bvh& tree, const Aabb& box, int i, std::vector<int>& scratch,
             std::vector<std::pair<int, int>>& out) {
  scratch.clear();
  tree.query(box, [&](int j) { scratch.push_back(j); });
  std::sort(scratch.begin(), scratch.end());
  for (int j : scratch) out.emplace_back(i, j);
}

double orient(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
              const Eigen::Vector3d& d) {
  return (b - a).dot((c - a).cross(d - a));
}

}  // namespace

StaticMeshBroadPhase::StaticMeshBroadPhase(Positions V, Triangles F, Edges E)
    : V_(std::move(V)), F_(std::move(F)), E_(std::move(E)) {
  std::vector<Aabb> vboxes(V_.rows());
  for (Eigen::Index v = 0; v < V_.rows(); ++v) {
    vboxes[v].extend(row(V_, static_cast<int>(v)));
    bounds_.extend(vboxes[v]);
  }
  vertex_tree_ = Bvh(std::move(vboxes));
  edge_tree_ = Bvh(static_boxes(V_, E_));
  triangle_tree_ = Bvh(static_boxes(V_, F_));
}

StaticMeshCandidates StaticMeshBroadPhase::query(const Eigen::Ref<const Positions>& V0,
                                                 const Eigen::Ref<const Positions>& V1,
                                                 const std::vector<int>& vertices,
                                                 const Eigen::Ref<const Triangles>& F,
                                                 const Eigen::Ref<const Edges>& E,
                                                 double inflation) const {
  StaticMeshCandidates c;
  if (V_.rows() == 0) return c;
  // The whole moving surface first: far from every obstacle, nothing else is looked at.
  Aabb all;
  for (int v : vertices) {
    all.extend(row(V0, v));
    all.extend(row(V1, v));
  }
  all.inflate(inflation);
  if (!all.overlaps(bounds_)) return c;
  std::vector<int> scratch;
  for (int v : vertices) {
    Aabb box;
    box.extend(row(V0, v));
    box.extend(row(V1, v));
    box.inflate(inflation);
    if (box.overlaps(bounds_)) collect(triangle_tree_, box, v, scratch, c.vertex_triangle);
  }
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Aabb box = element_box(V0, V1, F, f, inflation);
    if (box.overlaps(bounds_))
      collect(vertex_tree_, box, static_cast<int>(f), scratch, c.triangle_vertex);
  }
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    const Aabb box = element_box(V0, V1, E, e, inflation);
    if (box.overlaps(bounds_)) collect(edge_tree_, box, static_cast<int>(e), scratch, c.edge_edge);
  }
  return c;
}

void StaticMeshBroadPhase::crossing_candidates(
    const Eigen::Ref<const Positions>& V, const Eigen::Ref<const Triangles>& F,
    const Eigen::Ref<const Edges>& E, std::vector<std::pair<int, int>>& edge_triangle,
    std::vector<std::pair<int, int>>& triangle_edge) const {
  edge_triangle.clear();
  triangle_edge.clear();
  std::vector<int> scratch;
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    const Aabb box = element_box(V, V, E, e, 0.0);
    if (box.overlaps(bounds_))
      collect(triangle_tree_, box, static_cast<int>(e), scratch, edge_triangle);
  }
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Aabb box = element_box(V, V, F, f, 0.0);
    if (box.overlaps(bounds_))
      collect(edge_tree_, box, static_cast<int>(f), scratch, triangle_edge);
  }
}

Edges unique_edges(const Eigen::Ref<const Triangles>& F) {
  std::vector<std::pair<int, int>> edges;
  edges.reserve(3 * F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  Edges E(static_cast<Eigen::Index>(edges.size()), 2);
  for (std::size_t i = 0; i < edges.size(); ++i)
    E.row(static_cast<Eigen::Index>(i)) << edges[i].first, edges[i].second;
  return E;
}

bool segment_triangle_intersect(const Eigen::Vector3d& p, const Eigen::Vector3d& q,
                                const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                const Eigen::Vector3d& c) {
  const double sp = orient(a, b, c, p), sq = orient(a, b, c, q);
  if ((sp > 0 && sq > 0) || (sp < 0 && sq < 0)) return false;
  if (sp == 0 && sq == 0) {
    // Coplanar: a crossing then also shows as a segment-segment contact with an edge or as an
    // endpoint inside; both are at distance zero, which the distance checks report.
    return false;
  }
  const double s1 = orient(p, q, a, b), s2 = orient(p, q, b, c), s3 = orient(p, q, c, a);
  return (s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0);
}

}  // namespace rbaa::contact
