// Issue 15's bar: the speed work (the rigid predictor and the rigid Newton sub-step) must leave
// trajectories and gradients unchanged within Newton's tolerance. Each shipped config at a coarse
// mesh is run twice, with `newton.rigid_predictor` on (the default) and off (Newton as it was
// before the speed work: the BDF extrapolation as the initial guess, no sub-step), and the final
// positions, the objective and its adjoint gradient are compared.

#include <gtest/gtest.h>

#include <Eigen/Core>

#include <cstdio>
#include <string>

#include "rbaa/diff/trajectory_gradient.hpp"
#include "rbaa/diff/trajectory_objective.hpp"
#include "rbaa/material/design_space.hpp"
#include "rbaa/scene/scene.hpp"
#include "rbaa/scene/scene_mesh.hpp"
#include "rbaa/scene/scene_world.hpp"
#include "rbaa/sim/barrier_stiffness.hpp"
#include "rbaa/sim/observables.hpp"
#include "rbaa/sim/simulator.hpp"
#include "support/intersection_free.hpp"

namespace rbaa {
namespace {

struct Run {
  double objective = 0;
  Eigen::VectorXd gradient, q_end;
  double tolerance_m_per_s = 0, time_step = 0, gap = 0;
  int steps = 0, newton_iterations = 0;
};

Run run_config(const std::string& name, bool predictor) {
  const Scene scene = load_scene(std::string(RBAA_SOURCE_DIR) + "/configs/" + name + ".yaml",
                                 {"mesh.target_tets=300",
                                  std::string("newton.rigid_predictor=") + (predictor ? "true" : "false")});
  const TetMesh mesh = make_scene_mesh(scene);
  const SimulationSettings settings = simulation_settings(scene, scene_barrier_stiffness(scene, mesh));
  const Eigen::VectorXd q0 = Eigen::Map<const Eigen::VectorXd>(mesh.V.data(), 3 * mesh.num_vertices());
  const Eigen::VectorXd v0 = rigid_velocities(q0, scene.position, scene.velocity, scene.angular_velocity);
  Simulator ref(mesh,
                MaterialField::uniform(mesh.num_tets(), scene.reference_Y, scene.reference_nu,
                                       scene.reference_rho),
                settings);
  const Trajectory reference = ref.run(q0, v0);
  const test::IntersectionCheck check(mesh, settings);
  EXPECT_EQ(check.first_intersection(reference), "") << name << " reference";
  auto objective =
      UndirectedTrajectoryObjective::from_reference(mesh, scene.reference_rho, reference.q.back());
  const DesignSpace ds(mesh, design_space_options(scene));
  TrajectoryGradientFunction f(mesh, settings, q0, v0, ds, objective);
  Run r;
  r.objective = f.evaluate(ds.initial_theta(true), &r.gradient);
  const Trajectory& t = f.last().trajectory;
  EXPECT_EQ(check.first_intersection(t), "") << name;
  r.q_end = t.q.back();
  r.gap = objective->gap(r.q_end);
  r.steps = t.num_steps();
  r.time_step = t.time_step;
  for (const StepStats& s : t.steps) r.newton_iterations += s.newton_iterations;
  r.tolerance_m_per_s = f.simulator().velocity_tolerance();
  return r;
}

void expect_unchanged(const std::string& name) {
  const Run fast = run_config(name, true), plain = run_config(name, false);
  ASSERT_EQ(fast.steps, plain.steps);
  // Each step converges to |dq|_inf / h below the tolerance: the two runs' states may differ by
  // about a tolerance-sized step per step, tol * h * steps, before the contact amplifies it.
  const double position_bar = fast.tolerance_m_per_s * fast.time_step * fast.steps;
  const double dq = (fast.q_end - plain.q_end).lpNorm<Eigen::Infinity>();
  const double dobj = std::abs(fast.objective - plain.objective) / std::abs(plain.objective);
  const double dg = (fast.gradient - plain.gradient).norm() / plain.gradient.norm();
  // C = -gap^2 / L^2, so |dC| / |C| = 2 |d gap| / gap <= 2 |dq| / gap; the gradient, the
  // adjoint through the same states, moves by up to ~15 times |dq| / gap (measured 0.03 to 14).
  const double relative_bar = 100 * position_bar / plain.gap;
  std::printf("%-6s Newton iterations %4d (plain %4d); gap %.3e m; final positions differ by "
              "%.2e m (tol h steps %.2e m); objective by %.2e, gradient by %.2e relative "
              "(tol h steps / gap %.2e)\n",
              name.c_str(), fast.newton_iterations, plain.newton_iterations, plain.gap, dq,
              position_bar, dobj, dg, position_bar / plain.gap);
  EXPECT_LT(fast.newton_iterations, plain.newton_iterations) << name;
  EXPECT_LE(dq, 100 * position_bar) << name;
  EXPECT_LE(dobj, 2 * relative_bar) << name;
  EXPECT_LE(dg, 10 * relative_bar) << name;
}

TEST(FastNewtonUnchanged, Ball) { expect_unchanged("ball"); }
TEST(FastNewtonUnchanged, Star) { expect_unchanged("star"); }
TEST(FastNewtonUnchanged, Bunny) { expect_unchanged("bunny"); }
TEST(FastNewtonUnchanged, Cube) { expect_unchanged("cube"); }

}  // namespace
}  // namespace rbaa
