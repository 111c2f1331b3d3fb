#pragma once
// Gmsh .msh files, ASCII versions 2.2 and 4.1: nodes, linear tetrahedra and per-element scalar
// fields ($ElementData), which is how rbaa stores materials next to the mesh.

#include <string>

#include "rbaa/io/tet_mesh_file.hpp"

namespace rbaa {

enum class MshVersion { kV22, kV41 };

/// Reads the nodes and 4-node tetrahedra (element type 4) of an ASCII .msh 2.x or 4.1 file.
/// Node tags may be any positive numbers; vertices are numbered 0..#V-1 in file order, and nodes
/// no tet uses are dropped. Points, lines, triangles and quadrangles are skipped; other volume
/// elements (quadratic tets, hexahedra, prisms, pyramids) are errors. Every $ElementData block
/// with one component must give one value per tet; it becomes element_data[name] (#T, ordered
/// like the tets; a later block of the same name replaces an earlier one, e.g. time steps).
/// Throws InputError "FILE:LINE: ..." on malformed input; does not check tet orientation
/// (read_tet_mesh does).
TetMeshFile read_msh(const std::string& path);

/// Writes `mesh` (#V by 3, #T by 4) as an ASCII .msh of the given version, atomically, with
/// every coordinate exact. Each `element_data` field (#T values) becomes a $ElementData block.
void write_msh(const std::string& path, const TetMesh& mesh, const ElementData& element_data = {},
               MshVersion version = MshVersion::kV41);

}  // namespace rbaa
