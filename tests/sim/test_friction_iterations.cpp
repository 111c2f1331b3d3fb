// Friction re-lagged within a step (SimulationSettings::friction_iterations). A box lands
// obliquely on a floor (an analytic plane, or a two-triangle mesh square): in the step that
// brings it within d_hat, Coulomb's law is read off the step equation itself,
//   M (x - q_hat) = w (M g + F_contact),  F_contact = F_normal + F_friction,
// as the ratio of the floor's tangential force to its normal force. Lagged once, from q_n (above
// d_hat), the landing step has no friction: the ratio is 0. Re-lagged from the step's solution
// until a re-lagged solve takes no step, the friction is that of the landing itself: the ratio
// is mu (every bottom vertex slides at ~1 m/s, far above the smoothing speed). Free-flight steps
// re-lag nothing and solve once. (The derivatives take the lag at q_n: the adjoint's refusal of
// a simulator that re-lags is tested in tests/diff/test_friction_gradient.cpp.)

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "mesh_fixtures.hpp"
#include "obstacle_fixtures.hpp"
#include "rbaa/error.hpp"
#include "rbaa/sim/newton_solver.hpp"
#include "rbaa/sim/observables.hpp"
#include "rbaa/sim/simulator.hpp"
#include "support/intersection_free.hpp"

namespace rbaa {
namespace {

constexpr double kMu = 0.4, kH = 2e-3, kDhat = 1e-3;

struct Landing {
  int step = -1;             // index k of the landing step (it produces q[k + 1])
  double ratio = 0;          // -F_x / F_z of the floor on the box in that step
  double normal_force = 0;   // F_z (N)
  int relags = 0;            // that step's friction re-lags
  int newton = 0;            // that step's Newton iterations, re-lagged solves included
  Eigen::VectorXd final_q;   // the run's last positions
  int free_flight_relags = 0;  // summed over the steps before it
  int free_flight_newton = 0;  // Newton iterations summed over the steps before it
  std::string intersection;
  ContactResolvingStats resolving;
};

SimulationSettings floor_settings(bool on_mesh, int friction_iterations, int substeps = 0) {
  SimulationSettings s;
  s.time_step = kH;
  s.contact_substeps = substeps;
  s.num_steps = 6;
  s.d_hat = kDhat;
  s.kappa = 1e5;
  s.friction_iterations = friction_iterations;
  if (on_mesh) {
    ObstacleMesh floor = test::square_obstacle(1.0);
    floor.friction = kMu;
    s.obstacle_meshes = {floor};
  } else {
    Plane floor;
    floor.friction = kMu;
    s.planes = {floor};
  }
  return s;
}

// A 0.1 m box of 1 kg (Y = 1e8) off the square's diagonal, 6.5 mm above the floor, thrown at
// (1, 0, -1) m/s: two steps of free flight, then it lands.
TetMesh box() {
  return test::lifted(test::box_mesh(2, 2, 2, 0.05, Eigen::Vector3d(0.3, -0.3, 0)), 6.5e-3);
}

Landing land(bool on_mesh, int friction_iterations, int substeps = 0) {
  const TetMesh mesh = box();
  const SimulationSettings s = floor_settings(on_mesh, friction_iterations, substeps);
  Simulator sim(mesh, MaterialField::uniform(mesh.num_tets(), 1e8, 0.3, 1000), s);
  const Eigen::VectorXd q0 = test::positions(mesh);
  const Trajectory t = sim.run(
      q0, rigid_velocities(q0, Eigen::Vector3d::Zero(), Eigen::Vector3d(1, 0, -1), Eigen::Vector3d::Zero()));
  Landing r;
  r.intersection = test::first_intersection(mesh, s, t);
  const Eigen::VectorXd& m = sim.vertex_masses();
  r.final_q = t.q.back();
  r.resolving = t.resolving;
  for (int k = 0; k < t.num_steps(); ++k) {
    if (t.steps[k].min_distance >= kDhat) {
      r.free_flight_relags += t.steps[k].friction_relags;
      r.free_flight_newton += t.steps[k].newton_iterations;
      continue;
    }
    const BdfPredictor P = t.predictor(k);
    const Eigen::VectorXd q_hat = bdf_predict(
        t.integrator, P, {&t.position(k), &t.position(k - 1), &t.position(k - 2), &t.position(k - 3)});
    Eigen::Vector3d F = Eigen::Vector3d::Zero();  // sum of M (x - q_hat) / w - M g
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      F += m[v] * ((t.q[k + 1] - q_hat).segment<3>(3 * v) / P.weight - s.gravity);
    }
    r.step = k;
    r.ratio = -F.x() / F.z();
    r.normal_force = F.z();
    r.relags = t.steps[k].friction_relags;
    r.newton = t.steps[k].newton_iterations;
    break;
  }
  return r;
}

class FrictionIterations : public ::testing::TestWithParam<bool> {};

TEST_P(FrictionIterations, ReLaggedFrictionActsInTheStepThatLands) {
  const bool on_mesh = GetParam();
  const Landing once = land(on_mesh, 1), relagged = land(on_mesh, 20);
  std::printf("%s floor, landing step %d: friction / normal force lagged once %.3e (F_n %.4g N), "
              "re-lagged %.6f (F_n %.4g N, %d re-lags; mu %.2f); free flight: %d re-lags, "
              "%d Newton iterations (once: %d)\n",
              on_mesh ? "mesh" : "plane", relagged.step, once.ratio, once.normal_force,
              relagged.ratio, relagged.normal_force, relagged.relags, kMu,
              relagged.free_flight_relags, relagged.free_flight_newton, once.free_flight_newton);
  ASSERT_EQ(once.step, 2);
  ASSERT_EQ(relagged.step, 2);
  EXPECT_GT(once.normal_force, 1.0);  // a landing, not a graze (the box weighs 9.8 N)
  // Lagged from q_n, 2.5 mm above d_hat: no friction pair in the landing step.
  EXPECT_LT(std::abs(once.ratio), 1e-9);
  // Re-lagged: Coulomb within the step.
  EXPECT_GE(relagged.relags, 1);
  EXPECT_NEAR(relagged.ratio, kMu, 1e-4 * kMu);  // measured 7.5e-6 relative
  // The first solve is the lagged-once step's; each re-lagged solve adds at least the check.
  EXPECT_GE(relagged.newton, once.newton + relagged.relags);
  // Free flight: nothing lagged before or after, no re-solve.
  EXPECT_EQ(relagged.free_flight_relags, 0);
  EXPECT_EQ(relagged.free_flight_newton, once.free_flight_newton);
  EXPECT_EQ(once.intersection, "");
  EXPECT_EQ(relagged.intersection, "");
}

// k bounds the re-lags at k - 1, and the re-lagging stops at convergence, not at the bound: 20
// and 100 allowed give the same run bit for bit.
TEST_P(FrictionIterations, ReLagsStopAtTheBoundOrAtConvergence) {
  const bool on_mesh = GetParam();
  EXPECT_EQ(land(on_mesh, 2).relags, 1);
  EXPECT_EQ(land(on_mesh, 3).relags, 2);
  const Landing twenty = land(on_mesh, 20), hundred = land(on_mesh, 100);
  EXPECT_LT(twenty.relags, 19);
  EXPECT_EQ(hundred.relags, twenty.relags);
  EXPECT_EQ(hundred.newton, twenty.newton);
  EXPECT_EQ((hundred.final_q - twenty.final_q).lpNorm<Eigen::Infinity>(), 0.0);
}

// With contact-resolving steps (SimulationSettings::contact_substeps) the landing is taken at
// h / 8, the steps before it halved as their ballistic guesses meet the floor (16 steps shorter
// than h); the sub-step that lands re-lags as a whole step does (its own q_n, variable-step BDF
// weights and predictor), and Coulomb holds in it.
TEST_P(FrictionIterations, ReLaggingWorksWithinContactResolvingSteps) {
  const bool on_mesh = GetParam();
  const Landing once = land(on_mesh, 1, 8), relagged = land(on_mesh, 20, 8);
  std::printf("%s floor, h / 8 sub-steps, landing step %d: friction / normal force lagged once "
              "%.3e, re-lagged %.6f (F_n %.4g N, %d re-lags); %d rejected, %d refined steps\n",
              on_mesh ? "mesh" : "plane", relagged.step, once.ratio, relagged.ratio,
              relagged.normal_force, relagged.relags, relagged.resolving.rejected_steps,
              relagged.resolving.refined_steps);
  ASSERT_GT(relagged.step, 2);  // sub-steps before it
  ASSERT_EQ(once.step, relagged.step);
  EXPECT_GT(relagged.resolving.refined_steps, 0);
  EXPECT_GT(once.normal_force, 1.0);
  EXPECT_LT(std::abs(once.ratio), 1e-9);
  EXPECT_GE(relagged.relags, 1);
  EXPECT_NEAR(relagged.ratio, kMu, 1e-4 * kMu);
  EXPECT_EQ(relagged.free_flight_relags, 0);
  EXPECT_EQ(relagged.free_flight_newton, once.free_flight_newton);
  EXPECT_EQ(once.intersection, "");
  EXPECT_EQ(relagged.intersection, "");
}

INSTANTIATE_TEST_SUITE_P(Floors, FrictionIterations, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& p) {
                           return p.param ? "Mesh" : "Plane";
                         });

// A step's statistics over its re-lagged solves (NewtonResult::append): counts and seconds add,
// the returned iterate's descriptions are the later solve's.
TEST(FrictionIterations, AStepsNewtonStatisticsAddUpOverItsSolves) {
  auto result = [](double base) {
    NewtonResult r;
    r.iterations = static_cast<int>(base);
    r.exact_factor = base > 1;
    r.step_velocity = base + 0.5;
    r.line_search_halvings = static_cast<int>(2 * base);
    r.line_search_probes = static_cast<int>(3 * base);
    r.projected_fallbacks = static_cast<int>(4 * base);
    r.extrapolations = static_cast<int>(5 * base);
    r.chord_steps = static_cast<int>(6 * base);
    r.symbolic_analyses = static_cast<int>(7 * base);
    r.roundoff_limited = base > 1;
    r.floor_velocity = base + 0.25;
    r.gradient_seconds = 0.1 * base;
    r.assembly_seconds = 0.2 * base;
    r.factorization_seconds = 0.3 * base;
    r.solve_seconds = 0.4 * base;
    r.line_search_seconds = 0.5 * base;
    return r;
  };
  NewtonResult r = result(1);
  r.append(result(10));
  EXPECT_EQ(r.iterations, 11);
  EXPECT_TRUE(r.exact_factor);
  EXPECT_EQ(r.step_velocity, 10.5);
  EXPECT_EQ(r.line_search_halvings, 22);
  EXPECT_EQ(r.line_search_probes, 33);
  EXPECT_EQ(r.projected_fallbacks, 44);
  EXPECT_EQ(r.extrapolations, 55);
  EXPECT_EQ(r.chord_steps, 66);
  EXPECT_EQ(r.symbolic_analyses, 77);
  EXPECT_TRUE(r.roundoff_limited);
  EXPECT_EQ(r.floor_velocity, 10.25);
  EXPECT_DOUBLE_EQ(r.gradient_seconds, 1.1);
  EXPECT_DOUBLE_EQ(r.assembly_seconds, 2.2);
  EXPECT_DOUBLE_EQ(r.factorization_seconds, 3.3);
  EXPECT_DOUBLE_EQ(r.solve_seconds, 4.4);
  EXPECT_DOUBLE_EQ(r.line_search_seconds, 5.5);
  // And the other way round: the later solve's false flags win too.
  NewtonResult back = result(10);
  back.append(result(1));
  EXPECT_FALSE(back.exact_factor);
  EXPECT_FALSE(back.roundoff_limited);
}

TEST(FrictionIterationsErrors, OutOfRangeCountsAreRefusedByValue) {
  const TetMesh mesh = box();
  const MaterialField field = MaterialField::uniform(mesh.num_tets(), 1e8, 0.3, 1000);
  for (int k : {0, -1, 101}) {
    try {
      Simulator sim(mesh, field, floor_settings(false, k));
      ADD_FAILURE() << "friction iterations " << k << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("friction iterations " + std::to_string(k)),
                std::string::npos)
          << e.what();
    }
  }
  EXPECT_NO_THROW(Simulator(mesh, field, floor_settings(false, 100)));
}

}  // namespace
}  // namespace rbaa
