// The adjoint through lagged friction: the adjoint tests' coarse soft ball (diff_fixtures.hpp),
// thrown sliding at the plane z = 0 with mu = 0.5, so friction acts in several
// steps. The step equation depends on q_n and q_{n-1} through friction's lagged normal forces and
// x~ (plane_friction_form.hpp); the adjoint adds those history terms. Checked per field against
// central differences (SPEC bar 1e-5, or noise-dominated: see below) and against the
// tangent-linear model (issue 14's bar 1e-10).

#include <gtest/gtest.h>

#include <cstdio>

#include "diff_fixtures.hpp"
#include "rbaa/diff/adjoint.hpp"
#include "rbaa/error.hpp"
#include "rbaa/diff/gradient_check.hpp"
#include "rbaa/diff/trajectory_objective.hpp"
#include "support/intersection_free.hpp"

namespace rbaa {
namespace {

test::ThrownBall sliding_ball(double mu) {
  test::ThrownBall b = test::thrown_ball(Integrator::kBdf2);
  b.settings.planes[0].friction = mu;
  b.settings.num_steps = 20;
  // Slower towards the plane than the adjoint tests' ball and faster along it, so that it stays
  // in contact and slides (never sticks: D is smooth there) for most of the run.
  const Eigen::Vector3d c = b.mesh.V.colwise().mean().transpose();
  b.v0 = rigid_velocities(b.q0, c, Eigen::Vector3d(1.5, 0.3, -0.4), Eigen::Vector3d::Zero());
  return b;
}

DesignSpaceOptions soft_design(std::vector<DesignField> fields) {
  DesignSpaceOptions o;
  o.fields = std::move(fields);
  o.Y_min = 2e7;  // as in test_adjoint.cpp: soft enough that materials move the path in contact
  o.Y_max = 2e9;
  o.seed = 11;
  o.perturbation = 0.5;
  return o;
}

std::shared_ptr<UndirectedTrajectoryObjective> reference_objective(const test::ThrownBall& b) {
  Simulator ref(b.mesh, MaterialField::uniform(b.mesh.num_tets(), 5e9, 0.28, 2500), b.settings);
  const Trajectory t = ref.run(b.q0, b.v0);
  EXPECT_EQ(test::first_intersection(b.mesh, b.settings, t), "");
  return UndirectedTrajectoryObjective::from_reference(b.mesh, 2500, t.q.back());
}

TEST(FrictionGradient, FrictionActsAndChangesThePath) {
  const test::ThrownBall with = sliding_ball(0.5), without = sliding_ball(0.0);
  const MaterialField m = MaterialField::uniform(with.mesh.num_tets(), 1e9, 0.3, 2500);
  Simulator a(with.mesh, m, with.settings), b(without.mesh, m, without.settings);

  ASSERT_NE(a.plane_friction_form(), nullptr);
  EXPECT_EQ(b.plane_friction_form(), nullptr);
  int lagged = 0;
  const Trajectory ta = a.run(with.q0, with.v0, [&](int, const Eigen::VectorXd&, const StepStats&) {
    lagged += a.plane_friction_form()->num_lagged_pairs() > 0;
  });
  const Trajectory tb = b.run(without.q0, without.v0);
  const double gap = (ta.q.back() - tb.q.back()).cwiseAbs().maxCoeff();
  std::printf("sliding ball: friction in %d of %d steps; final positions differ by %.3e m\n",
              lagged, with.settings.num_steps, gap);
  EXPECT_GE(lagged, 10);
  EXPECT_GT(gap, 1e-4);
  EXPECT_EQ(test::first_intersection(with.mesh, with.settings, ta), "");
  EXPECT_EQ(test::first_intersection(without.mesh, without.settings, tb), "");
}

TEST(FrictionGradient, AdjointMatchesFiniteDifferencesPerField) {
  const test::ThrownBall b = sliding_ball(0.5);
  const auto objective = reference_objective(b);
  for (DesignField field : {DesignField::kY, DesignField::kNu, DesignField::kRho, DesignField::kAlpha}) {
    DesignSpace ds(b.mesh, soft_design({field}));
    TrajectoryGradientFunction f(b.mesh, b.settings, b.q0, b.v0, ds, objective);
    GradientCheckOptions o;
    o.step = 1e-2;  // test_adjoint.cpp explains the step
    o.directions = 2;
    const GradientCheckResult r = check_gradient(f, ds.initial_theta(true), o);
    std::printf("friction %-5s: C %.6e |g| %.3e contact steps %d/%d, relative errors",
                design_field_name(field), r.value, r.gradient_norm, r.active_contact_steps,
                b.settings.num_steps);
    for (const DirectionCheck& d : r.directions) {
      std::printf(" %.2e (at 4x the step %.2e, %s)", d.relative_error, d.coarse_relative_error,
                  d.noise_dominated ? "noise" : "not noise");
    }
    std::printf("\n");
    EXPECT_GE(r.active_contact_steps, 10);
    EXPECT_GT(r.gradient_norm, 0);
    EXPECT_LE(r.max_relative_error, 1e-5) << design_field_name(field);
    // The check's last run (a finite-difference one).
    EXPECT_EQ(test::first_intersection(b.mesh, b.settings, f.last().trajectory), "");
  }
}

TEST(FrictionGradient, AdjointMatchesTheTangentLinearModel) {
  const test::ThrownBall b = sliding_ball(0.5);
  const auto objective = reference_objective(b);
  DesignSpace ds(b.mesh, soft_design({DesignField::kY, DesignField::kNu, DesignField::kRho,
                                      DesignField::kAlpha}));
  TrajectoryGradientFunction f(b.mesh, b.settings, b.q0, b.v0, ds, objective);
  GradientCheckOptions o;
  o.method = GradientCheckMethod::kTangent;
  o.directions = 3;
  const GradientCheckResult r = check_gradient(f, ds.initial_theta(true), o);
  std::printf("friction tangent: |g| %.3e, contact steps %d, errors", r.gradient_norm,
              r.active_contact_steps);
  for (const DirectionCheck& d : r.directions) {
    std::printf(" %.2e (own round-off %.1e)", d.tangent_relative_error, d.tangent_noise);
  }
  std::printf("\n");
  EXPECT_GE(r.active_contact_steps, 10);
  EXPECT_LE(r.max_tangent_relative_error, 1e-10);
  EXPECT_EQ(test::first_intersection(b.mesh, b.settings, f.last().trajectory), "");
}

// The derivatives take the lag at q_n (form.hpp): a simulator that re-lags friction within each
// step (SimulationSettings::friction_iterations > 1) is refused by value, and 1 is accepted.
TEST(FrictionGradient, TheAdjointRefusesASimulatorThatReLagsFriction) {
  for (int k : {1, 2}) {
    test::ThrownBall b = sliding_ball(0.5);
    b.settings.num_steps = 4;
    b.settings.friction_iterations = k;
    const MaterialField m = MaterialField::uniform(b.mesh.num_tets(), 1e9, 0.3, 2500);
    Simulator sim(b.mesh, m, b.settings);
    const Trajectory t = sim.run(b.q0, b.v0);
    TrajectorySeed seed = TrajectorySeed::empty(t.num_steps());
    seed.dq.back() = Eigen::VectorXd::Ones(b.q0.size());
    if (k == 1) {
      EXPECT_NO_THROW(adjoint_gradient(sim, m, t, seed));
      continue;
    }
    try {
      adjoint_gradient(sim, m, t, seed);
      ADD_FAILURE() << "the adjoint accepted friction re-lagged within each step";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("friction iterations 2"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("(set 1)"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace rbaa
