#pragma once
// A bounding volume hierarchy over boxes, rebuilt from scratch whenever the boxes change (once per
// line search step: cheaper than refitting for the few thousand primitives of our bodies). Built
// top down, splitting each node at the median of its boxes' centres along its longest axis, so
// the tree is balanced whatever the boxes' sizes: a backboard of two large triangles and a ball of
// thousands of small ones share one tree without a cell size to tune.

#include <Eigen/Core>
#include <utility>
#include <vector>

#include "rbaa/contact/aabb.hpp"

namespace rbaa::contact {

class Bvh {
 public:
  Bvh() = default;
  /// Builds over boxes; the query reports indices into this vector.
  explicit Bvh(std::vector<Aabb> boxes);

  /// Calls visit(i) for every box i that overlaps query, each once, in no particular order.
  template <class Visit>
  void query(const Aabb& query, Visit&& visit) const;

  bool empty() const { return boxes_.empty(); }
  std::size_t size() const { return boxes_.size(); }

 private:
  struct Node {
    Aabb box;
    int left = -1, right = -1;  ///< children, or -1 for a leaf
    int begin = 0, end = 0;     ///< a leaf's range in order_
  };
  int build(int begin, int end);

  std::vector<Aabb> boxes_;
  std::vector<int> order_;  ///< box indices, grouped by leaf
  std::vector<Node> nodes_;
  std::vector<Eigen::Vector3d> centres_;       ///< boxes' centres, during the build only
  std::vector<std::pair<double, int>> keyed_;  ///< partition buffer, during the build only
};

template <class Visit>
void Bvh::query(const Aabb& query, Visit&& visit) const {
  if (nodes_.empty()) return;
  int stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (!node.box.overlaps(query)) continue;
    if (node.left < 0) {
      for (int k = node.begin; k < node.end; ++k)
        if (boxes_[order_[k]].overlaps(query)) visit(order_[k]);
    } else {
      stack[top++] = node.left;
      stack[top++] = node.right;
    }
  }
}

}  // namespace rbaa::contact
