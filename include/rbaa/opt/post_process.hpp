#pragma once
// After the Adam loop (SPEC section 5): round the occupancy, make the occupied elements one
// face-connected body with the boundary shell, re-fit the densities to the reference moments,
// and cut the void elements out of the mesh for re-simulation.

#include <Eigen/Core>

#include <vector>

#include "rbaa/geometry/moments.hpp"
#include "rbaa/material/design_space.hpp"
#include "rbaa/material/material_field.hpp"
#include "rbaa/mesh/tet_mesh.hpp"
#include "rbaa/opt/density_refit.hpp"
#include "rbaa/opt/occupancy.hpp"

namespace rbaa {

/// A mesh with its void elements removed: elements with alpha = 0 go, and so do the vertices only
/// they used (they would carry no mass and no stiffness and make the system singular).
struct SolidObject {
  TetMesh mesh;
  MaterialField materials;
  std::vector<int> element_origin;  ///< #T_solid: index of each element in the full mesh
  std::vector<int> vertex_origin;   ///< #V_solid: index of each vertex in the full mesh
};

/// Keeps the elements with alpha > 0 (renumbering vertices in their original order).
SolidObject remove_void_elements(const TetMesh& mesh, const MaterialField& field);

struct PostProcessResult {
  MaterialField rounded;            ///< full mesh: alpha in {0, 1}, re-fitted rho
  SolidObject solid;                ///< the same without its void elements
  ConnectivityReport connectivity;
  DensityRefitResult refit;
  double void_fraction = 0;         ///< void volume / total volume
  double max_residual_before_refit = 0;  ///< max normalised moment residual after rounding
};

/// Rounds interior alpha at `threshold` (the design's held elements stay 1: boundary elements
/// and those of its solid vertices, DesignSpaceOptions::solid_vertices), repairs connectivity,
/// re-fits rho within the design's density range to `reference` (max normalised residual
/// <= 1e-10) and removes the void elements. Throws rbaa::InputError when the void fraction leaves
/// no density within bounds that can match m0.
PostProcessResult post_process(const TetMesh& mesh, const DesignSpace& design,
                               const MaterialField& continuous, const Moments& reference,
                               double threshold);

}  // namespace rbaa
