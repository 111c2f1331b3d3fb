#pragma once
// Tetrahedralisation of closed surfaces with CGAL Mesh_3 (sequential, fixed seed: the same input
// gives the same mesh), and the reference shapes at a target element count.

#include <string>

#include "rbaa/mesh/meshing_outcome.hpp"
#include "rbaa/mesh/surface.hpp"
#include "rbaa/mesh/tet_mesh.hpp"

namespace rbaa {

struct MeshingOptions {
  /// Wanted number of tets; the cell size is adjusted until the count is within `tolerance`.
  int target_tets = 5000;
  double tolerance = 0.05;
  int max_attempts = 8;
  /// Dihedral angle (degrees) below which surface edges become sharp features kept by the mesh.
  double feature_angle_deg = 60.0;
  /// facet_distance = ratio * cell size (surface approximation error bound).
  double facet_distance_ratio = 1.0 / 15.0;
  unsigned seed = 0;
};

/// Tetrahedralises a closed, outward-oriented surface. The result is validated (positive,
/// non-degenerate tets); throws rbaa::InputError naming `source` on failure. The returned mesh is
/// the attempt closest to options.target_tets, which a surface's detail may not allow within
/// options.tolerance: `outcome` (if given) records the search and says why.
TetMesh tetrahedralize(const SurfaceMesh& surface, const MeshingOptions& options,
                       const std::string& source, MeshingOutcome* outcome = nullptr);

/// Tetrahedralises once at a given cell size (m); used by tetrahedralize's count search.
TetMesh tetrahedralize_with_size(const SurfaceMesh& surface, double cell_size,
                                 const MeshingOptions& options, const std::string& source);

/// Parameters of the reference shapes; values <= 0 take SPEC section 7's defaults.
struct ShapeParameters {
  double radius = 0;  ///< sphere (default 0.121)
  double side = 0;    ///< cube (default 0.05)
};

/// The one size a mesh source reads: "radius" for the sphere, "side" for the cube, "volume" for a
/// surface file (`shape` empty), "" for the other shapes. A size given to another source is not
/// read (the config and `rbaa mesh` refuse it by this rule).
const char* mesh_size_key(const std::string& shape);

/// The paper's tet counts: ball 9056, star 1506, bunny 2274, cube 10164, bat 9098.
int default_tet_count(const std::string& shape);

/// Meshes a reference shape (sphere, cube, star, bat, bunny) with about `target_tets` tets
/// (default_tet_count when 0). The bunny is CGAL's bunny00.off turned upright
/// ((x, y, z) <- (z, x, y)), scaled to volume 1.5604 m^3 and centred at its centroid.
TetMesh mesh_shape(const std::string& shape, int target_tets, const ShapeParameters& params = {},
                   MeshingOutcome* outcome = nullptr);

/// Meshes a closed surface file; with volume > 0 the tet mesh is scaled to that volume and
/// centred at its centroid.
TetMesh mesh_surface_file(const std::string& path, int target_tets, double volume = 0.0,
                          MeshingOutcome* outcome = nullptr);

/// Path of CGAL's bunny00.off (RBAA_DATA_DIR, the build tree, or the installed share folder).
std::string bunny_surface_path();

}  // namespace rbaa
