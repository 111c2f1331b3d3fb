#pragma once
// The reference object of a scene, meshed (or read) and placed at its initial pose.

#include <Eigen/Core>
#include <string>

#include "rbaa/mesh/tet_mesh.hpp"
#include "rbaa/scene/scene.hpp"

namespace rbaa {

/// Builds the scene's tet mesh (CGAL for shapes and surfaces, deterministic; or reads the mesh
/// file), rotates it about its centre of mass by the scene's rotation and moves the centre of
/// mass (at uniform density) to scene.position. Throws rbaa::InputError if the placed object
/// intersects or touches an obstacle (some vertex with normal . x - offset <= d_hat).
/// This is the reference placement attacks design on.
TetMesh make_scene_mesh(const Scene& scene);

/// A further body's mesh (scene.bodies[i]) placed like the object: rotated about its volume
/// centroid, which is then at body.position. Throws rbaa::InputError naming the body if it
/// touches an obstacle.
TetMesh make_body_mesh(const Scene& scene, const BodySpec& body);

/// A copy of the object at a further body's pose (body.object_copy): the run's placed object
/// mesh, turned from the object's rotation to the body's (R_body R_object^T about
/// scene.position) and moved from scene.position to body.position, so that the object's centre
/// of mass (at scene.position in every run: make_scene_mesh, place_centre_of_mass) lands at the
/// body's position. Equal rotations only translate. Throws rbaa::InputError naming the body if it
/// touches an obstacle.
TetMesh make_copy_mesh(const Scene& scene, const BodySpec& body, const TetMesh& object_mesh);

/// Translates a placed mesh so that its centre of mass under the per-element density (#T,
/// kg/m^3, rho alpha: element masses rho alpha V) is at scene.position, which is what
/// object.position means. make_scene_mesh puts the volume centroid there, which is the centre of
/// mass only at uniform density; runs of a given non-uniform material (a materials file, an
/// adversarial .msh, an exported object's kept elements) call this. A centre of mass already
/// within 1e-10 of the radius of gyration of the position (make_scene_mesh's at uniform density,
/// an attack's moment-matched object) returns the mesh unchanged, bit for bit.
/// Throws rbaa::InputError naming `source` if the moved object touches an obstacle.
/// An attack's object as its file gives it, turned into `scene`'s pose when its attack config did
/// not turn it and `scene` does (a demonstration that starts its object turned, such as the cube
/// stack's striker): when `scene` turns its object and the given mesh's bounding box differs in
/// size (beyond 1e-9 of the reference's diagonal) from `reference`'s (the scene's placed reference
/// mesh) but matches it once turned by scene's rotation about its middle, the turned mesh; else
/// the mesh unchanged. Translations are left to the caller (place_centre_of_mass).
TetMesh turn_into_scene_pose(const Scene& scene, const TetMesh& reference, const TetMesh& given);

/// An attack's object as its file gives it, in `scene`'s pose before placement, checked against
/// `reference` (the scene's placed reference mesh): turned (turn_into_scene_pose) and, in a
/// demonstration (which starts its object elsewhere than the attack did: the ball from its
/// release, not from just before the backboard), moved so that its bounding box's middle is the
/// reference's. Throws rbaa::InputError naming `source` unless its outer surface is then the
/// reference's (surface_mismatch). rbaa evaluate and rbaa export take an adversarial object so.
TetMesh adversarial_in_scene(const Scene& scene, const TetMesh& reference, const TetMesh& given,
                             const std::string& source);

TetMesh place_centre_of_mass(const Scene& scene, TetMesh mesh, const Eigen::VectorXd& density,
                             const std::string& source);

/// The object mesh as produced by the mesh source, before placement (centred as generated).
TetMesh make_source_mesh(const MeshSource& source, const std::string& scene_source);

}  // namespace rbaa
