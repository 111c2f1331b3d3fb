// Several bodies in one simulation: two coarse balls colliding off-centre in free space (no
// gravity, no obstacles) through IPC contact between bodies. What contact must keep: linear
// momentum to 1e-10 relative, BDF-2's discrete angular balance sum_i q_{n+1,i} x (M q_hat)_i = 0
// to round-off (BDF-2 does not conserve angular momentum itself); no configuration ever
// intersects; the bodies exchange momentum. Overlapping bodies are refused naming both.

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cstdio>

#include "body_fixtures.hpp"
#include "mesh_fixtures.hpp"
#include "rbaa/error.hpp"
#include "rbaa/sim/observables.hpp"
#include "rbaa/sim/simulator.hpp"
#include "support/intersection_free.hpp"

namespace rbaa {
namespace {

Eigen::Vector3d body_momentum(const Eigen::VectorXd& Mv, const Body& b) {
  return linear_momentum(Mv.segment(3 * b.vertex_begin, 3 * b.num_vertices()));
}

TEST(Bodies, TwoBallsCollidingKeepMomentumAndNeverIntersect) {
  const test::TwoBalls t = test::two_balls();
  Simulator sim(t.mesh, t.materials, t.settings);
  ASSERT_NE(sim.body_contact_form(), nullptr);
  const Eigen::VectorXd q0 = test::positions(t.mesh);
  const Eigen::VectorXd v0 = initial_velocities(q0, t.bodies);
  int contact_steps = 0;
  double worst_balance = 0, min_distance = 1;
  bool intersecting = false;
  const Trajectory traj = sim.run(q0, v0, [&](int, const Eigen::VectorXd& q, const StepStats& s) {
    contact_steps += s.active_pairs > 0;
    const BodyClearance c = sim.body_contact_form()->clearance(q, 1.0);
    intersecting = intersecting || c.intersecting;
    min_distance = std::min(min_distance, c.distance);
    // BDF-2's discrete angular balance at this step: sum q_{n+1} x (M q_hat) = 0. The predictor
    // the inertia form holds is this step's q_hat.
    const Eigen::VectorXd Mq_hat = sim.inertia_form().multiply(sim.inertia_form().predictor());
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double scale = 0;
    for (int v = 0; v < t.mesh.num_vertices(); ++v) {
      const Eigen::Vector3d term = q.segment<3>(3 * v).cross(Mq_hat.segment<3>(3 * v));
      sum += term;
      scale += q.segment<3>(3 * v).norm() * Mq_hat.segment<3>(3 * v).norm();
    }
    worst_balance = std::max(worst_balance, sum.norm() / scale);
  });
  const Eigen::VectorXd Mv0 = sim.inertia_form().multiply(traj.velocity(0));
  const Eigen::VectorXd MvN = sim.inertia_form().multiply(traj.velocity(traj.num_steps()));
  const Eigen::Vector3d p0 = linear_momentum(Mv0), pN = linear_momentum(MvN);
  const double p_scale = body_momentum(Mv0, t.bodies[0]).norm() + body_momentum(Mv0, t.bodies[1]).norm();
  const Eigen::Vector3d pA0 = body_momentum(Mv0, t.bodies[0]), pAN = body_momentum(MvN, t.bodies[0]);
  std::printf("two balls: contact in %d of %d steps, closest %.3e m; momentum drift %.2e "
              "(relative); A's momentum %.4f -> %.4f (x); angular balance %.2e\n",
              contact_steps, t.settings.num_steps, min_distance, (pN - p0).norm() / p_scale,
              pA0.x(), pAN.x(), worst_balance);
  EXPECT_GE(contact_steps, 3);
  EXPECT_FALSE(intersecting);
  EXPECT_EQ(test::first_intersection(t.mesh, t.settings, traj), "");  // exact, every position
  EXPECT_GT(min_distance, 0);
  EXPECT_LE((pN - p0).norm(), 1e-10 * p_scale);
  EXPECT_LE(worst_balance, 1e-13);
  // Contact moved momentum from A to B: A slowed down by a good part of its momentum.
  EXPECT_LT(pAN.x(), 0.8 * pA0.x());
}

TEST(Bodies, OverlappingBodiesAreRefusedNamingBoth) {
  const test::TwoBalls t = test::two_balls(-0.03);  // B's centre 0.06 from A's: the balls overlap
  Simulator sim(t.mesh, t.materials, t.settings);
  const Eigen::VectorXd q0 = test::positions(t.mesh);
  EXPECT_NE(test::first_intersection(t.mesh, t.settings, q0), "");  // the exact check agrees
  try {
    sim.reset(q0, initial_velocities(q0, t.bodies));
    FAIL() << "overlapping bodies were accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("bodies 0 and 1"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

TEST(Bodies, ABodyListThatDoesNotTileTheMeshIsRefused) {
  test::TwoBalls t = test::two_balls();
  t.settings.bodies[1].vertex_begin += 1;
  EXPECT_THROW(Simulator(t.mesh, t.materials, t.settings), InputError);
  t = test::two_balls();
  t.settings.bodies.pop_back();
  EXPECT_THROW(Simulator(t.mesh, t.materials, t.settings), InputError);
}

}  // namespace
}  // namespace rbaa
