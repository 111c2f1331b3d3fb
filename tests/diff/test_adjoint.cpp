// The adjoint gradient of whole simulations against central finite differences (SPEC section 3):
// a coarse ball thrown at a plane with contact active in several steps, each material field alone
// and all together, BDF-2 and BDF-1, consistent and lumped mass; a directed objective with a
// direct material term; stored Newton factors against rebuilt ones.
//
// Finite-difference step: directions are unit vectors in theta, the step s = 1e-2 (in theta
// units; theta_e moves by ~s / sqrt(#theta)) with Richardson extrapolation of the central
// differences at s and s/2, so the truncation error is O(s^4) ~ 1e-8 relative. Smaller steps let
// the noise of the converged Newton iterates (tolerance 1e-12 x diagonal per second, ~1e-17 m per
// step here) divided by s dominate: at s = 1e-4 the error rose to ~1e-6 in exploration, at 1e-2
// it was 1e-8 to 1e-10. A contact pair entering or leaving between C(theta + s d) and
// C(theta - s d) does not break the differences: b is C^2 at d_hat.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "diff_fixtures.hpp"
#include "rbaa/diff/adjoint.hpp"
#include "rbaa/diff/gradient_check.hpp"
#include "rbaa/diff/trajectory_objective.hpp"
#include "rbaa/error.hpp"
#include "sim/finite_differences.hpp"
#include "support/intersection_free.hpp"

namespace rbaa {
namespace {

constexpr double kBar = 1e-5;  // SPEC section 3

DesignSpaceOptions test_design(std::vector<DesignField> fields) {
  DesignSpaceOptions o;
  o.fields = std::move(fields);
  // Stiff enough to stay a solid, soft enough (mid-range 1e9 Pa) that the elastic parameters
  // change the trajectory measurably during the contact.
  o.Y_min = 2e7;
  o.Y_max = 2e9;
  o.seed = 7;
  o.perturbation = 0.5;  // a strongly non-uniform field
  return o;
}

const char* integrator_name(Integrator i) { return i == Integrator::kBdf2 ? "BDF-2" : "BDF-1"; }

std::string fields_name(const std::vector<DesignField>& fields) {
  std::string s;
  for (DesignField f : fields) s += std::string(s.empty() ? "" : ",") + design_field_name(f);
  return s;
}

// The undirected objective against a uniform, stiffer reference run of the same scene.
std::shared_ptr<UndirectedTrajectoryObjective> reference_objective(const test::ThrownBall& b) {
  Simulator ref(b.mesh, MaterialField::uniform(b.mesh.num_tets(), 5e9, 0.28, 2500), b.settings);
  const Trajectory t = ref.run(b.q0, b.v0);
  EXPECT_EQ(test::first_intersection(b.mesh, b.settings, t), "");
  return UndirectedTrajectoryObjective::from_reference(b.mesh, 2500, t.q.back());
}

void expect_gradient(const test::ThrownBall& b, std::shared_ptr<const TrajectoryObjective> objective,
                     const std::vector<DesignField>& fields, const char* label) {
  DesignSpace ds(b.mesh, test_design(fields));
  TrajectoryGradientFunction f(b.mesh, b.settings, b.q0, b.v0, ds, objective);
  GradientCheckOptions o;
  o.step = 1e-2;
  o.directions = 2;
  const GradientCheckResult r = check_gradient(f, ds.initial_theta(true), o);
  std::printf("%s %-16s: C %.6e |g| %.3e contact steps %d/%d, relative errors", label,
              fields_name(fields).c_str(), r.value, r.gradient_norm, r.active_contact_steps,
              b.settings.num_steps);
  for (const DirectionCheck& d : r.directions) std::printf(" %.2e", d.relative_error);
  std::printf("\n");
  EXPECT_GE(r.active_contact_steps, 3) << "the check must cover several contact steps";
  EXPECT_GT(r.gradient_norm, 0);
  EXPECT_LE(r.max_relative_error, kBar) << label << " " << fields_name(fields);
  // Every stored factor was used: Newton ended every step on the exact Hessian here.
  EXPECT_EQ(f.last().adjoint.rebuilt_factorizations, 0);
  // The check's last run (a finite-difference one).
  EXPECT_EQ(test::first_intersection(b.mesh, b.settings, f.last().trajectory), "");
}

const std::vector<std::vector<DesignField>> kFieldSets = {
    {DesignField::kY}, {DesignField::kNu}, {DesignField::kRho}, {DesignField::kAlpha},
    {DesignField::kY, DesignField::kNu, DesignField::kRho, DesignField::kAlpha}};

TEST(Adjoint, UndirectedGradientMatchesFiniteDifferencesBdf2) {
  const test::ThrownBall b = test::thrown_ball(Integrator::kBdf2);
  const auto objective = reference_objective(b);
  for (const auto& fields : kFieldSets) expect_gradient(b, objective, fields, "BDF-2");
}

TEST(Adjoint, UndirectedGradientMatchesFiniteDifferencesBdf1) {
  const test::ThrownBall b = test::thrown_ball(Integrator::kBdf1);
  const auto objective = reference_objective(b);
  for (const auto& fields : kFieldSets) expect_gradient(b, objective, fields, "BDF-1");
}

TEST(Adjoint, LumpedMassGradientMatchesFiniteDifferences) {
  test::ThrownBall b = test::thrown_ball(Integrator::kBdf2);
  b.settings.mass = MassModel::kLumped;
  const auto objective = reference_objective(b);
  expect_gradient(b, objective, kFieldSets.back(), "BDF-2 lumped");
}

TEST(Adjoint, DirectedCentreOfMassObjectiveWithDirectTerms) {
  // The centre of mass weighs positions with the object's own masses, so rho and alpha enter
  // directly too; the objective also reads an intermediate step (k = 6), not only q_N.
  for (Integrator integrator : {Integrator::kBdf2, Integrator::kBdf1}) {
    const test::ThrownBall b = test::thrown_ball(integrator);
    auto com_x = std::make_shared<CentreOfMassObservable>(b.mesh, Eigen::Vector3d(1, 0.3, 0), -1);
    auto com_z = std::make_shared<CentreOfMassObservable>(b.mesh, Eigen::Vector3d::UnitZ(), 6);
    auto objective = std::make_shared<DirectedObjective>(std::vector<DirectedObjective::Term>{
        {com_x, 0.0, 1.0}, {com_z, 0.02, 10.0}});
    expect_gradient(b, objective, kFieldSets.back(), integrator_name(integrator));
  }
}

TEST(Adjoint, StoredFactorsGiveTheRebuiltGradient) {
  for (Integrator integrator : {Integrator::kBdf2, Integrator::kBdf1}) {
    const test::ThrownBall b = test::thrown_ball(integrator);
    const auto objective = reference_objective(b);
    DesignSpace ds(b.mesh, test_design(kFieldSets.back()));
    const Eigen::VectorXd theta = ds.initial_theta(true);
    TrajectoryGradientFunction stored(b.mesh, b.settings, b.q0, b.v0, ds, objective,
                                      FactorStorage::kStore);
    TrajectoryGradientFunction rebuilt(b.mesh, b.settings, b.q0, b.v0, ds, objective,
                                       FactorStorage::kRebuild);
    Eigen::VectorXd gs, gr;
    const double cs = stored.evaluate(theta, &gs);
    const double cr = rebuilt.evaluate(theta, &gr);
    EXPECT_EQ(cs, cr);
    EXPECT_EQ(test::first_intersection(b.mesh, b.settings, stored.last().trajectory), "");
    const AdjointStats& s = stored.last().adjoint;
    const AdjointStats& r = rebuilt.last().adjoint;
    EXPECT_EQ(s.stored_factor_solves, b.settings.num_steps);
    EXPECT_EQ(s.rebuilt_factorizations, 0);
    EXPECT_EQ(r.stored_factor_solves, 0);
    EXPECT_EQ(r.rebuilt_factorizations, b.settings.num_steps);
    EXPECT_GT(stored.last().stored_factor_bytes, 0u);
    const double rel = (gs - gr).norm() / gr.norm();
    std::printf("%s: stored vs rebuilt factors: relative gradient difference %.2e, %zu bytes kept\n",
                integrator_name(integrator), rel, stored.last().stored_factor_bytes);
    EXPECT_LE(rel, 1e-10);
  }
}

TEST(Adjoint, ReusedFactorBuffersGiveBitIdenticalGradients) {
  // The second and later evaluations refill the stored factors in place (CholmodFactor::assign);
  // the gradient must not depend on that, nor on a different design evaluated in between.
  const test::ThrownBall b = test::thrown_ball(Integrator::kBdf2);
  const auto objective = reference_objective(b);
  DesignSpace ds(b.mesh, test_design(kFieldSets.back()));
  const Eigen::VectorXd theta = ds.initial_theta(true);
  TrajectoryGradientFunction fresh(b.mesh, b.settings, b.q0, b.v0, ds, objective, FactorStorage::kStore);
  TrajectoryGradientFunction reused(b.mesh, b.settings, b.q0, b.v0, ds, objective, FactorStorage::kStore);
  Eigen::VectorXd g_fresh, g_other, g_again;
  fresh.evaluate(theta, &g_fresh);
  reused.evaluate(theta, &g_again);
  reused.evaluate(ds.initial_theta(false), &g_other);
  reused.evaluate(theta, &g_again);
  EXPECT_EQ(reused.last().adjoint.stored_factor_solves, b.settings.num_steps);
  ASSERT_EQ(g_fresh.size(), g_again.size());
  EXPECT_TRUE(g_fresh == g_again) << "max difference " << (g_fresh - g_again).cwiseAbs().maxCoeff();
  EXPECT_FALSE(g_fresh == g_other);
}

// The Ceres face of the trajectory term (ceres::FirstOrderFunction, for GradientProblemSolver),
// called as Ceres calls it, through the base class: the throwing member's value and gradient bit
// for bit, the value alone when no gradient is asked for, and a failed simulation an infeasible
// point (false, the message kept), not an exception.
TEST(Adjoint, CeresInterfaceGivesTheMembersValueAndGradient) {
  const test::ThrownBall b = test::thrown_ball(Integrator::kBdf2);
  const auto objective = reference_objective(b);
  DesignSpace ds(b.mesh, test_design(kFieldSets.back()));
  const Eigen::VectorXd theta = ds.initial_theta(true);
  TrajectoryGradientFunction member(b.mesh, b.settings, b.q0, b.v0, ds, objective);
  Eigen::VectorXd g;
  const double c = member.evaluate(theta, &g);
  ASSERT_GT(g.norm(), 0);

  TrajectoryGradientFunction function(b.mesh, b.settings, b.q0, b.v0, ds, objective);
  const ceres::FirstOrderFunction& ceres_face = function;
  ASSERT_EQ(ceres_face.NumParameters(), ds.size());
  double cost = 0;
  Eigen::VectorXd gradient = Eigen::VectorXd::Constant(ds.size(), std::nan(""));
  ASSERT_TRUE(ceres_face.Evaluate(theta.data(), &cost, gradient.data()));
  EXPECT_EQ(cost, c);
  EXPECT_TRUE(gradient == g) << "max difference " << (gradient - g).cwiseAbs().maxCoeff();
  double value_only = 0;
  ASSERT_TRUE(ceres_face.Evaluate(theta.data(), &value_only, nullptr));
  EXPECT_EQ(value_only, c);
  EXPECT_EQ(function.last_error(), "");

  SimulationSettings starved = b.settings;
  starved.newton_max_iterations = 1;
  TrajectoryGradientFunction failing(b.mesh, starved, b.q0, b.v0, ds, objective);
  EXPECT_THROW(failing.evaluate(theta, nullptr), SolverError);
  double unused = 0;
  EXPECT_FALSE(static_cast<const ceres::FirstOrderFunction&>(failing).Evaluate(theta.data(), &unused, gradient.data()));
  EXPECT_NE(failing.last_error().find("did not converge"), std::string::npos) << failing.last_error();
}

TEST(Adjoint, InitialStateAdjointMatchesFiniteDifferences) {
  // dC/dv_0 through the steps and the ballistic history, along one random direction.
  const test::ThrownBall b = test::thrown_ball(Integrator::kBdf2);
  const auto objective = reference_objective(b);
  const MaterialField m = MaterialField::uniform(b.mesh.num_tets(), 1e9, 0.3, 3000);
  Simulator sim(b.mesh, m, b.settings);
  DifferentiableSimulator diff(sim);
  const Trajectory t = diff.forward(m, b.q0, b.v0);
  EXPECT_EQ(test::first_intersection(b.mesh, b.settings, t), "");
  TrajectorySeed seed;
  objective->evaluate(t, m, &seed);
  const AdjointResult r = diff.backward(t, seed);
  Eigen::VectorXd d = Eigen::VectorXd::Random(b.v0.size());
  d /= d.norm();
  auto C = [&](double s) {
    return objective->evaluate(diff.forward(m, b.q0, b.v0 + s * d), m, nullptr);
  };
  const double s = 1e-3;  // m/s; the speeds are ~2 m/s
  const double fd = test::richardson_central_difference(C, s);
  const double ad = r.dv0.dot(d);
  std::printf("dC/dv0 . d: adjoint %.10e, finite difference %.10e\n", ad, fd);
  EXPECT_LE(std::abs(ad - fd), kBar * std::abs(fd));
}

}  // namespace
}  // namespace rbaa
