// The adjoint through mesh-obstacle contact: the adjoint tests' coarse soft ball
// (diff_fixtures.hpp) thrown not at the plane z = 0 but at the top corner of a box obstacle right
// under it, so that body-vertex/obstacle-triangle, obstacle-vertex/body-triangle and edge-edge
// pairs (the box's edges run parallel to the ball's bottom face edges: mollified) are all active.
// Nothing in the adjoint knows about them: it uses the exact Hessian of every form, which this form
// provides. Checked against central finite differences (SPEC bar 1e-5, per field and all together)
// and the tangent-linear model (issue 14's bar 1e-10).

#include <gtest/gtest.h>

#include <cstdio>

#include "diff_fixtures.hpp"
#include "rbaa/diff/gradient_check.hpp"
#include "rbaa/diff/trajectory_objective.hpp"
#include "sim/obstacle_fixtures.hpp"
#include "support/intersection_free.hpp"

namespace rbaa {
namespace {

test::ThrownBall ball_at_box_corner() {
  test::ThrownBall b = test::thrown_ball(Integrator::kBdf2);
  b.settings.planes.clear();
  // The ball's lowest point is over (0.05, -0.02); the box's top corner is there.
  b.settings.obstacle_meshes = {
      test::box_obstacle(Eigen::Vector3d(-0.5, -0.5, -0.5), Eigen::Vector3d(0.05, -0.02, 0.0))};
  return b;
}

DesignSpaceOptions soft_design(std::vector<DesignField> fields) {
  DesignSpaceOptions o;
  o.fields = std::move(fields);
  o.Y_min = 2e7;  // as in test_adjoint.cpp: soft enough that materials move the path in contact
  o.Y_max = 2e9;
  o.seed = 7;
  o.perturbation = 0.5;
  return o;
}

std::shared_ptr<UndirectedTrajectoryObjective> reference_objective(const test::ThrownBall& b) {
  Simulator ref(b.mesh, MaterialField::uniform(b.mesh.num_tets(), 5e9, 0.28, 2500), b.settings);
  const Trajectory t = ref.run(b.q0, b.v0);
  EXPECT_EQ(test::first_intersection(b.mesh, b.settings, t), "");
  return UndirectedTrajectoryObjective::from_reference(b.mesh, 2500, t.q.back());
}

TEST(MeshObstacleGradient, AllPairKindsAreActive) {
  const test::ThrownBall b = ball_at_box_corner();
  Simulator sim(b.mesh, MaterialField::uniform(b.mesh.num_tets(), 1e9, 0.3, 2500), b.settings);
  const Trajectory t = sim.run(b.q0, b.v0);
  int vt = 0, tv = 0, ee = 0, steps = 0;
  for (std::size_t k = 1; k < t.q.size(); ++k) {
    const auto& pairs = sim.mesh_obstacle_form()->active_pairs(t.q[k]);
    steps += !pairs.empty();
    for (const ObstaclePair& p : pairs) {
      vt += p.kind == ObstaclePairKind::kVertexTriangle;
      tv += p.kind == ObstaclePairKind::kTriangleVertex;
      ee += p.kind == ObstaclePairKind::kEdgeEdge;
    }
  }
  std::printf("ball on a box corner: %d contact steps; pairs over the run: VT %d, TV %d, EE %d\n",
              steps, vt, tv, ee);
  EXPECT_EQ(test::first_intersection(b.mesh, b.settings, t), "");
  EXPECT_GE(steps, 3);
  EXPECT_GT(vt, 0);
  EXPECT_GT(tv, 0);
  EXPECT_GT(ee, 0);
}

TEST(MeshObstacleGradient, AdjointMatchesFiniteDifferencesPerField) {
  const test::ThrownBall b = ball_at_box_corner();
  const auto objective = reference_objective(b);
  const std::vector<std::vector<DesignField>> sets = {
      {DesignField::kY},
      {DesignField::kNu},
      {DesignField::kRho},
      {DesignField::kAlpha},
      {DesignField::kY, DesignField::kNu, DesignField::kRho, DesignField::kAlpha}};
  for (const auto& fields : sets) {
    DesignSpace ds(b.mesh, soft_design(fields));
    TrajectoryGradientFunction f(b.mesh, b.settings, b.q0, b.v0, ds, objective);
    GradientCheckOptions o;
    o.step = 1e-2;  // test_adjoint.cpp explains the step
    o.directions = 2;
    const GradientCheckResult r = check_gradient(f, ds.initial_theta(true), o);
    std::string name;
    for (DesignField d : fields)
      name += std::string(name.empty() ? "" : ",") + design_field_name(d);
    std::printf(
        "box corner %-16s: C %.6e |g| %.3e contact steps %d/%d, rebuilt factors %d, relative "
        "errors",
        name.c_str(), r.value, r.gradient_norm, r.active_contact_steps, b.settings.num_steps,
        f.last().adjoint.rebuilt_factorizations);
    for (const DirectionCheck& d : r.directions) std::printf(" %.2e", d.relative_error);
    std::printf("\n");
    EXPECT_GE(r.active_contact_steps, 3);
    EXPECT_GT(r.gradient_norm, 0);
    // SPEC's bar 1e-5 for each field and all four together (measured on 2026-11-26: <= 7e-10 Y,
    // 5.5e-8 nu, 4.2e-10 rho, 2.6e-7 alpha, 1.4e-9 all four). The all-fields case measured 2.5e-5
    // before 943ec7f and was left out: C scanned along a direction departed from its quadratic by
    // ~1e-11 irregularly. The cause was Newton stopping at its round-off floor in the contact
    // steps (the line search cannot see a 1e-14 m step's energy change), not the adjoint; since
    // the solver takes a gradient-lowering step there the case is back in.
    EXPECT_LE(r.max_relative_error, 1e-5) << name;
    // The check's last run (a finite-difference one).
    EXPECT_EQ(test::first_intersection(b.mesh, b.settings, f.last().trajectory), "") << name;
  }
}

TEST(MeshObstacleGradient, AdjointMatchesTheTangentLinearModel) {
  const test::ThrownBall b = ball_at_box_corner();
  const auto objective = reference_objective(b);
  DesignSpace ds(b.mesh, soft_design({DesignField::kY, DesignField::kNu, DesignField::kRho,
                                      DesignField::kAlpha}));
  TrajectoryGradientFunction f(b.mesh, b.settings, b.q0, b.v0, ds, objective);
  GradientCheckOptions o;
  o.method = GradientCheckMethod::kTangent;
  o.directions = 3;
  const GradientCheckResult r = check_gradient(f, ds.initial_theta(true), o);
  std::printf("box corner tangent: |g| %.3e, contact steps %d, errors", r.gradient_norm,
              r.active_contact_steps);
  for (const DirectionCheck& d : r.directions) {
    std::printf(" %.2e (own round-off %.1e)", d.tangent_relative_error, d.tangent_noise);
  }
  std::printf("\n");
  EXPECT_GE(r.active_contact_steps, 3);
  EXPECT_LE(r.max_tangent_relative_error, 1e-10);
  EXPECT_EQ(test::first_intersection(b.mesh, b.settings, f.last().trajectory), "");
}

}  // namespace
}  // namespace rbaa
