#include "rbaa/sim/barrier_stiffness.hpp"

#include <algorithm>
#include <cmath>

#include "rbaa/contact/barrier.hpp"

namespace rbaa {

double barrier_stiffness_from_energy(double m0, double speed, double d_hat) {
  return 0.5 * m0 * speed * speed / contact::Barrier(d_hat).value(1e-3 * d_hat);
}

double barrier_design_speed(double speed, const Eigen::Vector3d& gravity,
                            const std::vector<Plane>& planes,
                            const std::vector<ObstacleMesh>& obstacle_meshes,
                            const Eigen::Vector3d& centre_of_mass) {
  const double g = gravity.norm();
  if (g > 0) {
    const Eigen::Vector3d up = -gravity / g;
    double height = 0;
    for (const Plane& plane : planes) {
      const double facing = plane.normal.dot(up);
      if (facing <= 1e-12) continue;  // walls and ceilings do not end a fall
      height = std::max(height, (plane.normal.dot(centre_of_mass) - plane.offset) / facing);
    }
    // A mesh obstacle: the fall down to its lowest vertex (it may be a floor, a bin, a rim).
    for (const ObstacleMesh& mesh : obstacle_meshes) {
      if (mesh.V.rows() == 0) continue;
      const double lowest = (mesh.V * up).minCoeff();
      height = std::max(height, up.dot(centre_of_mass) - lowest);
    }
    speed = std::max(speed, std::sqrt(2.0 * g * height));
  }
  return speed;
}

}  // namespace rbaa
