#pragma once
// A rigid object among half-space obstacles in Bullet (double precision): the rigid-body
// simulator every adversarial object must fool. Bullet types stay inside src/rigid.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <vector>

#include "rbaa/rigid/rigid_body.hpp"
#include "rbaa/scene/scene.hpp"

namespace rbaa {

struct RigidSettings {
  double internal_step = 1e-3;  ///< Bullet's fixed step (s); outputs are sampled at the scene's h
  double restitution = 1.0;     ///< body restitution; Bullet multiplies it with the plane's
  /// Restitution of each plane (index as in the scene); missing entries are 1.
  std::vector<double> plane_restitution;
  double friction = 0.0;
  double margin = 1e-4;         ///< collision margin (m), at most d_hat (Bullet's 0.04 m default
                                ///< is nearly the cube's half size)
  /// Split impulse with a generous penetration threshold: Bullet's default Baumgarte correction
  /// (erp 0.2) pushes bodies apart with extra energy and spoils the restitution.
  bool split_impulse = true;
  int solver_iterations = 200;  ///< projected Gauss-Seidel sweeps per step (Bullet default 10)
};

/// State of the object at one output time, in the mesh frame: the mesh point x0 (rest mesh
/// coordinates) is at position + orientation (x0 - rest centre).
struct RigidState {
  double time = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< centre of mass (m)
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< mesh frame rotation
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();          ///< m/s
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  ///< rad/s (world)
};

/// Simulates the rigid object from the scene's initial state (centre of mass at
/// scene.position, velocity, angular velocity; `rest_mesh` is the placed initial mesh, so its
/// orientation is the identity) among the scene's planes, with the scene's gravity, for
/// `duration` seconds; returns states at t = 0, h, 2h, ... (scene.time_step).
std::vector<RigidState> simulate_rigid(const RigidMassProperties& mass, const RigidShape& shape,
                                       const Scene& scene, const RigidSettings& settings,
                                       double duration);

}  // namespace rbaa
