// The adjoint with driven (Dirichlet) vertices: a soft bar swung by its end face (driven about z)
// strikes a free ball (sim/driven_fixtures.hpp, a bat in miniature); the objective is the ball's
// final centre of mass, the variables the bar's materials. The driven positions are known
// functions of time: no adjoint flows into them, and the free dofs' dependence on them does not
// depend on the materials. Per field, against central differences (SPEC's bar 1e-5) and against
// the tangent-linear model (normwise, measured ~1e-15).

#include <gtest/gtest.h>

#include <random>

#include <algorithm>
#include <cstdio>

#include "rbaa/diff/gradient_check.hpp"
#include "rbaa/diff/tangent_linear.hpp"
#include "rbaa/diff/trajectory_gradient.hpp"
#include "rbaa/diff/trajectory_objective.hpp"
#include "rbaa/sim/mass_matrix.hpp"
#include "rbaa/sim/simulator.hpp"
#include "sim/driven_fixtures.hpp"
#include "sim/finite_differences.hpp"
#include "support/intersection_free.hpp"

namespace rbaa {
namespace {

// C = |c - target|^2, c the final centre of mass of the vertices [begin, end) weighted by fixed
// vertex masses (the ball's own, not designed here): no direct material term.
class FinalCentreObjective : public TrajectoryObjective {
 public:
  FinalCentreObjective(Eigen::VectorXd masses, int begin, int end, Eigen::Vector3d target)
      : masses_(std::move(masses)), begin_(begin), end_(end), target_(target) {}

  Eigen::Vector3d centre(const Eigen::VectorXd& q) const {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    double m = 0;
    for (int v = begin_; v < end_; ++v) {
      c += masses_[v] * q.segment<3>(3 * v);
      m += masses_[v];
    }
    return c / m;
  }

  double evaluate(const Trajectory& t, const MaterialField&, TrajectorySeed* seed) const override {
    const Eigen::Vector3d d = centre(t.q.back()) - target_;
    if (seed != nullptr) {
      *seed = TrajectorySeed::empty(t.num_steps());
      Eigen::VectorXd g = Eigen::VectorXd::Zero(t.q.back().size());
      const double m = masses_.segment(begin_, end_ - begin_).sum();
      for (int v = begin_; v < end_; ++v) g.segment<3>(3 * v) = 2.0 * masses_[v] / m * d;
      seed->dq.back() = g;
    }
    return d.squaredNorm();
  }

 private:
  Eigen::VectorXd masses_;
  int begin_, end_;
  Eigen::Vector3d target_;
};

DesignSpaceOptions soft_design(std::vector<DesignField> fields) {
  DesignSpaceOptions o;
  o.fields = std::move(fields);
  o.Y_min = 2e6;
  o.Y_max = 2e8;
  o.reference_rho = 1000;
  o.seed = 5;
  o.perturbation = 0.5;
  return o;
}

struct StrikeCase {
  test::DrivenScene scene = test::driven_bar(6, 10.0, 0.0, 0.025, 2);
  std::shared_ptr<FinalCentreObjective> objective;
  StrikeCase() {
    scene.settings.num_steps = 25;
    const Body& ball = scene.bodies[1];
    objective = std::make_shared<FinalCentreObjective>(
        vertex_masses(scene.mesh, Eigen::VectorXd::Constant(scene.mesh.num_tets(), 1000.0)),
        ball.vertex_begin, ball.vertex_end, Eigen::Vector3d(0.0, 0.1, 0.0));
  }
};

// The strike run from the Y design's perturbed start, and its adjoint.
struct StrikeAdjoint {
  DesignSpace ds;
  TrajectoryGradientFunction f;
  Eigen::VectorXd g;
  TrajectorySeed seed;
  AdjointResult a;
  explicit StrikeAdjoint(const StrikeCase& s)
      : ds(s.scene.mesh, soft_design({DesignField::kY})),
        f(s.scene.mesh, s.scene.settings, s.scene.q0, s.scene.v0, ds, s.objective) {
    f.evaluate(ds.initial_theta(true), &g);
    s.objective->evaluate(f.last().trajectory, f.last().materials, &seed);
    a = f.differentiable().backward(f.last().trajectory, seed);
  }
};

TEST(DrivenGradient, AdjointMatchesFiniteDifferencesAndTheTangentPerFieldOfTheDrivenBody) {
  const StrikeCase s;
  const Body& bar = s.scene.bodies[0];
  for (DesignField field :
       {DesignField::kY, DesignField::kNu, DesignField::kRho, DesignField::kAlpha}) {
    DesignSpace ds(s.scene.mesh, soft_design({field}));
    TrajectoryGradientFunction f(s.scene.mesh, s.scene.settings, s.scene.q0, s.scene.v0, ds,
                                 s.objective);
    GradientCheckOptions o;
    o.method = GradientCheckMethod::kBoth;
    o.step = 1e-2;  // test_adjoint.cpp explains the step
    o.directions = 2;
    o.element_begin = bar.element_begin;
    o.element_end = bar.element_end;
    const GradientCheckResult r = check_gradient(f, ds.initial_theta(true), o);
    std::printf(
        "driven bar -> ball, %-5s of the bar: C %.6e |g| %.3e contact steps %d; errors vs FD",
        design_field_name(field), r.value, r.gradient_norm, r.active_contact_steps);
    for (const DirectionCheck& d : r.directions) std::printf(" %.2e", d.relative_error);
    std::printf(", vs tangent");
    for (const DirectionCheck& d : r.directions) std::printf(" %.2e", d.tangent_relative_error);
    std::printf("\n");
    EXPECT_GE(r.active_contact_steps, 3);
    for (const DirectionCheck& d : r.directions) {
      EXPECT_NE(d.adjoint, 0.0);
      EXPECT_LE(d.relative_error, 1e-5) << design_field_name(field);
    }
    EXPECT_LE(r.max_tangent_relative_error, 1e-12) << design_field_name(field);
    // The check's last run (a finite-difference one).
    EXPECT_EQ(test::first_intersection(s.scene.mesh, s.scene.settings, f.last().trajectory), "")
        << design_field_name(field);
  }
}

// Driven vertices with contact-resolving steps (variable-step BDF-2 around the strike, as
// configs/bat_accurate.yaml attacks the bat): the drive is evaluated at every sub-step's time and
// the adjoint replays each step's own size. Every field of the bar together, against central
// differences and the tangent.
TEST(DrivenGradient, ContactResolvingStepsMatchFiniteDifferencesAndTheTangent) {
  StrikeCase s;
  s.scene.settings.contact_substeps = 4;
  const Body& bar = s.scene.bodies[0];
  DesignSpace ds(s.scene.mesh, soft_design({DesignField::kY, DesignField::kNu, DesignField::kRho,
                                            DesignField::kAlpha}));
  TrajectoryGradientFunction f(s.scene.mesh, s.scene.settings, s.scene.q0, s.scene.v0, ds,
                               s.objective);
  GradientCheckOptions o;
  o.method = GradientCheckMethod::kBoth;
  o.step = 1e-2;
  o.directions = 2;
  o.element_begin = bar.element_begin;
  o.element_end = bar.element_end;
  const GradientCheckResult r = check_gradient(f, ds.initial_theta(true), o);
  const Trajectory& t = f.last().trajectory;
  std::printf("driven bar -> ball, 4 sub-steps: %d steps for %d of h (%d shorter), contact steps "
              "%d, |g| %.3e; errors vs FD",
              t.num_steps(), s.scene.settings.num_steps, t.resolving.refined_steps,
              r.active_contact_steps, r.gradient_norm);
  for (const DirectionCheck& d : r.directions) std::printf(" %.2e", d.relative_error);
  std::printf(", vs tangent");
  for (const DirectionCheck& d : r.directions) std::printf(" %.2e", d.tangent_relative_error);
  std::printf("\n");
  // The strike was resolved: the run took shorter steps around it.
  EXPECT_GT(t.num_steps(), s.scene.settings.num_steps);
  EXPECT_GE(t.resolving.refined_steps, 1);
  EXPECT_GE(r.active_contact_steps, 3);
  for (const DirectionCheck& d : r.directions) {
    EXPECT_NE(d.adjoint, 0.0);
    EXPECT_LE(d.relative_error, 1e-5);
  }
  EXPECT_LE(r.max_tangent_relative_error, 1e-12);
  EXPECT_EQ(test::first_intersection(s.scene.mesh, s.scene.settings, t), "");
  // At every step, sub-steps included, the driven vertices sit where the drive puts them at that
  // step's own time.
  double worst = 0;
  for (int k = 0; k <= t.num_steps(); ++k) {
    for (int v : bar.driven_vertices) {
      const Eigen::Vector3d want = bar.drive.position(s.scene.q0.segment<3>(3 * v), t.time(k));
      worst = std::max(worst, (t.q[k].segment<3>(3 * v) - want).norm());
    }
  }
  EXPECT_LT(worst, 1e-12);
}

// The initial state's derivatives on the driven bar's free vertices. Simulator::reset gives every
// vertex of a driven body the drive's velocity and rigid past, q_{-k,i} = drive.position(q_{0,i},
// -k h): the run does not read v0 there (a run from another v0 is the same run), and q0 enters
// the past through the drive's rotation R(angle(-k h)), not as the ballistic identity. Central
// differences of C along a direction on those vertices, and the tangent, agree with the adjoint.
TEST(DrivenGradient, TheInitialStateEntersADrivenBodyThroughItsDrive) {
  const StrikeCase s;
  StrikeAdjoint run(s);
  const Trajectory t = run.f.last().trajectory;
  const MaterialField materials = run.f.last().materials;
  const AdjointResult& a = run.a;

  const Body& bar = s.scene.bodies[0];
  std::vector<char> driven(s.scene.mesh.num_vertices(), 0);
  for (int v : bar.driven_vertices) driven[v] = 1;
  Eigen::VectorXd d = Eigen::VectorXd::Zero(s.scene.q0.size());
  std::srand(11);
  int free_vertices = 0;
  for (int v = bar.vertex_begin; v < bar.vertex_end; ++v) {
    if (driven[v]) continue;
    d.segment<3>(3 * v) = Eigen::Vector3d::Random();
    ++free_vertices;
  }
  ASSERT_GT(free_vertices, 0);
  ASSERT_NE(bar.drive.angular_velocity, 0.0);  // the past is turned, not translated

  // v0: not read on the driven body.
  EXPECT_EQ(d.cwiseProduct(a.dv0).cwiseAbs().maxCoeff(), 0.0);
  Simulator sim(s.scene.mesh, materials, s.scene.settings);
  auto C = [&](const Eigen::VectorXd& q0, const Eigen::VectorXd& v0) {
    return s.objective->evaluate(sim.run(q0, v0), materials, nullptr);
  };
  const double c0 = C(s.scene.q0, s.scene.v0);
  EXPECT_EQ(C(s.scene.q0, s.scene.v0 + d), c0);

  // q0: central differences (Richardson-extrapolated) against the adjoint and the tangent.
  auto along = [&](double e) { return C(s.scene.q0 + e * d, s.scene.v0); };
  const double central = test::richardson_central_difference(along, 1e-6);
  TangentDirection direction;
  direction.q0 = d;
  const TangentResult tl = tangent_linear(run.f.simulator(), materials, t, run.seed, {direction});
  std::printf("driven bar's free vertices, dC/dq0 . d: adjoint %.9e, tangent %.9e, central "
              "differences %.9e\n",
              a.dq0.dot(d), tl.derivatives[0], central);
  EXPECT_NE(a.dq0.dot(d), 0.0);
  EXPECT_NEAR(a.dq0.dot(d), central, 1e-5 * std::abs(central));
  EXPECT_NEAR(tl.derivatives[0], a.dq0.dot(d), 1e-12 * std::abs(a.dq0.dot(d)));
}

TEST(DrivenGradient, NoAdjointReachesTheDrivenDofs) {
  const StrikeCase s;
  StrikeAdjoint run(s);
  TrajectoryGradientFunction& f = run.f;
  const Eigen::VectorXd& g = run.g;
  const AdjointResult& a = run.a;
  const int stored = f.last().adjoint.stored_factor_solves;
  EXPECT_GT(stored, 0);
  EXPECT_EQ(test::first_intersection(s.scene.mesh, s.scene.settings, f.last().trajectory), "");
  EXPECT_GT(a.dq0.norm(), 0.0);
  // A seed on the driven dofs alone (random, at every step) reaches nothing: no solve, a zero
  // material gradient and zero initial-state derivatives. Checking dq0 and dv0 at the driven dofs
  // of the strike's own seed could not fail (the adjoint zeroes those entries at its end); with the
  // per-step zeroing of the driven dofs' adjoint removed, this seed gave |dC/dalpha| 1.6e-4,
  // |dq0| 8.6e-4 and 25 solves (the reviewing helper's plant).
  const Simulator& sim = f.simulator();
  const Trajectory& t = f.last().trajectory;
  std::mt19937_64 rng(1);
  std::normal_distribution<double> normal;
  TrajectorySeed driven_only = TrajectorySeed::empty(t.num_steps());
  for (int k = 0; k <= t.num_steps(); ++k) {
    driven_only.dq[k] = Eigen::VectorXd::Zero(sim.num_dofs());
    for (int d : sim.driven_dofs()) driven_only.dq[k][d] = normal(rng);
  }
  ASSERT_FALSE(sim.driven_dofs().empty());
  const AdjointResult none = f.differentiable().backward(t, driven_only);
  EXPECT_EQ(none.stats.solves, 0);
  for (const Eigen::VectorXd* v : {&none.materials.Y, &none.materials.nu, &none.materials.rho,
                                   &none.materials.alpha, &none.dq0, &none.dv0}) {
    EXPECT_TRUE(v->isZero(0.0)) << v->norm();
  }
  // Stored factors and rebuilt ones give the same gradient (both of the eliminated Hessian).
  f.differentiable().set_storage(FactorStorage::kRebuild);
  Eigen::VectorXd g_rebuilt;
  f.evaluate(run.ds.initial_theta(true), &g_rebuilt);
  EXPECT_GT(f.last().adjoint.rebuilt_factorizations, 0);
  std::printf(
      "driven: %d stored factor solves; stored vs rebuilt factors, relative difference %.2e\n",
      stored, (g - g_rebuilt).norm() / g.norm());
  EXPECT_LE((g - g_rebuilt).norm(), 1e-10 * g.norm());
}

}  // namespace
}  // namespace rbaa
