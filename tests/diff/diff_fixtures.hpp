#pragma once
// A small differentiable scene for the adjoint tests: a coarse ball thrown at the plane z = 0
// with a barrier soft enough that contact lasts several steps.

#include <memory>

#include "rbaa/diff/trajectory_gradient.hpp"
#include "rbaa/sim/simulator.hpp"
#include "sim/mesh_fixtures.hpp"

namespace rbaa::test {

struct ThrownBall {
  TetMesh mesh;
  SimulationSettings settings;
  Eigen::VectorXd q0, v0;
};

inline ThrownBall thrown_ball(Integrator integrator, int n = 3) {
  ThrownBall b;
  b.mesh = lifted(ball_mesh(0.1, n, Eigen::Vector3d(0.05, -0.02, 0.0)), 0.004);
  b.settings.time_step = 2e-3;
  b.settings.num_steps = 12;
  b.settings.integrator = integrator;
  b.settings.planes = {Plane{Eigen::Vector3d::UnitZ(), 0.0}};
  b.settings.d_hat = 3e-3;
  b.settings.kappa = 2e2;
  b.settings.newton_tolerance = 1e-12;
  b.q0 = positions(b.mesh);
  const Eigen::Vector3d c = b.mesh.V.colwise().mean().transpose();
  b.v0 = rigid_velocities(b.q0, c, Eigen::Vector3d(0.4, 0.1, -2.0), Eigen::Vector3d(3.0, -2.0, 1.0));
  return b;
}

}  // namespace rbaa::test
