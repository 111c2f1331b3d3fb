#include "rbaa/contact/broad_phase.hpp"

#include <algorithm>

#include "rbaa/contact/bvh.hpp"

namespace rbaa::contact {
namespace {

// Box of a primitive (row i of `elements`, its vertex indices) over the step, grown by half the
// inflation: two boxes grown by r / 2 each overlap iff the original boxes are within r of each
// other along every axis, which any two points closer than r are.
Aabb swept_box(const Eigen::MatrixXd& V0, const Eigen::MatrixXd& V1,
               const Eigen::MatrixXi& elements, Eigen::Index i, double half_inflation) {
  Aabb box;
  for (Eigen::Index k = 0; k < elements.cols(); ++k) {
    const int v = elements(i, k);
    box.extend(Eigen::Vector3d(V0(v, 0), V0(v, 1), V0(v, 2)));
    box.extend(Eigen::Vector3d(V1(v, 0), V1(v, 1), V1(v, 2)));
  }
  box.inflate(half_inflation);
  return box;
}

Aabb swept_vertex_box(const Eigen::MatrixXd& V0, const Eigen::MatrixXd& V1, int v,
                      double half_inflation) {
  Aabb box;
  box.extend(Eigen::Vector3d(V0(v, 0), V0(v, 1), V0(v, 2)));
  box.extend(Eigen::Vector3d(V1(v, 0), V1(v, 1), V1(v, 2)));
  box.inflate(half_inflation);
  return box;
}

std::vector<Aabb> swept_boxes(const Eigen::MatrixXd& V0, const Eigen::MatrixXd& V1,
                              const Eigen::MatrixXi& elements, double half_inflation) {
  std::vector<Aabb> boxes(elements.rows());
  for (Eigen::Index i = 0; i < elements.rows(); ++i)
    boxes[i] = swept_box(V0, V1, elements, i, half_inflation);
  return boxes;
}

}  // namespace

std::vector<VertexTriangleCandidate> vertex_triangle_candidates(const Eigen::MatrixXd& V0,
                                                                const Eigen::MatrixXd& V1,
                                                                const Eigen::MatrixXi& F,
                                                                double inflation,
                                                                const CanCollide& can_collide) {
  const Bvh bvh(swept_boxes(V0, V1, F, inflation / 2));
  std::vector<VertexTriangleCandidate> out;
  for (int v = 0; v < static_cast<int>(V0.rows()); ++v) {
    const Aabb box = swept_vertex_box(V0, V1, v, inflation / 2);
    const std::size_t first = out.size();
    bvh.query(box, [&](int f) {
      if (F(f, 0) == v || F(f, 1) == v || F(f, 2) == v) return;
      if (can_collide && !can_collide(v, F(f, 0))) return;
      out.push_back({v, f});
    });
    std::sort(out.begin() + first, out.end(),
              [](const auto& a, const auto& b) { return a.triangle < b.triangle; });
  }
  return out;
}

std::vector<EdgeEdgeCandidate> edge_edge_candidates(const Eigen::MatrixXd& V0,
                                                    const Eigen::MatrixXd& V1,
                                                    const Eigen::MatrixXi& E, double inflation,
                                                    const CanCollide& can_collide) {
  std::vector<Aabb> boxes = swept_boxes(V0, V1, E, inflation / 2);
  const Bvh bvh(boxes);
  std::vector<EdgeEdgeCandidate> out;
  for (int a = 0; a < static_cast<int>(E.rows()); ++a) {
    const std::size_t first = out.size();
    bvh.query(boxes[a], [&](int b) {
      if (b <= a) return;
      if (E(a, 0) == E(b, 0) || E(a, 0) == E(b, 1) || E(a, 1) == E(b, 0) || E(a, 1) == E(b, 1))
        return;
      if (can_collide && !can_collide(E(a, 0), E(b, 0))) return;
      out.push_back({a, b});
    });
    std::sort(out.begin() + first, out.end(),
              [](const auto& x, const auto& y) { return x.edge_b < y.edge_b; });
  }
  return out;
}

}  // namespace rbaa::contact
