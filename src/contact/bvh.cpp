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
  keyed_.resize(boxes_.size());
  // Median splits down to leaves of kLeafSize / 2 .. kLeafSize boxes: fewer than n nodes.
  nodes_.reserve(boxes_.size());
  build(0, static_cast<int>(boxes_.size()));
  centres_ = {};
  keyed_ = {};
}

int Bvh::build(int begin, int end) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  if (end - begin <= kLeafSize) {
    Aabb box;
    for (int k = begin; k < end; ++k) box.extend(boxes_[order_[k]]);
    nodes_[index].box = box;
    nodes_[index].begin = begin;
    nodes_[index].end = end;
    return index;
  }
  Aabb centres;
  for (int k = begin; k < end; ++k) centres.extend(centres_[order_[k]]);
  int axis;
  (centres.max - centres.min).maxCoeff(&axis);
  const int mid = begin + (end - begin) / 2;
  // Partition by (centre along the axis, index) pairs copied into one contiguous buffer: the
  // selection then reads memory in order instead of chasing indices into the centres.
  for (int k = begin; k < end; ++k) keyed_[k] = {centres_[order_[k]][axis], order_[k]};
  std::nth_element(keyed_.begin() + begin, keyed_.begin() + mid, keyed_.begin() + end);
  for (int k = begin; k < end; ++k) order_[k] = keyed_[k].second;
  const int left = build(begin, mid);
  const int right = build(mid, end);
  // nodes_ may have reallocated during the recursion: index, not a reference.
  nodes_[index].left = left;
  nodes_[index].right = right;
  nodes_[index].box = nodes_[left].box;  // bounds bottom up: each box is read once
  nodes_[index].box.extend(nodes_[right].box);
  return index;
}

}  // namespace rbaa::contact
