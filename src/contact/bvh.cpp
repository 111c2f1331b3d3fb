#include "rbaa/contact/bvh.hpp"

#include <algorithm>
#include <numeric>

namespace rbaa::contact {
namespace {

// Leaves hold up to this many boxes; with median splits the depth is about log2(n / 4), far
// below the query's fixed stack of 64 for any mesh that fits in memory.
constexpr int kLeafSize = 4;

}  // namespace

Bvh::Bvh(std::vector<Aabb> boxes) : boxes_(std::move(boxes)) {
  if (boxes_.empty()) return;
  order_.resize(boxes_.size());
  std::iota(order_.begin(), order_.end(), 0);
  centres_.resize(boxes_.size());
  for (std::size_t i = 0; i < boxes_.size(); ++i) centres_[i] = boxes_[i].center();
  nodes_.reserve(2 * boxes_.size() / kLeafSize + 1);
  build(0, static_cast<int>(boxes_.size()));
  centres_.clear();
  centres_.shrink_to_fit();
}

int Bvh::build(int begin, int end) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Aabb box, centres;
  for (int k = begin; k < end; ++k) {
    box.extend(boxes_[order_[k]]);
    centres.extend(centres_[order_[k]]);
  }
  nodes_[index].box = box;
  if (end - begin <= kLeafSize) {
    nodes_[index].begin = begin;
    nodes_[index].end = end;
    return index;
  }
  int axis;
  (centres.max - centres.min).maxCoeff(&axis);
  const int mid = begin + (end - begin) / 2;
  std::nth_element(
      order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
      [&](int i, int j) { return boxes_[i].center()[axis] < boxes_[j].center()[axis]; });
  const int left = build(begin, mid);
  const int right = build(mid, end);
  nodes_[index].left = left;  // nodes_ may have reallocated: index, not a reference
  nodes_[index].right = right;
  return index;
}

}  // namespace rbaa::contact
