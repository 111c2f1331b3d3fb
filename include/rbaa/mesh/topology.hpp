#pragma once
// Combinatorial structure of a tet mesh: its boundary surface, which elements and vertices touch
// it, and face adjacency between elements (the dual graph used by connectivity repair).

#include <string>
#include <vector>

#include "rbaa/mesh/tet_mesh.hpp"

namespace rbaa {

/// #F by 3 boundary triangles (faces used by exactly one tet), oriented with outward normals.
/// Deterministic order: by element index, then local face index.
Faces boundary_faces(const TetMesh& mesh);

/// Why `adversarial` does not have `reference`'s outer surface, or "" when it does: their bounding
/// boxes agree and every boundary vertex of `reference` is a vertex of `adversarial`, both to 1e-9
/// of the reference's diagonal (the message begins with `what`).
std::string surface_mismatch(const TetMesh& reference, const TetMesh& adversarial,
                             const std::string& what);

/// Sorted indices of the vertices on the boundary surface.
std::vector<int> boundary_vertices(const TetMesh& mesh);

/// #T flags: element has a boundary face (or, with by_vertex, any boundary vertex).
std::vector<char> boundary_elements(const TetMesh& mesh, bool by_vertex = false);

/// #T by 4 face neighbours: entry (e, k) is the element sharing the face opposite local vertex k
/// of element e, or -1 on the boundary. Throws rbaa::InputError if a face is shared by more
/// than two tets (non-manifold).
Tets face_adjacency(const TetMesh& mesh);

/// Throws rbaa::InputError naming `source` and the face unless every face is shared by at most
/// two tets lying on its opposite sides (tets positively oriented): a repeated tet, or two on one
/// side of a face, overlap and would count their volume twice.
void validate_tet_faces(const TetMesh& mesh, const std::string& source);

/// Face-connected component label of every flagged element (-1 for the others), numbered in
/// order of their smallest element, given the face adjacency `adj`; returns how many there are.
int label_components(const Tets& adj, const std::vector<char>& flags, std::vector<int>& label);

/// Number of face-connected components among the elements with flag set (all if empty).
int count_components(const TetMesh& mesh, const std::vector<char>& flags = {});

}  // namespace rbaa
