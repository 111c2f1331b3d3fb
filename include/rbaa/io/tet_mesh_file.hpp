#pragma once
// Reading and writing tetrahedral meshes whatever the format: the extension chooses Gmsh (.msh),
// MEDIT (.mesh) or TetGen (.node/.ele). Readers of one format live in msh.hpp, medit.hpp and
// tetgen.hpp; this is the entry point the command line uses.

#include <Eigen/Core>
#include <map>
#include <string>

#include "rbaa/mesh/tet_mesh.hpp"

namespace rbaa {

/// Named per-tetrahedron scalars (e.g. "Y", "nu", "rho", "alpha"), each #T long, ordered like
/// the mesh's tets.
using ElementData = std::map<std::string, Eigen::VectorXd>;

/// A mesh as read from a file, with the per-element data the file carried (only .msh carries any).
struct TetMeshFile {
  TetMesh mesh;
  ElementData element_data;
};

/// Reads a tet mesh choosing the format by extension: .msh (Gmsh 2.2 or 4.1 ASCII), .mesh
/// (MEDIT), .node or .ele (TetGen; a base name whose .node and .ele exist works too). Then
/// validates it (validate_tet_mesh), so inverted or degenerate tets are rejected. Throws
/// InputError naming the file (and the line, for syntax errors).
TetMeshFile read_tet_mesh(const std::string& path);

/// Writes `mesh` in the format of `path`'s extension (.msh as Gmsh 4.1; .mesh; .node or .ele
/// writes both TetGen files). `element_data` (each #T long) needs .msh; other formats cannot hold
/// it and throw InputError when it is not empty.
void write_tet_mesh(const std::string& path, const TetMesh& mesh,
                    const ElementData& element_data = {});

/// Removes vertices no tet refers to and renumbers the rest, keeping their order. Mesh files
/// often carry such vertices (geometry points, mid-edge nodes of quadratic tets) that a solid
/// simulation must not see. Returns how many were removed.
int remove_unreferenced_vertices(TetMesh& mesh);

}  // namespace rbaa
