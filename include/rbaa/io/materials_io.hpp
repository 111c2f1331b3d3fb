#pragma once
// Per-element materials on disk: a CSV with one row per tet, or the element data of a .msh
// written by rbaa (the attack's adversarial.msh), so the result of an attack can be fed back to
// `rbaa simulate --materials=FILE`.

#include <string>

#include "rbaa/io/tet_mesh_file.hpp"
#include "rbaa/material/material_field.hpp"

namespace rbaa {

/// Reads a material field for a mesh of `num_tets` tets from a .csv (header naming columns Y,
/// nu, rho and optionally alpha, in any order, other columns ignored; one row per tet in tet
/// order; alpha defaults to 1) or a .msh (element data fields Y, nu, rho, optional alpha). Then
/// validates it (validate_material_field). Throws InputError naming the file (and line for CSV)
/// on a missing column, a wrong number of rows, a non-numeric or non-finite value.
MaterialField read_materials(const std::string& path, int num_tets);

/// The same for the tets of `mesh`; a .msh must also carry `mesh`'s own tets (the same vertex
/// indices, tet by tet): another mesh of the same count is refused, naming the first tet that
/// differs. (Its vertex positions may differ: a scene places its mesh.)
MaterialField read_materials(const std::string& path, const TetMesh& mesh);

/// Writes `field` as CSV with header "Y,nu,rho,alpha" and one row per tet, atomically, exactly.
void write_materials_csv(const std::string& path, const MaterialField& field);

/// The field as element data {"Y", "nu", "rho", "alpha"} (#T each), ready for write_msh.
ElementData material_element_data(const MaterialField& field);

}  // namespace rbaa
