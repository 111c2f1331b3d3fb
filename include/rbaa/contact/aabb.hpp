#pragma once
// Axis-aligned bounding boxes of primitives, static or swept over a linear step, inflated by a
// distance so that a pair closer than it has overlapping boxes.

#include <Eigen/Core>
#include <limits>

namespace rbaa::contact {

struct Aabb {
  Eigen::Vector3d min = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d max = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());

  /// Grows the box to contain x.
  void extend(const Eigen::Vector3d& x) {
    min = min.cwiseMin(x);
    max = max.cwiseMax(x);
  }
  void extend(const Aabb& b) {
    min = min.cwiseMin(b.min);
    max = max.cwiseMax(b.max);
  }
  /// Grows the box by r on every side.
  void inflate(double r) {
    min.array() -= r;
    max.array() += r;
  }
  /// Closed boxes: touching counts as overlapping.
  bool overlaps(const Aabb& b) const {
    return (min.array() <= b.max.array()).all() && (b.min.array() <= max.array()).all();
  }
  Eigen::Vector3d center() const { return (min + max) / 2; }
};

}  // namespace rbaa::contact
