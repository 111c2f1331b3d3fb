#pragma once
// Rigid-body observables of a deformable trajectory: centre of mass, momenta, the best-fit
// rotation from the rest pose, and the restitution of every bounce.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

#include "rbaa/scene/scene.hpp"
#include "rbaa/sim/trajectory.hpp"

namespace rbaa {

/// sum_i m_i x_i / sum_i m_i with the vertex masses (#V): exact for the consistent mass too.
Eigen::Vector3d centre_of_mass(const Eigen::VectorXd& q, const Eigen::VectorXd& vertex_masses);

/// Linear momentum sum_i (M v)_i, given the stacked product Mv (3 #V).
Eigen::Vector3d linear_momentum(const Eigen::VectorXd& Mv);

/// Angular momentum about the origin sum_i x_i x (M v)_i.
Eigen::Vector3d angular_momentum(const Eigen::VectorXd& q, const Eigen::VectorXd& Mv);

/// The rotation R minimising sum_i m_i |R (X_i - X_c) - (x_i - x_c)|^2 (mass-weighted Kabsch,
/// centred at the respective centres of mass), as a unit quaternion with w >= 0.
Eigen::Quaterniond best_fit_rotation(const Eigen::VectorXd& rest, const Eigen::VectorXd& q,
                                     const Eigen::VectorXd& vertex_masses);

/// One contact episode with one plane: the run of steps in which some surface vertex is within
/// d_hat of it. Normal velocities are the centre of mass's along the plane normal, at the last
/// step before and the first step after the episode.
struct Bounce {
  int plane = 0;
  int first_step = 0;      ///< first position index in contact
  int last_step = 0;       ///< last position index in contact
  double normal_velocity_in = 0;
  double normal_velocity_out = 0;
  double restitution = 0;  ///< -out / in; NaN while the episode is not over at the end
  bool complete = false;
};

/// Bounces of a trajectory. `distances[k][p]`: minimum distance of the surface to plane p at
/// position k; `com_velocity[k]`: the centre of mass velocity at position k. The outgoing
/// velocity is read `settle_steps` steps after the episode (fewer if another contact starts),
/// minus the gravity of those steps: BDF-2's velocity needs a few steps to settle after a bounce.
std::vector<Bounce> find_bounces(const std::vector<std::vector<double>>& distances,
                                 const std::vector<Eigen::Vector3d>& com_velocity,
                                 const std::vector<Plane>& planes, double d_hat,
                                 const Eigen::Vector3d& gravity, double time_step,
                                 int settle_steps = 5);

}  // namespace rbaa
