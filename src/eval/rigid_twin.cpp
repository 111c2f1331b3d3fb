#include "rbaa/eval/rigid_twin.hpp"

#include <sstream>
#include <string>

#include "rbaa/error.hpp"

namespace rbaa {

RigidWorld rigid_world(const Scene& scene, std::vector<RigidBody> bodies) {
  RigidWorld world;
  world.bodies = std::move(bodies);
  world.planes = scene.planes;
  world.obstacle_meshes = scene.obstacle_meshes;
  // The planes and meshes carry their own coefficients (contact.friction's where they set none).
  world.body_friction = scene.friction;
  world.pair_friction = scene.friction_pairs;
  world.gravity = scene.gravity;
  world.time_step = scene.time_step;
  return world;
}

std::vector<RigidState> simulate_rigid(const RigidMassProperties& mass, const RigidShape& shape,
                                       const Scene& scene, const RigidSettings& settings,
                                       double duration, const std::vector<RigidBody>& further,
                                       int body) {
  if (body < 0 || body > static_cast<int>(further.size())) {
    throw InputError(scene.source + ": the rigid twin has no body " + std::to_string(body) +
                     " (the object and " + std::to_string(further.size()) + " further)");
  }
  return simulate_rigid_bodies(mass, shape, scene, settings, duration, further)[body];
}

std::vector<std::vector<RigidState>> simulate_rigid_bodies(
    const RigidMassProperties& mass, const RigidShape& shape, const Scene& scene,
    const RigidSettings& settings, double duration, const std::vector<RigidBody>& further,
    std::vector<RigidTouch>* touches) {
  // A margin beyond d_hat would let the twin bounce off a gap the deformable body never feels.
  if (settings.margin > scene.d_hat) {
    std::ostringstream msg;
    msg << scene.source << ": the rigid twin's margin " << settings.margin
        << " m exceeds contact.d_hat = " << scene.d_hat << " m";
    throw InputError(msg.str());
  }
  std::vector<RigidBody> bodies;
  RigidBody object;
  object.name = scene.object_name;
  object.mass = mass;
  object.shape = shape;
  object.velocity = scene.velocity;
  object.angular_velocity = scene.angular_velocity;
  if (scene.driven.enabled) {
    // A driven object (the bat) is a kinematic twin carried by its drive (rigid_bodies does the
    // same for further bodies).
    object.kinematic = true;
    object.drive = scene.driven.motion;
    object.velocity = object.drive.point_velocity(mass.centre, 0.0);
    object.angular_velocity = object.drive.angular_speed(0.0) * object.drive.axis;
  }
  bodies.push_back(std::move(object));
  bodies.insert(bodies.end(), further.begin(), further.end());
  return simulate_rigid(rigid_world(scene, std::move(bodies)), settings, duration, touches);
}

}  // namespace rbaa
