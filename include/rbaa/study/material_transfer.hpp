#pragma once
// Moving per-element fields between two tet meshes of the same object (SPEC section 10's study:
// a finer mesh of the adversarial star, gradients compared across resolutions). Each target
// element takes the value of the source element that contains its centroid; a centroid outside
// every source element (a curved surface discretised differently) takes the source element whose
// centroid is nearest. A field constant on a region is thus reproduced exactly on every target
// element whose centroid lies in that region.

#include <Eigen/Core>

#include <vector>

#include "rbaa/material/material_field.hpp"
#include "rbaa/mesh/tet_mesh.hpp"

namespace rbaa {

/// Point location in a tet mesh through a uniform grid of buckets over the elements' bounding
/// boxes (about one element per bucket).
class ElementLocator {
 public:
  explicit ElementLocator(const TetMesh& mesh);
  /// The element containing p (barycentric coordinates >= -tolerance; the lowest index when
  /// several do), or -1.
  int containing(const Eigen::Vector3d& p, double tolerance = 1e-10) const;
  /// The element containing p, or else the one whose centroid is nearest to p.
  int containing_or_nearest(const Eigen::Vector3d& p) const;

 private:
  long bucket(const Eigen::Vector3i& c) const;
  Eigen::Vector3i cell(const Eigen::Vector3d& p) const;

  const TetMesh& mesh_;
  Eigen::MatrixX3d centroids_;
  std::vector<Eigen::Matrix3d> inverse_;  // barycentric map per element
  Eigen::Vector3d lo_, cell_size_;
  Eigen::Vector3i dims_;
  std::vector<int> start_, items_;
};

/// For every tet of `to`, the index of the `from` tet that holds its centroid (nearest centroid
/// when none does). #T_to entries.
std::vector<int> centroid_lookup(const TetMesh& from, const TetMesh& to);

/// Rows of `values` (#T_from by k) taken to `to`'s tets by centroid lookup (#T_to by k).
Eigen::MatrixXd transfer_element_values(const TetMesh& from, const Eigen::MatrixXd& values,
                                        const TetMesh& to);

/// The material field of `from` carried to `to` element-wise by centroid lookup.
MaterialField transfer_materials(const TetMesh& from, const MaterialField& field, const TetMesh& to);

}  // namespace rbaa
