// The adjoint through lagged friction on mesh pairs (pair_friction_form.hpp): the adjoint tests'
// coarse soft ball (diff_fixtures.hpp) thrown sliding onto a two-triangle floor with mu = 0.5,
// and the two colliding, spinning balls of the several-bodies tests (sim/body_fixtures.hpp) with
// mu = 0.5 between them. The step equation depends on q_n and q_{n-1} through the lagged normal
// forces, closest points, tangent bases and x~; the form's history hooks add those terms. Checked
// per field (and per body) against central differences (SPEC bar 1e-5) and against the
// tangent-linear model (1e-10; measured ~1e-15).

#include <gtest/gtest.h>

#include <cstdio>

#include "diff_fixtures.hpp"
#include "rbaa/diff/gradient_check.hpp"
#include "rbaa/diff/trajectory_objective.hpp"
#include "sim/body_fixtures.hpp"
#include "sim/obstacle_fixtures.hpp"
#include "support/intersection_free.hpp"

namespace rbaa {
namespace {

// The ball slides along the floor (as FrictionGradient's ball does on the plane), its contact
// patch 0.05 m or more from the square's diagonal: vertex - triangle pairs only, the frame's
// weights depending on the sliding vertex.
test::ThrownBall ball_on_mesh_floor(double mu) {
  test::ThrownBall b = test::thrown_ball(Integrator::kBdf2);
  b.settings.planes.clear();
  ObstacleMesh floor = test::square_obstacle(1.0);
  floor.friction = mu;
  b.settings.obstacle_meshes = {floor};
  b.settings.num_steps = 20;
  const Eigen::Vector3d c = b.mesh.V.colwise().mean().transpose();
  b.v0 = rigid_velocities(b.q0, c, Eigen::Vector3d(1.5, 0.3, -0.4), Eigen::Vector3d::Zero());
  return b;
}

DesignSpaceOptions soft_design(std::vector<DesignField> fields, double rho, unsigned seed) {
  DesignSpaceOptions o;
  o.fields = std::move(fields);
  o.Y_min = 2e7;  // as in test_adjoint.cpp: soft enough that materials move the path in contact
  o.Y_max = 2e9;
  o.reference_rho = rho;
  o.seed = seed;
  o.perturbation = 0.5;
  return o;
}

void print(const char* what, const GradientCheckResult& r) {
  std::printf("%s: |g| %.3e contact steps %d, relative errors", what, r.gradient_norm,
              r.active_contact_steps);
  for (const DirectionCheck& d : r.directions) {
    std::printf(" %.2e (at 4x the step %.2e, %s)", d.relative_error, d.coarse_relative_error,
                d.noise_dominated ? "noise" : "not noise");
  }
  std::printf("\n");
}

std::shared_ptr<UndirectedTrajectoryObjective> floor_objective(const test::ThrownBall& b) {
  Simulator ref(b.mesh, MaterialField::uniform(b.mesh.num_tets(), 5e9, 0.28, 2500), b.settings);
  const Trajectory t = ref.run(b.q0, b.v0);
  EXPECT_EQ(test::first_intersection(b.mesh, b.settings, t), "");
  return UndirectedTrajectoryObjective::from_reference(b.mesh, 2500, t.q.back());
}

TEST(MeshFrictionGradient, FrictionActsAndChangesThePath) {
  const test::ThrownBall with = ball_on_mesh_floor(0.5), without = ball_on_mesh_floor(0.0);
  const MaterialField m = MaterialField::uniform(with.mesh.num_tets(), 1e9, 0.3, 2500);
  Simulator a(with.mesh, m, with.settings), b(without.mesh, m, without.settings);
  ASSERT_NE(a.pair_friction_form(), nullptr);
  EXPECT_EQ(b.pair_friction_form(), nullptr);  // frictionless: no form at all
  int lagged = 0;
  const Trajectory ta = a.run(with.q0, with.v0, [&](int, const Eigen::VectorXd&, const StepStats&) {
    lagged += a.pair_friction_form()->num_lagged_pairs() > 0;
  });
  const Trajectory tb = b.run(without.q0, without.v0);
  const double gap = (ta.q.back() - tb.q.back()).cwiseAbs().maxCoeff();
  std::printf(
      "ball on a mesh floor: friction in %d of %d steps; final positions differ by %.3e m\n",
      lagged, with.settings.num_steps, gap);
  EXPECT_GE(lagged, 10);
  EXPECT_GT(gap, 1e-4);
  EXPECT_EQ(test::first_intersection(with.mesh, with.settings, ta), "");
  EXPECT_EQ(test::first_intersection(without.mesh, without.settings, tb), "");
}

TEST(MeshFrictionGradient, AdjointMatchesFiniteDifferencesPerField) {
  const test::ThrownBall b = ball_on_mesh_floor(0.5);
  const auto objective = floor_objective(b);
  for (DesignField field :
       {DesignField::kY, DesignField::kNu, DesignField::kRho, DesignField::kAlpha}) {
    DesignSpace ds(b.mesh, soft_design({field}, 2500, 11));
    TrajectoryGradientFunction f(b.mesh, b.settings, b.q0, b.v0, ds, objective);
    GradientCheckOptions o;
    o.step = 1e-2;  // test_adjoint.cpp explains the step
    o.directions = 2;
    const GradientCheckResult r = check_gradient(f, ds.initial_theta(true), o);
    print((std::string("mesh floor friction ") + design_field_name(field)).c_str(), r);
    EXPECT_GE(r.active_contact_steps, 10);
    EXPECT_GT(r.gradient_norm, 0);
    EXPECT_LE(r.max_relative_error, 1e-5) << design_field_name(field);
    // The check's last run (a finite-difference one).
    EXPECT_EQ(test::first_intersection(b.mesh, b.settings, f.last().trajectory), "");
  }
}

TEST(MeshFrictionGradient, AdjointMatchesTheTangentLinearModel) {
  const test::ThrownBall b = ball_on_mesh_floor(0.5);
  const auto objective = floor_objective(b);
  DesignSpace ds(b.mesh, soft_design({DesignField::kY, DesignField::kNu, DesignField::kRho,
                                      DesignField::kAlpha},
                                     2500, 11));
  TrajectoryGradientFunction f(b.mesh, b.settings, b.q0, b.v0, ds, objective);
  GradientCheckOptions o;
  o.method = GradientCheckMethod::kTangent;
  o.directions = 3;
  const GradientCheckResult r = check_gradient(f, ds.initial_theta(true), o);
  std::printf("mesh floor friction tangent: |g| %.3e, contact steps %d, errors", r.gradient_norm,
              r.active_contact_steps);
  for (const DirectionCheck& d : r.directions) std::printf(" %.2e", d.tangent_relative_error);
  std::printf("\n");
  EXPECT_GE(r.active_contact_steps, 10);
  EXPECT_LE(r.max_tangent_relative_error, 1e-10);
  EXPECT_EQ(test::first_intersection(b.mesh, b.settings, f.last().trajectory), "");
}

// The mesh-obstacle gradient tests' ball thrown at a box's top corner (test_mesh_obstacle_gradient
// .cpp), with mu = 0.5 on the box: vertex - triangle, triangle - vertex (the corner against the
// ball's faces) and edge - edge pairs all carry friction.
test::ThrownBall ball_at_box_corner(double mu) {
  test::ThrownBall b = test::thrown_ball(Integrator::kBdf2);
  b.settings.planes.clear();
  b.settings.obstacle_meshes = {
      test::box_obstacle(Eigen::Vector3d(-0.5, -0.5, -0.5), Eigen::Vector3d(0.05, -0.02, 0.0))};
  b.settings.obstacle_meshes[0].friction = mu;
  return b;
}

TEST(MeshFrictionGradient, AtABoxCornerEveryPairKindCarriesFriction) {
  const test::ThrownBall b = ball_at_box_corner(0.5);
  Simulator sim(b.mesh, MaterialField::uniform(b.mesh.num_tets(), 1e9, 0.3, 2500), b.settings);
  int vt = 0, tv = 0, ee = 0;
  const Trajectory run = sim.run(b.q0, b.v0, [&](int, const Eigen::VectorXd&, const StepStats&) {
    for (const LaggedFrictionPair& p : sim.pair_friction_form()->lagged_pairs()) {
      vt += !p.points.edge_edge && p.points.vertex[0] >= 0;
      tv += !p.points.edge_edge && p.points.vertex[0] < 0;
      ee += p.points.edge_edge;
    }
  });
  std::printf(
      "ball on a box corner with friction: lagged pairs over the run: VT %d, TV %d, EE %d\n", vt,
      tv, ee);
  EXPECT_GT(vt, 0);
  EXPECT_GT(tv, 0);
  EXPECT_GT(ee, 0);
  EXPECT_EQ(test::first_intersection(b.mesh, b.settings, run), "");
  const auto objective = floor_objective(b);
  for (DesignField field :
       {DesignField::kY, DesignField::kNu, DesignField::kRho, DesignField::kAlpha}) {
    DesignSpace ds(b.mesh, soft_design({field}, 2500, 7));
    TrajectoryGradientFunction f(b.mesh, b.settings, b.q0, b.v0, ds, objective);
    GradientCheckOptions o;
    o.step = 1e-2;
    o.directions = 2;
    o.method = GradientCheckMethod::kBoth;
    const GradientCheckResult r = check_gradient(f, ds.initial_theta(true), o);
    print((std::string("box corner friction ") + design_field_name(field)).c_str(), r);
    std::printf("  tangent errors");
    for (const DirectionCheck& d : r.directions) std::printf(" %.2e", d.tangent_relative_error);
    std::printf("\n");
    EXPECT_GE(r.active_contact_steps, 3);
    EXPECT_LE(r.max_relative_error, 1e-5) << design_field_name(field);
    EXPECT_LE(r.max_tangent_relative_error, 1e-10) << design_field_name(field);
    EXPECT_EQ(test::first_intersection(b.mesh, b.settings, f.last().trajectory), "");
  }
}

// The two balls with friction between them: A spins at 20 rad/s about z as it strikes B
// off-centre, so their surfaces slide while in contact (vertex - triangle and edge - edge pairs,
// every point a degree of freedom).
test::TwoBalls two_balls_with_friction(double mu) {
  test::TwoBalls t = test::two_balls();
  t.settings.body_friction = Eigen::MatrixXd::Zero(2, 2);
  t.settings.body_friction(0, 1) = t.settings.body_friction(1, 0) = mu;
  // Newton 10x tighter than the fixture's 1e-12: there one direction of nu of A measured 5.9e-5
  // at s = 1e-2 and 1.9e-6 at 4 s (noise-dominated: the two estimates disagree with each other);
  // at 1e-13 it measures 1.8e-6 and 1.3e-6, at 1e-14 5e-8. The error was Newton's stopping
  // error in the forward map, not the adjoint (whose tangent check is 4e-15 either way). 20 steps
  // (contact in steps 7-12) instead of 40 keep the run under a minute at that tolerance.
  t.settings.newton_tolerance = 1e-13;
  t.settings.num_steps = 20;
  return t;
}

std::shared_ptr<UndirectedTrajectoryObjective> balls_objective(const test::TwoBalls& t,
                                                               const Eigen::VectorXd& q0,
                                                               const Eigen::VectorXd& v0) {
  Simulator ref(t.mesh, MaterialField::uniform(t.mesh.num_tets(), 5e9, 0.28, 1000), t.settings);
  const Trajectory reference = ref.run(q0, v0);
  EXPECT_EQ(test::first_intersection(t.mesh, t.settings, reference), "");
  return UndirectedTrajectoryObjective::from_reference(t.mesh, 1000, reference.q.back());
}

TEST(TwoBodyFrictionGradient, FrictionActsAndChangesThePath) {
  const test::TwoBalls with = two_balls_with_friction(0.5), without = two_balls_with_friction(0.0);
  const Eigen::VectorXd q0 = test::positions(with.mesh);
  const Eigen::VectorXd v0 = initial_velocities(q0, with.bodies);
  Simulator a(with.mesh, with.materials, with.settings),
      b(without.mesh, without.materials, without.settings);
  ASSERT_NE(a.pair_friction_form(), nullptr);
  EXPECT_EQ(b.pair_friction_form(), nullptr);
  int lagged = 0, pairs = 0;
  const Trajectory ta = a.run(q0, v0, [&](int, const Eigen::VectorXd&, const StepStats&) {
    lagged += a.pair_friction_form()->num_lagged_pairs() > 0;
    pairs += a.pair_friction_form()->num_lagged_pairs();
  });
  const Trajectory tb = b.run(q0, v0);
  const double gap = (ta.q.back() - tb.q.back()).cwiseAbs().maxCoeff();
  std::printf(
      "two balls: friction in %d of %d steps (%d lagged pairs in all); final positions "
      "differ by %.3e m\n",
      lagged, with.settings.num_steps, pairs, gap);
  EXPECT_GE(lagged, 3);
  EXPECT_GT(gap, 1e-4);
  EXPECT_EQ(test::first_intersection(with.mesh, with.settings, ta), "");
  EXPECT_EQ(test::first_intersection(without.mesh, without.settings, tb), "");
}

TEST(TwoBodyFrictionGradient, AdjointMatchesFiniteDifferencesPerFieldAndBody) {
  const test::TwoBalls t = two_balls_with_friction(0.5);
  const Eigen::VectorXd q0 = test::positions(t.mesh);
  const Eigen::VectorXd v0 = initial_velocities(q0, t.bodies);
  const auto objective = balls_objective(t, q0, v0);
  for (DesignField field :
       {DesignField::kY, DesignField::kNu, DesignField::kRho, DesignField::kAlpha}) {
    DesignSpace ds(t.mesh, soft_design({field}, 1000, 5));
    TrajectoryGradientFunction f(t.mesh, t.settings, q0, v0, ds, objective);
    for (const Body& body : t.bodies) {
      GradientCheckOptions o;
      o.step = 1e-2;
      o.directions = 2;
      o.element_begin = body.element_begin;
      o.element_end = body.element_end;
      const GradientCheckResult r = check_gradient(f, ds.initial_theta(true), o);
      print((std::string("two balls friction ") + design_field_name(field) + " of " + body.name)
                .c_str(),
            r);
      EXPECT_GE(r.active_contact_steps, 3);
      for (const DirectionCheck& d : r.directions) EXPECT_NE(d.adjoint, 0.0);
      // As in TwoBodyGradient (test_two_body_gradient.cpp, where it is measured): a random
      // direction of nu is nearly orthogonal to nu's small gradient (|g| 6.5e-8), so s x slope
      // sits near C's noise, which follows Newton's final residual. Measured 2026-11-27 with the
      // chord start: one such direction of A 3.1e-5 at s = 1e-2, 4.1e-7 at 4 s (noise-dominated).
      // It is accepted only as noise-dominated; nu is held to 1e-5 along its own gradient below.
      for (const DirectionCheck& d : r.directions) {
        EXPECT_TRUE(d.relative_error <= 1e-5 || (field == DesignField::kNu && d.noise_dominated))
            << design_field_name(field) << " of " << body.name << ": " << d.relative_error;
      }
      EXPECT_EQ(test::first_intersection(t.mesh, t.settings, f.last().trajectory), "");
      if (field == DesignField::kNu) {
        // Along nu's gradient (restricted to this body), where the slope stands far above noise.
        const Eigen::VectorXd theta = ds.initial_theta(true);
        Eigen::VectorXd g;
        f.evaluate(theta, &g);
        Eigen::VectorXd d = Eigen::VectorXd::Zero(g.size());
        for (int i = 0; i < g.size(); ++i) {  // nu: one entry per element
          if (i >= body.element_begin && i < body.element_end) d[i] = g[i];
        }
        ASSERT_GT(d.norm(), 0.0);
        const double slope = d.norm();
        d /= slope;
        const double s = 1e-3;
        const double fd =
            (f.evaluate(theta + s * d, nullptr) - f.evaluate(theta - s * d, nullptr)) / (2 * s);
        const double error = std::abs(fd - slope) / std::max(std::abs(fd), slope);
        std::printf("two balls friction nu of %s along its gradient: slope %.6e, relative error %.2e\n",
                    body.name.c_str(), slope, error);
        EXPECT_LE(error, 1e-5) << "nu of " << body.name;
      }
    }
  }
}

TEST(TwoBodyFrictionGradient, AdjointMatchesTheTangentLinearModel) {
  const test::TwoBalls t = two_balls_with_friction(0.5);
  const Eigen::VectorXd q0 = test::positions(t.mesh);
  const Eigen::VectorXd v0 = initial_velocities(q0, t.bodies);
  const auto objective = balls_objective(t, q0, v0);
  DesignSpace ds(t.mesh, soft_design({DesignField::kY, DesignField::kNu, DesignField::kRho,
                                      DesignField::kAlpha},
                                     1000, 5));
  TrajectoryGradientFunction f(t.mesh, t.settings, q0, v0, ds, objective);
  GradientCheckOptions o;
  o.method = GradientCheckMethod::kTangent;
  o.directions = 3;
  const GradientCheckResult r = check_gradient(f, ds.initial_theta(true), o);
  std::printf("two balls friction tangent: |g| %.3e, contact steps %d, errors", r.gradient_norm,
              r.active_contact_steps);
  for (const DirectionCheck& d : r.directions) std::printf(" %.2e", d.tangent_relative_error);
  std::printf("\n");
  EXPECT_GE(r.active_contact_steps, 3);
  EXPECT_LE(r.max_tangent_relative_error, 1e-10);
  EXPECT_EQ(test::first_intersection(t.mesh, t.settings, f.last().trajectory), "");
}

}  // namespace
}  // namespace rbaa
