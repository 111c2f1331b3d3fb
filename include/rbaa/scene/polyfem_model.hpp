#pragma once
// A scene as PolyFEM sees it (io/polyfem_scene.hpp): the config's object (the reference, or an
// adversarial .msh with its void elements cut out) and its further bodies, obstacles, gravity,
// time stepping and contact, turned into the physical model the exporter writes.

#include <string>

#include "rbaa/scene/polyfem_scene.hpp"
#include "rbaa/material/material_field.hpp"
#include "rbaa/mesh/tet_mesh.hpp"
#include "rbaa/scene/scene.hpp"

namespace rbaa {

/// The object to export, placed at the scene's initial pose.
struct ExportObject {
  TetMesh mesh;
  MaterialField materials;      ///< #T; alpha in [round_threshold, 1]
  int removed_elements = 0;     ///< void elements cut out (alpha < round_threshold)
  int removed_vertices = 0;     ///< vertices only they used
  int fractional_elements = 0;  ///< kept elements with alpha < 1 (exported as alpha^3 Y, alpha rho)
};

/// The scene's reference object (make_scene_mesh) with the uniform reference material.
ExportObject reference_export_object(const Scene& scene);

/// An adversarial object from an rbaa .msh (the one `rbaa attack` writes, or any with element
/// data Y, nu, rho and optionally alpha, default 1): elements with alpha below the attack's
/// rounding threshold (attack.round_threshold, default 0.5; a rounded object marks void as 0)
/// are removed with the vertices only they used; then the mesh is moved so that its centre of
/// mass (element masses rho alpha V) is at object.position, as `rbaa evaluate` does. Throws
/// InputError naming the file for a missing field, an alpha outside [0, 1], an invalid material
/// on a kept element, or no element left.
ExportObject adversarial_export_object(const Scene& scene, const std::string& path);

/// The PolyFEM model of the scene with `object` in the object's place: the bodies (make_world),
/// stacked materials with occupancy folded in (E = alpha^3 Y, rho = alpha rho: what rbaa
/// simulates for a partly occupied element), the planes and obstacle meshes, gravity, h, T, the
/// integrator, mass model, d_hat and friction. PolyFEM has one friction coefficient for every
/// contact: throws InputError naming two surfaces whose coefficients differ.
PolyfemScene polyfem_model(const Scene& scene, const ExportObject& object);

}  // namespace rbaa
