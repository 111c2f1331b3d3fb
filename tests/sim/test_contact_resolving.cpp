// Contact-resolving steps (SimulationSettings::contact_substeps, issue 20 item 1): a stiff ball
// thrown at a plane keeps h in flight and h/k around the impact, every step ending on the grid of
// h; the refinement is deterministic, never intersects, and makes the rebound independent of
// where in a step of h the impact falls (BDF-2 at h = 0.01: restitution 0.38-1.15 over 3 mm of
// start, SPEC section 2).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "mesh_fixtures.hpp"
#include "rbaa/error.hpp"
#include "rbaa/sim/barrier_stiffness.hpp"
#include "rbaa/sim/observables.hpp"
#include "rbaa/sim/simulator.hpp"
#include "support/intersection_free.hpp"

namespace rbaa {
namespace {

constexpr double kRadius = 0.121;

struct Throw {
  TetMesh mesh;
  SimulationSettings settings;
  Eigen::VectorXd q0, v0;
};

// The ball (Y = 1e13) at height `gap` above z = 0 moving down at `speed`, no gravity, so that
// its rebound speed over its approach speed is the restitution.
Throw thrown_at_plane(double gap, double speed, double h, int num_steps, int substeps) {
  Throw t;
  t.mesh = test::ball_mesh(kRadius, 3, Eigen::Vector3d(0, 0, kRadius + gap));
  t.settings.time_step = h;
  t.settings.num_steps = num_steps;
  t.settings.gravity.setZero();
  t.settings.planes = {Plane{}};
  t.settings.contact_substeps = substeps;
  t.settings.kappa = barrier_stiffness_from_energy(2500 * 4.0 / 3.0 * M_PI * std::pow(kRadius, 3),
                                                   speed, t.settings.d_hat);
  t.q0 = test::positions(t.mesh);
  t.v0 = rigid_velocities(t.q0, Eigen::Vector3d(0, 0, kRadius + gap), Eigen::Vector3d(0, 0, -speed),
                          Eigen::Vector3d::Zero());
  return t;
}

MaterialField stiff(const TetMesh& mesh) {
  return MaterialField::uniform(mesh.num_tets(), 1e13, 0.28, 2500);
}

TEST(ContactResolving, RefinesAroundTheImpactAndEndsOnTheGrid) {
  const double h = 0.01;
  const Throw t = thrown_at_plane(0.0123, 5.0, h, 12, 8);
  Simulator sim(t.mesh, stiff(t.mesh), t.settings);
  const Trajectory a = sim.run(t.q0, t.v0);
  const Trajectory b = sim.run(t.q0, t.v0);
  const ContactResolvingStats& r = a.resolving;
  std::printf("contact-resolving: %d steps for %d of h, %d shorter than h, %d contacts, %d "
              "halved before Newton, %d rejected after\n", a.num_steps(), t.settings.num_steps,
              r.refined_steps, r.contacts, r.predicted_halvings, r.rejected_steps);
  ASSERT_EQ(a.step_sizes.size(), a.steps.size());
  ASSERT_EQ(a.times.size(), a.q.size());
  EXPECT_EQ(r.substeps, 8);
  EXPECT_GE(r.contacts, 1);
  EXPECT_GE(r.refined_steps, 1);
  // h -> h/2 -> h/4 -> h/8 at least once, here before Newton (the ballistic guess meets the plane).
  EXPECT_GE(r.predicted_halvings + r.rejected_steps, 3);
  EXPECT_GT(a.num_steps(), t.settings.num_steps);
  EXPECT_NEAR(a.times.back(), t.settings.num_steps * h, 1e-14);
  // Sizes are 2^j units of h/8 starting at multiples of themselves (so they tile every step of
  // h), sum to the times, and grow by at most 2 from one step to the next.
  double sum = 0;
  long at = 0;
  for (int k = 0; k < a.num_steps(); ++k) {
    const double dt = a.step_sizes[k];
    const double units = dt / (h / 8);
    EXPECT_NEAR(units, std::round(units), 1e-9) << k;
    EXPECT_GE(units, 1 - 1e-9);
    EXPECT_LE(units, 8 + 1e-9);
    const long u = std::lround(units);
    EXPECT_EQ(u & (u - 1), 0) << k;
    EXPECT_EQ(at % u, 0) << k;
    at += u;
    if (k > 0) {
      EXPECT_LE(dt / a.step_sizes[k - 1], 2.0 + 1e-12) << k;
    }
    sum += dt;
    EXPECT_NEAR(a.times[k + 1], sum, 1e-14) << k;
    // A step of more than one unit ends out of contact (it would have been halved).
    if (units > 1.5) {
      EXPECT_EQ(a.steps[k].active_pairs, 0) << k;
    }
  }
  // Deterministic to the bit, and never intersecting.
  ASSERT_EQ(b.num_steps(), a.num_steps());
  for (int k = 0; k <= a.num_steps(); ++k) {
    EXPECT_EQ((a.q[k] - b.q[k]).lpNorm<Eigen::Infinity>(), 0.0) << k;
    EXPECT_GT(test::min_vertex_plane_distance(a.q[k], t.settings.planes), 0.0) << k;
  }
  EXPECT_EQ(test::first_intersection(t.mesh, t.settings, a), "");  // every sub-step, exactly
}

// Constant steps are unchanged by the feature: 0 sub-steps records no sizes and gives the same
// trajectory as before it (the constant-step rule is the old one bit for bit, bdf.hpp).
TEST(ContactResolving, OffKeepsConstantSteps) {
  const Throw t = thrown_at_plane(0.0123, 5.0, 0.01, 6, 0);
  Simulator sim(t.mesh, stiff(t.mesh), t.settings);
  const Trajectory a = sim.run(t.q0, t.v0);
  EXPECT_TRUE(a.step_sizes.empty());
  EXPECT_EQ(a.num_steps(), 6);
  EXPECT_EQ(a.resolving.substeps, 0);
  EXPECT_DOUBLE_EQ(a.time(6), 0.06);
  EXPECT_EQ(test::first_intersection(t.mesh, t.settings, a), "");
}

double restitution(const Throw& t) {
  Simulator sim(t.mesh, stiff(t.mesh), t.settings);
  const Trajectory traj = sim.run(t.q0, t.v0);
  EXPECT_EQ(test::first_intersection(t.mesh, t.settings, traj), "");
  const Eigen::Vector3d v = centre_of_mass(traj.velocity(traj.num_steps()), sim.vertex_masses());
  return v.z() / -t.v0[2];
}

// The impact's phase within a step of h = 0.01 moves over 10 phases (the start gap by a tenth of
// the 5 cm the ball flies per step). Constant steps scatter the restitution (0.44-1.18); steps
// down to h/256 around the impact keep it within 2 % (issue 20's goal). h/16 does not: the ball
// stays within d_hat of the plane for ~0.4 ms, less than h/16 = 0.6 ms (measured: spread 44 %
// with 16 uniform sub-steps around the impact, 2.6 % with 64, 0.04 % with 256).
TEST(ContactResolving, RestitutionNoLongerDependsOnTheImpactPhase) {
  const double h = 0.01, speed = 5.0;
  std::vector<double> fixed, resolved;
  for (int p = 0; p < 10; ++p) {
    const double gap = 0.0123 + p * 0.1 * speed * h;
    fixed.push_back(restitution(thrown_at_plane(gap, speed, h, 8, 0)));
    resolved.push_back(restitution(thrown_at_plane(gap, speed, h, 8, 256)));
  }
  auto spread = [](const std::vector<double>& e) {
    const auto [lo, hi] = std::minmax_element(e.begin(), e.end());
    double mean = 0;
    for (double x : e) mean += x / e.size();
    return (*hi - *lo) / mean;
  };
  std::printf("restitution over 10 impact phases at h = 0.01:\n  constant h:        ");
  for (double e : fixed) std::printf(" %.4f", e);
  std::printf("  spread %.1f %%\n  down to h/256 at contact:", 100 * spread(fixed));
  for (double e : resolved) std::printf(" %.4f", e);
  std::printf("  spread %.2f %%\n", 100 * spread(resolved));
  for (double e : resolved) EXPECT_GT(e, 0.0);
  EXPECT_LE(spread(resolved), 0.02);
  EXPECT_GT(spread(fixed), 5 * spread(resolved));
}

TEST(ContactResolving, RefusesSubStepsThatAreNotPowersOfTwo) {
  Throw t = thrown_at_plane(0.0123, 5.0, 0.01, 2, 3);
  try {
    Simulator sim(t.mesh, stiff(t.mesh), t.settings);
    FAIL() << "3 sub-steps accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("contact sub-steps 3"), std::string::npos) << e.what();
  }
}

// A step size set once holds for every advance() after it, weights included: three steps of
// h/4 in free fall (gravity on, far from the plane) are the same whether set_next_step comes
// before the first step only or before each. The integrator re-derives the next step's rule and
// weight when it takes a step (after one h/4 from h the weight is ((3/8) h/4)^2 ... then
// ((1/3) h/4)^2 ...); forms that kept the first step's weight would pull the body by the wrong
// amount of gravity from the second step on.
TEST(ContactResolving, ASetStepHoldsForEveryAdvanceAfterIt) {
  Throw t = thrown_at_plane(1.0, 1.0, 0.01, 3, 4);
  t.settings.gravity = Eigen::Vector3d(0, 0, -9.8);
  Simulator once(t.mesh, stiff(t.mesh), t.settings), each(t.mesh, stiff(t.mesh), t.settings);
  once.reset(t.q0, t.v0);
  each.reset(t.q0, t.v0);
  once.set_next_step(1);
  for (int k = 0; k < 3; ++k) {
    each.set_next_step(1);
    once.advance();
    each.advance();
    const double gap = (once.integrator().current() - each.integrator().current()).cwiseAbs().maxCoeff();
    std::printf("step %d of h/4: set once vs before each, max difference %.3g m\n", k + 1, gap);
    EXPECT_EQ(gap, 0.0) << "step " << k + 1;
  }
  EXPECT_NEAR(once.time(), 0.0075, 1e-15);
}

}  // namespace
}  // namespace rbaa
