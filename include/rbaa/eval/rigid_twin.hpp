#pragma once
// The rigid twin of a scene, as `rbaa evaluate` runs it: rigid/ simulates a physical model
// (RigidWorld) and knows no config, so the scene's obstacles, gravity and time step are handed
// over here.

#include <vector>

#include "rbaa/rigid/rigid_simulation.hpp"
#include "rbaa/scene/scene.hpp"

namespace rbaa {

/// The scene's planes, obstacle meshes, gravity and time step around `bodies` (the object first,
/// then scene.bodies' twins), with the scene's Coulomb coefficients: each plane's and mesh's own,
/// contact.friction between bodies and contact.pairs for the pairs it names, as the deformable
/// simulator has them.
RigidWorld rigid_world(const Scene& scene, std::vector<RigidBody> bodies);

/// The object's states at t = 0, h, 2h, ... (h = scene.time_step) over `duration` seconds: the
/// object (mass properties and shape of its placed mesh, the scene's initial velocity and spin;
/// a driven object a kinematic body on its drive),
/// then `further` bodies, among the scene's obstacles. Throws rbaa::InputError when
/// settings.margin exceeds the scene's d_hat.
/// `body` picks whose states are returned: 0 the object, i > 0 further[i - 1].
std::vector<RigidState> simulate_rigid(const RigidMassProperties& mass, const RigidShape& shape,
                                       const Scene& scene, const RigidSettings& settings,
                                       double duration, const std::vector<RigidBody>& further = {},
                                       int body = 0);

/// The same run, every body's states: [0] the object, [i] further[i - 1]; with `touches`, the
/// pairs that touched (rigid_simulation.hpp; body indices as the states').
std::vector<std::vector<RigidState>> simulate_rigid_bodies(
    const RigidMassProperties& mass, const RigidShape& shape, const Scene& scene,
    const RigidSettings& settings, double duration, const std::vector<RigidBody>& further = {},
    std::vector<RigidTouch>* touches = nullptr);

}  // namespace rbaa
