#pragma once
// The tetrahedral mesh every module shares, and the per-element rest-shape data the simulator
// needs (volumes, inverse rest edge matrices).

#include <Eigen/Core>

#include <string>
#include <utility>
#include <vector>

namespace rbaa {

/// #V by 3 vertex positions in metres, row-major so that the stacked state q (3 #V) is a view of it.
using Vertices = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
/// #T by 4 vertex indices of the tetrahedra.
using Tets = Eigen::Matrix<int, Eigen::Dynamic, 4, Eigen::RowMajor>;
/// #F by 3 vertex indices of triangles.
using Faces = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// A tetrahedral mesh. Convention: every tet (a, b, c, d) is positively oriented,
/// ((b - a) x (c - a)) . (d - a) > 0.
struct TetMesh {
  Vertices V;
  Tets T;

  int num_vertices() const { return static_cast<int>(V.rows()); }
  int num_tets() const { return static_cast<int>(T.rows()); }
};

/// Drops the rows of V that no entry of `elements` (tets, faces: any row-major index matrix)
/// refers to and renumbers `elements`, keeping the order; entries outside [0, #V) are left for the
/// caller's checks. Returns how many rows were dropped.
template <class Elements>
int remove_unreferenced_vertices(Vertices& V, Elements& elements) {
  const int nv = static_cast<int>(V.rows());
  int* const index = elements.data();
  std::vector<int> new_index(nv, -1);
  for (Eigen::Index i = 0; i < elements.size(); ++i) {
    if (index[i] >= 0 && index[i] < nv) new_index[index[i]] = 0;
  }
  int kept = 0;
  for (int& k : new_index) {
    if (k == 0) k = kept++;
  }
  if (kept == nv) return 0;
  Vertices used(kept, 3);
  for (int v = 0; v < nv; ++v) {
    if (new_index[v] >= 0) used.row(new_index[v]) = V.row(v);
  }
  for (Eigen::Index i = 0; i < elements.size(); ++i) {
    if (index[i] >= 0 && index[i] < nv) index[i] = new_index[index[i]];
  }
  V = std::move(used);
  return nv - kept;
}

/// Signed volume ((b - a) x (c - a)) . (d - a) / 6.
double signed_tet_volume(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                         const Eigen::Vector3d& c, const Eigen::Vector3d& d);

/// #T signed volumes of the mesh's tets.
Eigen::VectorXd tet_volumes(const TetMesh& mesh);

/// Throws rbaa::InputError naming `source` and the first fault: indices out of range, unused
/// vertices, non-finite coordinates, inverted or degenerate tets (|volume| below
/// `relative_volume_tolerance` times the mean volume), tets that repeat or overlap across a face
/// (validate_tet_faces).
void validate_tet_mesh(const TetMesh& mesh, const std::string& source,
                       double relative_volume_tolerance = 1e-12);

/// Flips the orientation of negatively oriented tets (swaps the last two indices).
/// Returns how many were flipped.
int orient_tets_positively(TetMesh& mesh);

/// Axis-aligned bounding box diagonal length of the vertices.
double bounding_box_diagonal(const TetMesh& mesh);

/// The middle of the vertices' axis-aligned bounding box.
Eigen::RowVector3d box_middle(const TetMesh& mesh);

/// Per-element rest-shape data for linear-tet FEM: F = Ds Dm^-1 with Dm = [b-a, c-a, d-a].
struct RestShape {
  std::vector<Eigen::Matrix3d> Dm_inv;  ///< #T inverse rest edge matrices
  Eigen::VectorXd volume;               ///< #T rest volumes (positive)
};

/// Precomputes Dm^-1 and volumes; throws rbaa::InputError naming `source` on an inverted or
/// degenerate tet.
RestShape compute_rest_shape(const TetMesh& mesh, const std::string& source = "mesh");

}  // namespace rbaa
