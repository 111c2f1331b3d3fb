#pragma once
// The reference object of a scene, meshed (or read) and placed at its initial pose.

#include "rbaa/mesh/tet_mesh.hpp"
#include "rbaa/scene/scene.hpp"

namespace rbaa {

/// Builds the scene's tet mesh (CGAL for shapes and surfaces, deterministic; or reads the mesh
/// file), rotates it about its centre of mass by the scene's rotation and moves the centre of
/// mass (at uniform density) to scene.position. Throws rbaa::InputError if the placed object
/// intersects or touches an obstacle (some vertex with normal . x - offset <= d_hat).
TetMesh make_scene_mesh(const Scene& scene);

/// The object mesh as produced by the mesh source, before placement (centred as generated).
TetMesh make_source_mesh(const MeshSource& source, const std::string& scene_source);

}  // namespace rbaa
