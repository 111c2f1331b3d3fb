#include "rbaa/sim/barrier_stiffness.hpp"

#include <algorithm>
#include <cmath>

#include "rbaa/error.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/sim/barrier.hpp"

namespace rbaa {

double barrier_stiffness_from_energy(double m0, double speed, double d_hat) {
  return 0.5 * m0 * speed * speed / Barrier(d_hat).value(1e-3 * d_hat);
}

double barrier_design_speed(const Scene& scene, const Eigen::Vector3d& centre_of_mass) {
  double speed = scene.velocity.norm();
  const double g = scene.gravity.norm();
  if (g > 0) {
    const Eigen::Vector3d up = -scene.gravity / g;
    double height = 0;
    for (const Plane& plane : scene.planes) {
      const double facing = plane.normal.dot(up);
      if (facing <= 1e-12) continue;  // walls and ceilings do not end a fall
      height = std::max(height, (plane.normal.dot(centre_of_mass) - plane.offset) / facing);
    }
    // A mesh obstacle: the fall down to its lowest vertex (it may be a floor, a bin, a rim).
    for (const ObstacleMesh& mesh : scene.obstacle_meshes) {
      if (mesh.V.rows() == 0) continue;
      const double lowest = (mesh.V * up).minCoeff();
      height = std::max(height, up.dot(centre_of_mass) - lowest);
    }
    speed = std::max(speed, std::sqrt(2.0 * g * height));
  }
  return speed;
}

double scene_barrier_stiffness(const Scene& scene, const TetMesh& placed) {
  if (scene.kappa > 0) return scene.kappa;
  const Moments m = compute_moments(placed, scene.reference_rho);
  const double speed = barrier_design_speed(scene, m.centre_of_mass());
  if (!(speed > 0)) {
    throw InputError(scene.source + ": cannot choose the barrier stiffness kappa by the energy "
                     "rule: the object neither moves nor falls onto an obstacle; set 'kappa'");
  }
  return barrier_stiffness_from_energy(m.m0, speed, scene.d_hat);
}

}  // namespace rbaa
