// The adjoint through contact-resolving steps (variable-step BDF-2, bdf.hpp) against central
// finite differences: the thrown ball of diff_fixtures.hpp with 4 sub-steps around its contact,
// every material field together (frictionless and with mu = 0.5) and the initial state. The step schedule is fixed by the forward
// run (which steps were refined), as any adaptive integrator's; the differences are taken at
// perturbations small enough not to change it, which the test checks.

#include <gtest/gtest.h>

#include <cstdio>

#include "diff_fixtures.hpp"
#include "rbaa/diff/adjoint.hpp"
#include "rbaa/diff/gradient_check.hpp"
#include "rbaa/diff/trajectory_objective.hpp"
#include "support/intersection_free.hpp"

namespace rbaa {
namespace {

constexpr double kBar = 1e-5;  // SPEC section 3

test::ThrownBall resolving_ball() {
  test::ThrownBall b = test::thrown_ball(Integrator::kBdf2);
  b.settings.contact_substeps = 4;
  return b;
}

void expect_material_gradient(const test::ThrownBall& b, const char* label) {
  Simulator ref(b.mesh, MaterialField::uniform(b.mesh.num_tets(), 5e9, 0.28, 2500), b.settings);
  const Trajectory reference = ref.run(b.q0, b.v0);
  EXPECT_EQ(test::first_intersection(b.mesh, b.settings, reference), "");
  auto objective = UndirectedTrajectoryObjective::from_reference(b.mesh, 2500, reference.q.back());
  DesignSpaceOptions o;
  o.fields = {DesignField::kY, DesignField::kNu, DesignField::kRho, DesignField::kAlpha};
  o.Y_min = 2e7;
  o.Y_max = 2e9;
  o.seed = 7;
  o.perturbation = 0.5;
  DesignSpace ds(b.mesh, o);
  TrajectoryGradientFunction f(b.mesh, b.settings, b.q0, b.v0, ds, objective);
  GradientCheckOptions check;
  check.step = 1e-2;
  check.directions = 2;
  const GradientCheckResult r = check_gradient(f, ds.initial_theta(true), check);
  const Trajectory& t = f.last().trajectory;
  std::printf("%s: %d steps for %d of h (%d shorter), contact steps %d, "
              "|g| %.3e, relative errors", label, t.num_steps(), b.settings.num_steps,
              t.resolving.refined_steps, r.active_contact_steps, r.gradient_norm);
  for (const DirectionCheck& d : r.directions) std::printf(" %.2e", d.relative_error);
  std::printf("\n");
  // The run did change its step, around several contact steps.
  EXPECT_GT(t.num_steps(), b.settings.num_steps);
  EXPECT_GE(t.resolving.refined_steps, 1);
  EXPECT_GE(r.active_contact_steps, 3);
  EXPECT_GT(r.gradient_norm, 0);
  EXPECT_LE(r.max_relative_error, kBar);
  EXPECT_EQ(f.last().adjoint.rebuilt_factorizations, 0);
  EXPECT_EQ(test::first_intersection(b.mesh, b.settings, t), "");  // the check's last run
}

TEST(ContactResolvingGradient, MaterialsMatchFiniteDifferences) {
  expect_material_gradient(resolving_ball(), "contact-resolving adjoint");
}

// Lagged friction (mu = 0.5) takes each step's own rule: x~ = a0 q_n + a1 q_{n-1} and eps_v b.
TEST(ContactResolvingGradient, WithFrictionMatchesFiniteDifferences) {
  test::ThrownBall b = resolving_ball();
  b.settings.planes[0].friction = 0.5;
  expect_material_gradient(b, "contact-resolving adjoint, friction");
}

// dC/dq_0 and dC/dv_0 through variable steps, against central differences of whole runs.
TEST(ContactResolvingGradient, InitialStateMatchesFiniteDifferences) {
  const test::ThrownBall b = resolving_ball();
  const MaterialField materials = MaterialField::uniform(b.mesh.num_tets(), 1e9, 0.3, 2000);
  Simulator sim(b.mesh, materials, b.settings);
  const Trajectory t = sim.run(b.q0, b.v0);
  ASSERT_GT(t.num_steps(), b.settings.num_steps);
  // C = w . q_N for a fixed random w: its gradient is the adjoint of the seed w at step N.
  Eigen::VectorXd w = Eigen::VectorXd::Random(sim.num_dofs());
  TrajectorySeed seed = TrajectorySeed::empty(t.num_steps());
  seed.dq[t.num_steps()] = w;
  const AdjointResult a = adjoint_gradient(sim, materials, t, seed);
  Eigen::VectorXd dq0 = Eigen::VectorXd::Random(sim.num_dofs());
  Eigen::VectorXd dv0 = Eigen::VectorXd::Random(sim.num_dofs());
  // Finite differences of the whole run along (dq0, dv0), central, small enough to keep the
  // schedule (checked).
  const double s = 1e-7;
  Simulator plus_sim(b.mesh, materials, b.settings), minus_sim(b.mesh, materials, b.settings);
  const Trajectory plus = plus_sim.run(b.q0 + s * dq0, b.v0 + s * dv0);
  const Trajectory minus = minus_sim.run(b.q0 - s * dq0, b.v0 - s * dv0);
  ASSERT_EQ(plus.step_sizes, t.step_sizes);
  ASSERT_EQ(minus.step_sizes, t.step_sizes);
  const test::IntersectionCheck check(b.mesh, b.settings);
  for (const Trajectory* run : {&t, &plus, &minus}) EXPECT_EQ(check.first_intersection(*run), "");
  const double fd = w.dot(plus.q.back() - minus.q.back()) / (2 * s);
  const double adjoint = a.dq0.dot(dq0) + a.dv0.dot(dv0);
  std::printf("contact-resolving initial state: adjoint %.10e, finite differences %.10e\n",
              adjoint, fd);
  EXPECT_NEAR(adjoint, fd, 1e-6 * std::abs(fd));
}

}  // namespace
}  // namespace rbaa
