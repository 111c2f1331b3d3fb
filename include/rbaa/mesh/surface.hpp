#pragma once
// Closed triangle surfaces: the input of tetrahedralisation.

#include <string>

#include "rbaa/mesh/tet_mesh.hpp"

namespace rbaa {

/// A triangle surface: V is #V by 3, F is #F by 3 with outward (counter-clockwise seen from
/// outside) orientation when the surface is closed.
struct SurfaceMesh {
  Vertices V;
  Faces F;
};

/// Reads a closed surface (OFF, OBJ, STL, PLY) and checks it: readable, non-empty, manifold,
/// closed, not self-intersecting; drops points no face uses; orients it outward. Throws
/// rbaa::InputError naming the file and the fault.
SurfaceMesh read_surface(const std::string& path);

/// The same checks on a surface already in memory (`source` names it in errors).
void validate_surface(SurfaceMesh& surface, const std::string& source);

/// Volume enclosed by a closed, outward-oriented surface (m^3).
double enclosed_volume(const SurfaceMesh& surface);

}  // namespace rbaa
