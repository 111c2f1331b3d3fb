#pragma once
// What scene/ derives from a config for the simulator: its settings and its barrier stiffness.

#include <string>
#include <vector>

#include "rbaa/material/design_space.hpp"
#include "rbaa/material/material_field.hpp"
#include "rbaa/mesh/tet_mesh.hpp"
#include "rbaa/scene/scene.hpp"
#include "rbaa/sim/simulator.hpp"

namespace rbaa {

/// The steps of h a run of the scene takes: round(T / h) (T need not be a whole number of h).
int num_steps(const Scene& scene);

/// Settings of a scene: its h, steps = round(duration / h), integrator, mass model, gravity,
/// planes, obstacle meshes, friction, d_hat and Newton settings, with the given (frozen) kappa.
/// (The bodies' ranges come from the SceneWorld.)
SimulationSettings simulation_settings(const Scene& scene, double kappa);

/// The coefficients between the scene's bodies (the object, then scene.bodies): contact.friction
/// for every pair, overridden by contact.pairs; the diagonal 0. Empty without further bodies.
Eigen::MatrixXd body_friction(const Scene& scene);

/// scene.kappa if positive, else the energy rule (sim/barrier_stiffness.hpp) for the scene's
/// reference object (`placed`: the placed reference mesh, density scene.reference_rho). Throws
/// rbaa::InputError if the rule has nothing to go on (no speed and no fall) and the scene sets no
/// kappa.
double scene_barrier_stiffness(const Scene& scene, const TetMesh& placed);

/// Every body of a scene in one mesh: the object first, then scene.bodies in order.
struct SceneWorld {
  TetMesh mesh;              ///< the placed rest meshes, stacked
  std::vector<Body> bodies;  ///< ranges, centres (centres of mass) and initial motions
  /// The materials of the elements after the object's (the further bodies'), fixed; a copy of
  /// the object's elements hold the reference material here, replaced by materials().
  MaterialField fixed_materials;
  /// The indices (into bodies) of the copies of the object (BodySpec::object_copy), ascending.
  std::vector<int> copies;

  /// The stacked field: the object's materials, then the fixed ones, each copy of the object
  /// with the object's. Throws rbaa::InputError naming `source` when `object` does not fit the
  /// object's mesh.
  MaterialField materials(const MaterialField& object, const std::string& source = "materials") const;
  /// The object's rows of a stacked per-element vector (e.g. a material gradient).
  Eigen::VectorXd object_part(const Eigen::VectorXd& stacked) const {
    return stacked.head(bodies.front().num_elements());
  }
};

/// The world of a scene whose object is `object_mesh` (placed: make_scene_mesh, or moved by
/// place_centre_of_mass) and centred at scene.position: meshes and places every further body
/// (make_body_mesh), with its materials file or the reference material, its centre of mass moved
/// to its position. A body with a `driven` key gets its driven vertices (DriveSpec's selection on
/// its placed mesh) and its drive, and starts with the drive's rigid motion. Throws
/// rbaa::InputError naming both bodies when two start closer than d_hat, and naming the key when
/// a drive's vertex list or count does not fit its body. A body marked object_copy is instead
/// the object's mesh at its pose (make_copy_mesh), its elements the object's materials.
SceneWorld make_world(const Scene& scene, const TetMesh& object_mesh);

/// The scene with each body of demonstration.object_copies marked object_copy, so that make_world
/// (and so run_simulation, polyfem_model) makes it a copy of whatever object and materials a run
/// has: `rbaa evaluate` and `rbaa export` use it; the attack does not (its design is the
/// object's elements alone). Without object_copies, the scene itself.
Scene with_object_copies(const Scene& scene);

/// The bodies a simulation of the world needs in its settings: all of them when there are several
/// or one is driven, else none (the whole mesh is the one body).
std::vector<Body> simulated_bodies(const SceneWorld& world);

/// The same physical scene with body `name` in the object's place: the object's keys (mesh,
/// pose, motion, drive) and bodies[i]'s trade places, object_name becomes `name` and the old
/// object a body named after the old object_name; contact.pairs follow their bodies (names such as
/// evaluation.body's need nothing: an empty one means the object, now body `name`), and an automatic kappa is frozen at the original scene's (the energy rule reads the
/// object's speed and mass, and an attack on body i ran with it). What reads the object (the
/// verbs that place an adversarial object, the rigid twin, the traces) then reads body `name`.
/// `name` == scene.object_name returns the scene. Throws rbaa::InputError naming the scene when
/// there is no such body, when it has a materials file (the object's materials are a run's), or
/// when the scene has demonstration.object_copies (copies of which object?).
Scene swap_object(const Scene& scene, const std::string& name);

/// The design space a scene's attack section asks for: ranges, fields, initial values, alpha0,
/// seed, perturbation, boundary rule.
DesignSpaceOptions design_space_options(const Scene& scene);

}  // namespace rbaa
