#include "rbaa/contact/broad_phase.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "rbaa/contact/bvh.hpp"

namespace rbaa::contact {
namespace {

// Box of a primitive (row i of `elements`, its vertex indices) over the step, grown by half the
// inflation: two boxes grown by r / 2 each overlap iff the original boxes are within r of each
// other along every axis, which any two points closer than r are.
template <class Elements>
Aabb swept_box(const Eigen::Ref<const Positions>& V0, const Eigen::Ref<const Positions>& V1,
               const Elements& elements, Eigen::Index i, double half_inflation) {
  Aabb box;
  for (Eigen::Index k = 0; k < elements.cols(); ++k) {
    const int v = elements(i, k);
    box.extend(Eigen::Vector3d(V0(v, 0), V0(v, 1), V0(v, 2)));
    box.extend(Eigen::Vector3d(V1(v, 0), V1(v, 1), V1(v, 2)));
  }
  box.inflate(half_inflation);
  return box;
}

Aabb swept_vertex_box(const Eigen::Ref<const Positions>& V0, const Eigen::Ref<const Positions>& V1,
                      int v, double half_inflation) {
  Aabb box;
  box.extend(Eigen::Vector3d(V0(v, 0), V0(v, 1), V0(v, 2)));
  box.extend(Eigen::Vector3d(V1(v, 0), V1(v, 1), V1(v, 2)));
  box.inflate(half_inflation);
  return box;
}

template <class Elements>
std::vector<Aabb> swept_boxes(const Eigen::Ref<const Positions>& V0,
                              const Eigen::Ref<const Positions>& V1, const Elements& elements,
                              double half_inflation) {
  std::vector<Aabb> boxes(elements.rows());
  for (Eigen::Index i = 0; i < elements.rows(); ++i)
    boxes[i] = swept_box(V0, V1, elements, i, half_inflation);
  return boxes;
}

// Primitives split by the group of their first vertex, with each group's overall bounds.
struct Groups {
  std::vector<int> ids;                   ///< distinct groups, ascending
  std::vector<std::vector<int>> members;  ///< per group: primitive indices
  std::vector<Aabb> bounds;               ///< per group: union of its members' boxes
};

template <class GroupOf>
Groups split(const std::vector<Aabb>& boxes, const GroupOf& group_of) {
  Groups g;
  for (std::size_t i = 0; i < boxes.size(); ++i) g.ids.push_back(group_of(i));
  std::sort(g.ids.begin(), g.ids.end());
  g.ids.erase(std::unique(g.ids.begin(), g.ids.end()), g.ids.end());
  g.members.resize(g.ids.size());
  g.bounds.resize(g.ids.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const std::size_t k = std::lower_bound(g.ids.begin(), g.ids.end(), group_of(i)) - g.ids.begin();
    g.members[k].push_back(static_cast<int>(i));
    g.bounds[k].extend(boxes[i]);
  }
  return g;
}

// The members whose boxes overlap `region` (a group's bounds): only these can pair with it.
std::vector<int> overlapping(const std::vector<int>& members, const std::vector<Aabb>& boxes,
                             const Aabb& region) {
  std::vector<int> out;
  for (int i : members)
    if (boxes[i].overlaps(region)) out.push_back(i);
  return out;
}

// Calls emit(a, b) for every a in `as`, b in `bs` whose boxes overlap, building a BVH over the
// shorter list (a build costs several queries) and querying it with the longer.
template <class Emit>
void overlapping_pairs(const std::vector<int>& as, const std::vector<Aabb>& a_boxes,
                       const std::vector<int>& bs, const std::vector<Aabb>& b_boxes, Emit&& emit) {
  if (as.empty() || bs.empty()) return;
  const bool tree_over_b = bs.size() <= as.size();
  const std::vector<int>& in_tree = tree_over_b ? bs : as;
  const std::vector<Aabb>& tree_boxes = tree_over_b ? b_boxes : a_boxes;
  std::vector<Aabb> boxes(in_tree.size());
  for (std::size_t k = 0; k < in_tree.size(); ++k) boxes[k] = tree_boxes[in_tree[k]];
  const Bvh bvh(std::move(boxes));
  for (int q : tree_over_b ? as : bs) {
    const Aabb& box = tree_over_b ? a_boxes[q] : b_boxes[q];
    bvh.query(box, [&](int k) {
      if (tree_over_b)
        emit(q, in_tree[k]);
      else
        emit(in_tree[k], q);
    });
  }
}

void check_groups(const std::vector<int>& groups, Eigen::Index num_vertices) {
  if (!groups.empty() && static_cast<Eigen::Index>(groups.size()) != num_vertices)
    throw std::invalid_argument("broad phase: " + std::to_string(groups.size()) +
                                " vertex groups for " + std::to_string(num_vertices) + " vertices");
}

}  // namespace

std::vector<VertexTriangleCandidate> vertex_triangle_candidates(
    const Eigen::Ref<const Positions>& V0, const Eigen::Ref<const Positions>& V1,
    const Eigen::Ref<const Triangles>& F, double inflation, const std::vector<int>& groups) {
  check_groups(groups, V0.rows());
  std::vector<Aabb> vertex_boxes(V0.rows());
  for (Eigen::Index v = 0; v < V0.rows(); ++v)
    vertex_boxes[v] = swept_vertex_box(V0, V1, static_cast<int>(v), inflation / 2);
  const std::vector<Aabb> triangle_boxes = swept_boxes(V0, V1, F, inflation / 2);
  const Groups vg =
      split(vertex_boxes, [&](std::size_t v) { return groups.empty() ? 0 : groups[v]; });
  const Groups tg =
      split(triangle_boxes, [&](std::size_t f) { return groups.empty() ? 0 : groups[F(f, 0)]; });
  std::vector<VertexTriangleCandidate> out;
  for (std::size_t i = 0; i < vg.ids.size(); ++i)
    for (std::size_t j = 0; j < tg.ids.size(); ++j) {
      if (!groups.empty() && vg.ids[i] == tg.ids[j]) continue;
      if (!vg.bounds[i].overlaps(tg.bounds[j])) continue;
      overlapping_pairs(overlapping(vg.members[i], vertex_boxes, tg.bounds[j]), vertex_boxes,
                        overlapping(tg.members[j], triangle_boxes, vg.bounds[i]), triangle_boxes,
                        [&](int v, int f) {
                          if (F(f, 0) != v && F(f, 1) != v && F(f, 2) != v) out.push_back({v, f});
                        });
    }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
    return a.vertex != b.vertex ? a.vertex < b.vertex : a.triangle < b.triangle;
  });
  return out;
}

std::vector<EdgeEdgeCandidate> edge_edge_candidates(const Eigen::Ref<const Positions>& V0,
                                                    const Eigen::Ref<const Positions>& V1,
                                                    const Eigen::Ref<const Edges>& E,
                                                    double inflation,
                                                    const std::vector<int>& groups) {
  check_groups(groups, V0.rows());
  const std::vector<Aabb> boxes = swept_boxes(V0, V1, E, inflation / 2);
  const Groups eg =
      split(boxes, [&](std::size_t e) { return groups.empty() ? 0 : groups[E(e, 0)]; });
  std::vector<EdgeEdgeCandidate> out;
  const auto emit = [&](int a, int b) {
    if (a == b) return;
    if (E(a, 0) == E(b, 0) || E(a, 0) == E(b, 1) || E(a, 1) == E(b, 0) || E(a, 1) == E(b, 1))
      return;
    out.push_back({a, b});
  };
  const std::size_t n = eg.ids.size();
  // Each unordered pair of groups once; a group with itself only without groups.
  for (std::size_t g = 0; g < n; ++g)
    for (std::size_t h = groups.empty() ? g : g + 1; h < n; ++h) {
      if (!eg.bounds[g].overlaps(eg.bounds[h])) continue;
      overlapping_pairs(overlapping(eg.members[g], boxes, eg.bounds[h]), boxes,
                        overlapping(eg.members[h], boxes, eg.bounds[g]), boxes, [&](int a, int b) {
                          // Within one group both orders come up: keep one.
                          if (g != h || a < b) emit(std::min(a, b), std::max(a, b));
                        });
    }
  std::sort(out.begin(), out.end(), [](const auto& x, const auto& y) {
    return x.edge_a != y.edge_a ? x.edge_a < y.edge_a : x.edge_b < y.edge_b;
  });
  return out;
}

}  // namespace rbaa::contact
