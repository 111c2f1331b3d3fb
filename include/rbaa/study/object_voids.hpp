#pragma once
// What the survival check can tell of an adversarial object's voids from its file and the config's
// mesh, before carrying its materials to a finer mesh (which would fill its holes). An attack
// writes its object without the elements it emptied (alpha = 0 cut out, the rest rounded to 1), so
// a void shows as alpha < 1 (a continuous design) or as elements missing from the mesh the attack
// ran on. When that mesh is the config's, the missing elements are counted; when the attack ran
// on another mesh (another mesh.target_tets), its holes show as inner surfaces: pieces of the
// boundary surface beyond the config mesh's (an attack keeps its boundary elements, so a hole
// touches the outer surface at most at an edge or a vertex).

#include <string>

#include "rbaa/material/material_field.hpp"
#include "rbaa/mesh/tet_mesh.hpp"

namespace rbaa {

struct ObjectVoids {
  int partial_elements = 0;     ///< elements with alpha < 1
  bool part_of_config = false;  ///< every tet of the object is one of the config mesh's
  int removed_elements = 0;     ///< the config mesh's tets missing from it (part_of_config only)
  int inner_surfaces = 0;       ///< pieces of its boundary surface beyond the config mesh's

  bool any() const { return partial_elements > 0 || removed_elements > 0 || inner_surfaces > 0; }
  /// e.g. "12 elements with alpha < 1, 340 elements of the config's mesh removed".
  std::string describe() const;
};

/// `object` (#T tets) with its `materials` (#T) against the scene's `config_mesh`, both placed as
/// the scene places the object.
ObjectVoids find_object_voids(const TetMesh& object, const MaterialField& materials,
                              const TetMesh& config_mesh);

/// Whether every tet of `part` is a tet of `whole`, vertices matched by their exact positions (an
/// attack's object is its mesh's vertices as written, to the last digit).
bool is_part_of(const TetMesh& part, const TetMesh& whole);

/// Pieces of the boundary surface: boundary triangles joined across the edges that exactly two
/// of them share. A closed manifold surface is one piece; each inner cavity is one more, also
/// where it touches another piece at an edge (four triangles there) or a vertex.
int boundary_surface_pieces(const TetMesh& mesh);

}  // namespace rbaa
