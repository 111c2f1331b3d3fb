// Kinematic bodies in the rigid twin (issue 16's bat): a body on a PrescribedMotion is a Bullet
// kinematic object that follows the drive's pose exactly at every internal step, pushes a
// dynamic body along its face normal and is not pushed back; rigid_bodies makes a driven Body one.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>

#include "rbaa/rigid/rigid_body.hpp"
#include "rbaa/rigid/rigid_simulation.hpp"

namespace rbaa {
namespace {

// A 0.6 x 0.04 x 0.2 m paddle from the origin along +x (centre (0.3, 0, 0)), turning about the
// world z axis through the origin at omega rad/s; its +y face leads.
RigidBody paddle(double omega) {
  RigidBody p;
  p.name = "paddle";
  p.mass.mass = 2.0;
  p.mass.centre = Eigen::Vector3d(0.3, 0, 0);
  p.mass.principal_moments = Eigen::Vector3d(0.007, 0.067, 0.06);
  p.shape.kind = RigidShapeKind::kBox;
  p.shape.centre = p.mass.centre;
  p.shape.half_extents = Eigen::Vector3d(0.3, 0.02, 0.1);
  p.kinematic = true;
  p.drive.axis = Eigen::Vector3d::UnitZ();
  p.drive.angular_velocity = omega;
  p.velocity = p.drive.point_velocity(p.mass.centre, 0.0);
  p.angular_velocity = omega * p.drive.axis;
  return p;
}

// A ball of radius 0.05 m, 0.5 kg, at (0.45, 0.3, 0) coming at 3 m/s along -y.
RigidBody ball() {
  RigidBody b;
  b.name = "ball";
  b.mass.mass = 0.5;
  b.mass.centre = Eigen::Vector3d(0.45, 0.3, 0);
  b.mass.principal_moments = Eigen::Vector3d::Constant(0.4 * 0.5 * 0.05 * 0.05);
  b.shape.kind = RigidShapeKind::kSphere;
  b.shape.centre = b.mass.centre;
  b.shape.radius = 0.05;
  b.velocity = Eigen::Vector3d(0, -3, 0);
  return b;
}

TEST(RigidKinematic, APaddleFollowsItsDriveExactlyAndStrikesTheBallAlongItsFaceNormal) {
  const double omega = 5.0;
  RigidWorld world;
  world.bodies = {paddle(omega), ball()};
  world.gravity = Eigen::Vector3d::Zero();
  RigidSettings settings;
  settings.internal_step = 1e-3;
  world.time_step = settings.internal_step;  // a sample at every internal step
  const auto states = simulate_rigid(world, settings, 0.2);
  const RigidBody& p = world.bodies[0];

  // The paddle's pose and motion at every internal step: the drive's.
  double position_error = 0, angle_error = 0, velocity_error = 0;
  for (const RigidState& s : states[0]) {
    const Eigen::Quaterniond R(Eigen::AngleAxisd(omega * s.time, Eigen::Vector3d::UnitZ()));
    position_error =
        std::max(position_error, (s.position - p.drive.position(p.mass.centre, s.time)).norm());
    angle_error = std::max(angle_error, s.orientation.angularDistance(R));
    velocity_error = std::max(velocity_error,
                              (s.velocity - p.drive.point_velocity(p.mass.centre, s.time)).norm() +
                                  (s.angular_velocity - omega * Eigen::Vector3d::UnitZ()).norm());
  }

  // The strike: the sample at which the ball's velocity jumps.
  const std::vector<RigidState>& b = states[1];
  size_t hit = 0;
  for (size_t k = 1; k < b.size() && hit == 0; ++k) {
    if ((b[k].velocity - b[k - 1].velocity).norm() > 0.1) hit = k;
  }
  ASSERT_GT(hit, 0u) << "the paddle never struck the ball";
  const double t = b[hit].time;
  const Eigen::Vector3d n(-std::sin(omega * t), std::cos(omega * t), 0);  // the +y face's normal
  const Eigen::Vector3d v_in = b[hit - 1].velocity, v_out = b.back().velocity;
  const Eigen::Vector3d impulse = ball().mass.mass * (v_out - v_in);
  const double impulse_angle = std::acos(std::min(1.0, impulse.normalized().dot(n))) * 180.0 / M_PI;
  // The paddle's face point under the ball's centre moves at omega r along n.
  const Eigen::Vector3d c = b[hit].position;
  const double face_speed = omega * std::hypot(c.x(), c.y());
  const double closing_in = face_speed - v_in.dot(n), leaving_out = v_out.dot(n) - face_speed;
  std::printf(
      "kinematic paddle: follows its drive to %.2e m, %.2e rad, %.2e (m/s + rad/s) over "
      "%zu internal steps; strikes the ball at t = %.3f s: v (%.3f, %.3f, %.3f) -> "
      "(%.3f, %.3f, %.3f) m/s, impulse %.2f deg off the face normal, normal speed "
      "relative to the face %.3f in, %.3f out\n",
      position_error, angle_error, velocity_error, states[0].size() - 1, t, v_in.x(), v_in.y(),
      v_in.z(), v_out.x(), v_out.y(), v_out.z(), impulse_angle, closing_in, leaving_out);
  EXPECT_LE(position_error, 1e-12);
  EXPECT_LE(angle_error, 1e-12);
  EXPECT_LE(velocity_error, 1e-12);
  EXPECT_GT(v_out.y(), 3.0);      // reversed, faster than it came: the paddle drives it
  EXPECT_LT(impulse_angle, 3.0);  // frictionless: the impulse is along the face normal
  EXPECT_NEAR(leaving_out / closing_in, 1.0, 0.1);  // restitution 1 against infinite mass
}

TEST(RigidKinematic, ADrivenBodyBecomesAKinematicTwinOnItsDrive) {
  // A two-tet body (a double tetrahedron) driven about z through (1, 0, 0).
  TetMesh mesh;
  mesh.V.resize(5, 3);
  mesh.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0.4, 0.4, -1;
  mesh.T.resize(2, 4);
  mesh.T << 0, 1, 2, 3, 0, 2, 1, 4;
  Body body;
  body.name = "bat";
  body.vertex_end = 5;
  body.element_end = 2;
  body.driven_vertices = {0};
  body.drive.centre = Eigen::Vector3d(1, 0, 0);
  body.drive.angular_velocity = 2.0;
  const std::vector<RigidBody> twins =
      rigid_bodies(mesh, {body}, Eigen::VectorXd::Constant(2, 1000.0));
  ASSERT_EQ(twins.size(), 1u);
  EXPECT_TRUE(twins[0].kinematic);
  EXPECT_EQ(twins[0].drive.centre, body.drive.centre);
  EXPECT_LT((twins[0].velocity - body.drive.point_velocity(twins[0].mass.centre, 0)).norm(), 1e-15);
  EXPECT_EQ(twins[0].angular_velocity, Eigen::Vector3d(0, 0, 2));
}

}  // namespace
}  // namespace rbaa
