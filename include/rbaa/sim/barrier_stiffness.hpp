#pragma once
// The barrier stiffness kappa by SPEC section 2's energy rule. Every scene starts out of contact,
// where IPC's gradient balance is undefined; instead kappa is chosen so that one surface vertex
// carrying the body's whole kinetic energy would stop at d = 1e-3 d_hat:
//
//   kappa = (1/2) m0 v^2 / b(1e-3 d_hat),  v = max(|v0|, sqrt(2 |g| H)),
//
// H the height of the centre of mass above the lowest obstacle that faces up against gravity (for
// a mesh obstacle: its lowest vertex).
// kappa (J per unit of b) multiplies b inside the h^2-weighted potential, so it does not change
// with h. Computed once from the reference scene and frozen for every run of an attack.

#include <Eigen/Core>

#include <vector>

#include "rbaa/sim/world.hpp"

namespace rbaa {

/// (1/2) m0 v^2 / b(1e-3 d_hat) for mass m0 (kg), speed v (m/s), activation distance d_hat (m).
double barrier_stiffness_from_energy(double m0, double speed, double d_hat);

/// The speed the rule uses: max(speed, sqrt(2 |g| H)) for a body whose centre of mass is at
/// `centre_of_mass` (speed: its initial speed).
double barrier_design_speed(double speed, const Eigen::Vector3d& gravity,
                            const std::vector<Plane>& planes,
                            const std::vector<ObstacleMesh>& obstacle_meshes,
                            const Eigen::Vector3d& centre_of_mass);

}  // namespace rbaa
