// Tangent-linear sensitivities against the adjoint (the dot-product test, gradient_check.hpp):
// on the paper's scenes at coarse meshes, field by field, where finite differences cannot resolve
// Y and nu; on random per-element materials over the whole rigid range with near-void elements;
// along initial-state directions (dC/dq_0, dC/dv_0); and the check catching a wrong adjoint term.

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cstdio>
#include <random>

#include "diff_fixtures.hpp"
#include "rbaa/diff/gradient_check.hpp"
#include "rbaa/diff/tangent_linear.hpp"
#include "rbaa/diff/trajectory_objective.hpp"
#include "rbaa/scene/scene.hpp"
#include "rbaa/scene/scene_mesh.hpp"
#include "rbaa/scene/scene_world.hpp"
#include "rbaa/sim/barrier_stiffness.hpp"
#include "support/intersection_free.hpp"

namespace rbaa {
namespace {

constexpr double kTangentBar = 1e-10;  // issue 14: tangent and adjoint agree to round-off

// A shipped config at a coarse mesh: the placed mesh, settings and the undirected objective
// against the uniform reference, as `rbaa gradcheck` builds them.
struct ConfigProblem {
  Scene scene;
  TetMesh mesh;
  SimulationSettings settings;
  Eigen::VectorXd q0, v0;
  std::shared_ptr<UndirectedTrajectoryObjective> objective;
};

ConfigProblem config_problem(const std::string& name, std::vector<std::string> overrides = {}) {
  ConfigProblem p;
  overrides.insert(overrides.begin(), "mesh.target_tets=300");
  p.scene = load_scene(std::string(RBAA_SOURCE_DIR) + "/configs/" + name + ".yaml", overrides);
  p.mesh = make_scene_mesh(p.scene);
  p.settings = simulation_settings(p.scene, scene_barrier_stiffness(p.scene, p.mesh));
  p.q0 = Eigen::Map<const Eigen::VectorXd>(p.mesh.V.data(), 3 * p.mesh.num_vertices());
  p.v0 = rigid_velocities(p.q0, p.scene.position, p.scene.velocity, p.scene.angular_velocity);
  Simulator ref(p.mesh,
                MaterialField::uniform(p.mesh.num_tets(), p.scene.reference_Y, p.scene.reference_nu,
                                       p.scene.reference_rho),
                p.settings);
  const Trajectory reference = ref.run(p.q0, p.v0);
  EXPECT_EQ(test::first_intersection(p.mesh, p.settings, reference), "") << name;
  p.objective = UndirectedTrajectoryObjective::from_reference(p.mesh, p.scene.reference_rho,
                                                              reference.q.back());
  return p;
}

GradientCheckResult tangent_check(TrajectoryGradientFunction& f, const Eigen::VectorXd& theta,
                                  bool material_space) {
  GradientCheckOptions o;
  o.method = GradientCheckMethod::kTangent;
  o.directions = 3;
  o.material_space = material_space;
  return check_gradient(f, theta, o);
}

// strict: the error itself within 1e-10; otherwise within the bar or 4x the tangent's own
// measured round-off (the cube: 150 stiff steps, its Y and nu move the objective by 1e-13).
void expect_config_fields(const std::string& name, bool strict = true,
                          const std::vector<std::string>& overrides = {}) {
  const ConfigProblem p = config_problem(name, overrides);
  for (DesignField field : {DesignField::kY, DesignField::kNu, DesignField::kRho, DesignField::kAlpha}) {
    DesignSpaceOptions options = design_space_options(p.scene);
    options.fields = {field};
    const DesignSpace ds(p.mesh, options);
    TrajectoryGradientFunction f(p.mesh, p.settings, p.q0, p.v0, ds, p.objective);
    const GradientCheckResult r = tangent_check(f, ds.initial_theta(true), false);
    std::printf("%s %-5s: %d tets, %d steps, contact in %d, |g| %.3e, tangent errors", name.c_str(),
                design_field_name(field), p.mesh.num_tets(), p.settings.num_steps,
                r.active_contact_steps, r.gradient_norm);
    for (const DirectionCheck& d : r.directions) {
      std::printf(" %.2e (pointwise %.2e, own round-off %.1e)", d.tangent_relative_error,
                  d.tangent_pointwise_error, d.tangent_noise);
    }
    std::printf("\n");
    EXPECT_GT(r.active_contact_steps, 0) << name;
    EXPECT_GT(r.gradient_norm, 0) << name;
    EXPECT_TRUE(r.tangent_pass) << name << " " << design_field_name(field);
    EXPECT_EQ(test::first_intersection(p.mesh, p.settings, f.last().trajectory), "")
        << name << " " << design_field_name(field);
    if (strict) {
      EXPECT_LE(r.max_tangent_relative_error, kTangentBar) << name << " " << design_field_name(field);
    }
  }
}

TEST(TangentLinear, BallConfigEveryField) { expect_config_fields("ball"); }
// Contact-resolving steps (variable-step BDF-2 around the impact): the same bar.
TEST(TangentLinear, BallConfigWithContactSubStepsEveryField) {
  expect_config_fields("ball", true, {"time.contact_substeps=8"});
}
TEST(TangentLinear, StarConfigEveryField) { expect_config_fields("star"); }
TEST(TangentLinear, BunnyConfigEveryField) { expect_config_fields("bunny"); }
TEST(TangentLinear, CubeConfigEveryField) { expect_config_fields("cube", false); }

// Random per-element materials over the whole rigid range, a fifth of the interior near void
// (alpha at alpha_min), checked in material space with every field at once.
TEST(TangentLinear, RandomMaterialsWithNearVoidElements) {
  const ConfigProblem p = config_problem("ball");
  const DesignSpaceOptions options = design_space_options(p.scene);
  const DesignSpace ds(p.mesh, options);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  MaterialField m = MaterialField::uniform(p.mesh.num_tets(), 1e10, 0.3, 2500);
  int near_void = 0;
  for (int e = 0; e < p.mesh.num_tets(); ++e) {
    // Strictly inside the ranges (the tanh maps reach the ends only at infinity).
    auto inside = [&](double lo, double hi) { return lo + (hi - lo) * (0.001 + 0.998 * unit(rng)); };
    m.Y[e] = std::exp(inside(std::log(options.Y_min), std::log(options.Y_max)));
    m.nu[e] = inside(options.nu_min, options.nu_max);
    m.rho[e] = inside(options.rho_min, options.rho_max);
    if (!ds.boundary()[e]) {
      const bool empty = unit(rng) < 0.2;
      m.alpha[e] = empty ? options.alpha_min * 1.001 : inside(options.alpha_min, 1.0);
      near_void += empty;
    }
  }
  ASSERT_GT(near_void, 5);
  TrajectoryGradientFunction f(p.mesh, p.settings, p.q0, p.v0, ds, p.objective);
  const GradientCheckResult r = tangent_check(f, ds.to_theta(m), true);
  std::printf("random materials, %d near-void elements: |g| %.3e, contact in %d steps, errors",
              near_void, r.gradient_norm, r.active_contact_steps);
  for (const DirectionCheck& d : r.directions) std::printf(" %.2e", d.tangent_relative_error);
  std::printf("\n");
  EXPECT_GT(r.active_contact_steps, 0);
  EXPECT_LE(r.max_tangent_relative_error, kTangentBar);
  EXPECT_EQ(test::first_intersection(p.mesh, p.settings, f.last().trajectory), "");
}

// The thrown test ball (1e9 Pa) run once, with the undirected objective's seed against a
// stiffer reference run: what the adjoint and the tangent both consume.
struct ThrownBallRun {
  test::ThrownBall b = test::thrown_ball(Integrator::kBdf2);
  MaterialField m = MaterialField::uniform(b.mesh.num_tets(), 1e9, 0.3, 2500);
  Simulator sim{b.mesh, m, b.settings};
  Trajectory t;
  TrajectorySeed seed;

  ThrownBallRun() {
    t = sim.run(b.q0, b.v0);
    Simulator ref(b.mesh, MaterialField::uniform(b.mesh.num_tets(), 5e9, 0.28, 2500), b.settings);
    const Trajectory reference = ref.run(b.q0, b.v0);
    const test::IntersectionCheck check(b.mesh, b.settings);
    EXPECT_EQ(check.first_intersection(t), "");
    EXPECT_EQ(check.first_intersection(reference), "");
    UndirectedTrajectoryObjective::from_reference(b.mesh, 2500, reference.q.back())
        ->evaluate(t, m, &seed);
  }
};

// dC/dq_0 and dC/dv_0 (through the steps and the ballistic history) against tangents along
// random initial-state directions.
TEST(TangentLinear, InitialStateDirectionsMatchTheAdjoint) {
  ThrownBallRun run;
  const test::ThrownBall& b = run.b;
  const MaterialField& m = run.m;
  Simulator& sim = run.sim;
  const Trajectory& t = run.t;
  const TrajectorySeed& seed = run.seed;
  const AdjointResult a = adjoint_gradient(sim, m, t, seed);

  std::mt19937_64 rng(3);
  std::normal_distribution<double> normal;
  std::vector<TangentDirection> dirs(2);
  for (auto& d : dirs) {
    d.q0 = Eigen::VectorXd::NullaryExpr(b.q0.size(), [&] { return normal(rng); });
    d.v0 = Eigen::VectorXd::NullaryExpr(b.q0.size(), [&] { return normal(rng); });
  }
  const TangentResult tl = tangent_linear(sim, m, t, seed, dirs);
  for (std::size_t i = 0; i < dirs.size(); ++i) {
    const double adjoint = a.dq0.dot(dirs[i].q0) + a.dv0.dot(dirs[i].v0);
    const double scale = std::max(a.dq0.norm() * dirs[i].q0.norm() + a.dv0.norm() * dirs[i].v0.norm(),
                                  tl.bounds[i]);
    std::printf("initial-state direction %zu: adjoint %+.12e tangent %+.12e error %.2e\n", i,
                adjoint, tl.derivatives[i], std::abs(adjoint - tl.derivatives[i]) / scale);
    EXPECT_LE(std::abs(adjoint - tl.derivatives[i]), kTangentBar * scale);
    EXPECT_GT(std::abs(adjoint), 1e-3 * scale);  // not a cancellation to nothing
  }
}

// dq_N itself (final_dq): in free flight a translation t of q_0 moves every later position by t,
// and a uniform velocity change u of v_0 moves q_N by N h u (BDF-2 and its ballistic start
// reproduce uniform motion exactly; elasticity does not see either).
TEST(TangentLinear, FinalPositionsOfRigidInitialChangesAreExact) {
  test::ThrownBall b = test::thrown_ball(Integrator::kBdf2);
  b.settings.planes.clear();
  const MaterialField m = MaterialField::uniform(b.mesh.num_tets(), 1e9, 0.3, 2500);
  Simulator sim(b.mesh, m, b.settings);
  const Trajectory t = sim.run(b.q0, b.v0);
  const TrajectorySeed seed = TrajectorySeed::empty(t.num_steps());
  const Eigen::Vector3d shift(0.01, -0.02, 0.03), u(0.5, 0.25, -1.0);
  TangentDirection translate, accelerate;
  translate.q0 = shift.replicate(b.mesh.num_vertices(), 1);
  accelerate.v0 = u.replicate(b.mesh.num_vertices(), 1);
  const TangentResult r = tangent_linear(sim, m, t, seed, {translate, accelerate});
  ASSERT_EQ(r.final_dq.size(), 2u);
  const double T = t.num_steps() * t.time_step;
  double e_shift = 0, e_velocity = 0;
  for (int v = 0; v < b.mesh.num_vertices(); ++v) {
    e_shift = std::max(e_shift, (r.final_dq[0].segment<3>(3 * v) - shift).norm());
    e_velocity = std::max(e_velocity, (r.final_dq[1].segment<3>(3 * v) - T * u).norm());
  }
  std::printf("free flight: dq_N of a translation off by %.2e m, of a velocity change by %.2e m\n",
              e_shift, e_velocity);
  // Exact up to the solves' round-off through H = M + w K (measured 3e-12 and 1e-12 relative); a
  // wrong history coefficient would be off by O(1).
  EXPECT_LE(e_shift, 1e-9 * shift.norm());
  EXPECT_LE(e_velocity, 1e-9 * T * u.norm());
  EXPECT_EQ(r.derivatives, (std::vector<double>{0.0, 0.0}));  // an empty seed: nothing observed
}

// A state whose exact Hessian is indefinite (one tet pushed through its opposite face, stiff,
// large step) makes the backward pass fall back to LDL^T, and its statistics say so once, as do
// the tangent's.
TEST(TangentLinear, IndefiniteHessianFallsBackToLdltAndIsCounted) {
  TetMesh tet;
  tet.V.resize(4, 3);
  tet.V << 0, 0, 0.1, 0.1, 0, 0.1, 0, 0.1, 0.1, 0, 0, 0.2;
  tet.T.resize(1, 4);
  tet.T << 0, 1, 2, 3;
  SimulationSettings s;
  s.time_step = 1.0;
  s.num_steps = 1;
  s.gravity = Eigen::Vector3d::Zero();
  const MaterialField m = MaterialField::uniform(1, 1e10, 0.3, 1000);
  Simulator sim(tet, m, s);
  // A one-step "trajectory" ending in the inverted state (not a converged one: the adjoint and the
  // tangent only linearise about it).
  Trajectory t;
  t.time_step = s.time_step;
  t.integrator = s.integrator;
  const Eigen::VectorXd q0 = test::positions(tet);
  t.history = {q0, q0, q0};
  // Vertex 3 pushed down towards and through the face z = 0.1 (and sideways): the first of these
  // states whose exact Hessian an independent dense Cholesky rejects (all of them, measured).
  Eigen::VectorXd q1;
  for (double z : {0.099, 0.09, 0.05, 0.0, -0.2}) {
    for (double x : {0.0, 0.03, 0.2}) {
      Eigen::VectorXd q = q0;
      q[3 * 3 + 0] = x;
      q[3 * 3 + 2] = z;
      sim.potential().solution_changed(q);
      const Eigen::MatrixXd H = Eigen::MatrixXd(sim.potential().hessian(q, HessianKind::kExact))
                                    .selfadjointView<Eigen::Lower>();
      const bool indefinite = Eigen::LLT<Eigen::MatrixXd>(H).info() != Eigen::Success;
      if (indefinite && q1.size() == 0) q1 = q;
    }
  }
  ASSERT_GT(q1.size(), 0) << "no indefinite state among the candidates";
  t.q = {q0, q1};
  t.steps.resize(1);

  TrajectorySeed seed = TrajectorySeed::empty(1);
  seed.dq[1] = Eigen::VectorXd::LinSpaced(12, -1.0, 1.0);
  const AdjointResult a = adjoint_gradient(sim, m, t, seed);
  EXPECT_EQ(a.stats.rebuilt_factorizations, 1);
  EXPECT_EQ(a.stats.ldlt_fallbacks, 1);
  TangentDirection d;
  d.materials.Y = Eigen::VectorXd::Constant(1, 1e9);
  const TangentResult r = tangent_linear(sim, m, t, seed, {d});
  EXPECT_EQ(r.stats.ldlt_fallbacks, 1);
  // The two agree only to ~5e-7 here: CHOLMOD's LDL^T does not pivot, and on an indefinite
  // matrix its solves lose digits (a converged step's exact Hessian is positive definite; this
  // state is fabricated to reach the fallback).
  std::printf("indefinite state: tangent %.10e, adjoint %.10e\n", r.derivatives[0], a.materials.Y[0] * 1e9);
  EXPECT_NEAR(r.derivatives[0], a.materials.Y[0] * 1e9, 1e-5 * std::abs(r.derivatives[0]));
}

// A wrong adjoint term in one element (its dC/dY off by 1e-6 relative of the gradient) is caught
// by the tangent along a direction through that element, far above round-off.
TEST(TangentLinear, CatchesAWrongAdjointTerm) {
  ThrownBallRun run;
  const test::ThrownBall& b = run.b;
  const MaterialField& m = run.m;
  Simulator& sim = run.sim;
  const Trajectory& t = run.t;
  const TrajectorySeed& seed = run.seed;
  AdjointResult a = adjoint_gradient(sim, m, t, seed);

  TangentDirection d;
  d.materials.Y = Eigen::VectorXd::Ones(b.mesh.num_tets()) / std::sqrt(b.mesh.num_tets());
  const TangentResult tl = tangent_linear(sim, m, t, seed, {d});
  const double scale = std::max(a.materials.Y.norm(), tl.bounds[0]);
  const double right = std::abs(a.materials.Y.dot(d.materials.Y) - tl.derivatives[0]) / scale;
  a.materials.Y[7] += 1e-6 * a.materials.Y.norm();
  const double wrong = std::abs(a.materials.Y.dot(d.materials.Y) - tl.derivatives[0]) / scale;
  std::printf("tangent vs adjoint: %.2e; with element 7's dC/dY off by 1e-6 |g|: %.2e\n", right,
              wrong);
  EXPECT_LE(right, kTangentBar);
  EXPECT_GT(wrong, 100 * kTangentBar);
}

}  // namespace
}  // namespace rbaa
