#include "rbaa/scene/scene_world.hpp"

#include <cmath>

#include "rbaa/error.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/sim/barrier_stiffness.hpp"

namespace rbaa {

SimulationSettings simulation_settings(const Scene& scene, double kappa) {
  SimulationSettings s;
  s.time_step = scene.time_step;
  s.num_steps = static_cast<int>(std::lround(scene.duration / scene.time_step));
  s.integrator = scene.integrator;
  s.mass = scene.mass;
  s.gravity = scene.gravity;
  s.planes = scene.planes;
  s.obstacle_meshes = scene.obstacle_meshes;
  s.d_hat = scene.d_hat;
  s.kappa = kappa;
  s.newton_tolerance = scene.newton_tolerance;
  s.newton_max_iterations = scene.newton_max_iterations;
  s.rigid_predictor = scene.newton_rigid_predictor;
  return s;
}

double scene_barrier_stiffness(const Scene& scene, const TetMesh& placed) {
  if (scene.kappa > 0) return scene.kappa;
  const Moments m = compute_moments(placed, scene.reference_rho);
  const double speed = barrier_design_speed(scene.velocity.norm(), scene.gravity, scene.planes,
                                            scene.obstacle_meshes, m.centre_of_mass());
  if (!(speed > 0)) {
    throw InputError(scene.source + ": cannot choose the barrier stiffness kappa by the energy "
                     "rule: the object neither moves nor falls onto an obstacle; set 'kappa'");
  }
  return barrier_stiffness_from_energy(m.m0, speed, scene.d_hat);
}

}  // namespace rbaa
