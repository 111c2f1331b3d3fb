#pragma once
// TetGen .node/.ele file pairs. TetGen numbers from 0 or 1 depending on its input (-z switch),
// so the reader takes the base from the first node index.

#include <string>

#include "rbaa/mesh/tet_mesh.hpp"

namespace rbaa {

/// The base name of a TetGen pair: "a/mesh.1.node" and "a/mesh.1.ele" give "a/mesh.1"; any other
/// name is returned unchanged.
std::string tetgen_base_name(const std::string& path);

/// Reads BASE.node and BASE.ele, where `path` is either file or the base name. Indexing is 0- or
/// 1-based as the first node index says; attributes and boundary markers are ignored; of 10-node
/// tets the 4 corners are kept. Vertices no tet uses are dropped. When every tet is negatively
/// oriented the file follows the opposite convention and all are flipped (swap of the last two).
/// Throws InputError "FILE:LINE: ..." on malformed input.
TetMesh read_tetgen(const std::string& path);

/// Writes BASE.node and BASE.ele (1-based, no attributes or markers), each atomically, where
/// `path` is either file or the base name. #V by 3 coordinates are written exactly.
void write_tetgen(const std::string& path, const TetMesh& mesh);

}  // namespace rbaa
