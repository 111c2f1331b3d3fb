#pragma once
// Driven (Dirichlet) bodies for the simulator's and the adjoint's tests, free of gravity:
// * a coarse bar along +x whose x = 0 end face is driven about the z axis through that face's
//   centre (a bat swung by its knob, in miniature), alone or sweeping into a free ball;
// * a fully driven paddle translating into a free ball.

#include <vector>

#include "mesh_fixtures.hpp"
#include "rbaa/material/material_field.hpp"
#include "rbaa/sim/simulator.hpp"

namespace rbaa::test {

struct DrivenScene {
  TetMesh mesh;
  std::vector<Body> bodies;  ///< bodies[0] is driven; bodies[1], if any, the free ball
  SimulationSettings settings;
  MaterialField materials;
  Eigen::VectorXd q0, v0;

  const Body& driven() const { return bodies.front(); }
};

/// Vertices of `m` (ids offset by `first`) whose x is the smallest.
inline std::vector<int> min_x_vertices(const TetMesh& m, int first = 0) {
  std::vector<int> ids;
  const double x = m.V.col(0).minCoeff();
  for (int v = 0; v < m.num_vertices(); ++v) {
    if (m.V(v, 0) <= x + 1e-12) ids.push_back(first + v);
  }
  return ids;
}

// Stacks `driven` (body 0, its motion `drive`, its driven vertices `ids`) and, when ball_radius >
// 0, a ball of that radius at `ball_centre` (body 1, at rest).
inline DrivenScene stack(const TetMesh& driven, std::vector<int> ids, const PrescribedMotion& drive,
                         double ball_radius, const Eigen::Vector3d& ball_centre) {
  DrivenScene s;
  Body a;
  a.name = "'striker'";
  a.vertex_end = driven.num_vertices();
  a.element_end = driven.num_tets();
  a.centre = driven.V.colwise().mean().transpose();
  a.driven_vertices = std::move(ids);
  a.drive = drive;
  a.velocity = drive.point_velocity(a.centre, 0.0);
  a.angular_velocity = drive.angular_speed(0.0) * drive.axis;
  s.bodies.push_back(a);
  s.mesh = driven;
  if (ball_radius > 0) {
    const TetMesh b = ball_mesh(ball_radius, 3, ball_centre);
    s.mesh.V.resize(driven.num_vertices() + b.num_vertices(), 3);
    s.mesh.V << driven.V, b.V;
    s.mesh.T.resize(driven.num_tets() + b.num_tets(), 4);
    s.mesh.T << driven.T, (b.T.array() + driven.num_vertices()).matrix();
    Body ball;
    ball.name = "'ball'";
    ball.vertex_begin = a.vertex_end;
    ball.vertex_end = s.mesh.num_vertices();
    ball.element_begin = a.element_end;
    ball.element_end = s.mesh.num_tets();
    ball.centre = ball_centre;
    s.bodies.push_back(ball);
  }
  s.settings.gravity.setZero();
  s.settings.newton_tolerance = 1e-12;
  s.settings.bodies = s.bodies;
  s.materials = MaterialField::uniform(s.mesh.num_tets(), 1e8, 0.3, 1000);
  s.q0 = positions(s.mesh);
  s.v0 = initial_velocities(s.q0, s.bodies);
  return s;
}

/// A bar of n x 1 x 1 cubes of side 0.02 from the origin along +x, its x = 0 face (4 vertices)
/// driven about the z axis through (0, 0.01, 0.01) at omega (rad/s), or, with spin_up > 0, at a
/// speed rising linearly from 0 to omega over spin_up seconds (the bar starting at rest). With
/// ball_radius > 0 a free ball waits 5 mm ahead of the bar's leading (+y) face at x = 0.09. With
/// refine = 2 each cube is split into 8 (the bar then has interior elements, which alpha needs).
inline DrivenScene driven_bar(int n, double omega, double spin_up = 0, double ball_radius = 0,
                              int refine = 1) {
  const TetMesh bar = box_mesh(n * refine, refine, refine, 0.02 / refine);
  PrescribedMotion drive;
  drive.axis = Eigen::Vector3d::UnitZ();
  drive.centre = Eigen::Vector3d(0, 0.01, 0.01);
  if (spin_up > 0) {
    drive.angular_velocity_table = {Eigen::Vector2d(0, 0), Eigen::Vector2d(spin_up, omega)};
  } else {
    drive.angular_velocity = omega;
  }
  DrivenScene s = stack(bar, min_x_vertices(bar), drive, ball_radius,
                        Eigen::Vector3d(0.09, 0.02 + 0.005 + ball_radius, 0.01));
  s.settings.time_step = 1e-3;
  s.settings.num_steps = 30;
  s.settings.d_hat = 2e-3;
  s.settings.kappa = 1e3;
  return s;
}

/// A paddle of 1 x 2 x 2 cubes of side 0.02, every vertex driven at `speed` (m/s) along +x, and a
/// free ball of radius 0.025 at rest 5 mm ahead of it.
inline DrivenScene driven_paddle(double speed = 1.0) {
  const TetMesh paddle = box_mesh(1, 2, 2, 0.02);
  std::vector<int> all(paddle.num_vertices());
  for (int v = 0; v < paddle.num_vertices(); ++v) all[v] = v;
  PrescribedMotion drive;
  drive.velocity = Eigen::Vector3d(speed, 0, 0);
  DrivenScene s =
      stack(paddle, all, drive, 0.025, Eigen::Vector3d(0.02 + 0.005 + 0.025, 0.02, 0.02));
  s.settings.time_step = 1e-3;
  s.settings.num_steps = 40;
  s.settings.d_hat = 2e-3;
  s.settings.kappa = 1e3;
  return s;
}

}  // namespace rbaa::test
