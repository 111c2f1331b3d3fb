#pragma once
// MEDIT .mesh files (ASCII, as written by MMG, TetGen and CGAL): Vertices and Tetrahedra with
// 1-based indices. Only the tet mesh is kept; surface annotations are skipped.

#include <string>

#include "rbaa/mesh/tet_mesh.hpp"

namespace rbaa {

/// Reads the Vertices and Tetrahedra of an ASCII .mesh (Dimension 3); skips Triangles, Edges,
/// Corners, Ridges, Normals and similar; refuses other volume elements. Vertices no tet uses are
/// dropped. Throws InputError "FILE:LINE: ..." on malformed input; orientation is not checked.
TetMesh read_medit(const std::string& path);

/// Writes `mesh` (#V by 3, #T by 4) as MEDIT .mesh (MeshVersionFormatted 2, references 0 for
/// vertices, 1 for tets), atomically, with every coordinate exact.
void write_medit(const std::string& path, const TetMesh& mesh);

}  // namespace rbaa
