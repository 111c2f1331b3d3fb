// Newton's extrapolation (newton_solver.cpp): bench_contact's four stiff 5 cm cubes (~500 tets
// each) stacked 0.5 mm apart on a floor, one 0.01 s step, where the PSD-projected contact
// Hessians add curvature the energy lacks and plain Newton creeps: 47 iterations without
// extrapolation, 14 with it (measured 2026-11-26). At ~150 tets per cube the stack takes 12 .. 13
// either way, so the finer stack is the one that shows it.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "rbaa/mesh/tetrahedralize.hpp"
#include "rbaa/sim/barrier_stiffness.hpp"
#include "rbaa/sim/simulator.hpp"
#include "support/intersection_free.hpp"

namespace rbaa {
namespace {

TEST(NewtonExtrapolation, AStackOfCubesSettlesInFewIterations) {
  ShapeParameters p;
  p.side = 0.05;
  const TetMesh cube = mesh_shape("cube", 500, p);
  const int n = 4;
  TetMesh stack;
  stack.V.resize(n * cube.num_vertices(), 3);
  stack.T.resize(n * cube.num_tets(), 4);
  std::vector<Body> bodies;
  const double lowest = cube.V.col(2).minCoeff();
  for (int b = 0; b < n; ++b) {
    Body body;
    body.name = "cube " + std::to_string(b);
    body.vertex_begin = b * cube.num_vertices();
    body.vertex_end = (b + 1) * cube.num_vertices();
    body.element_begin = b * cube.num_tets();
    body.element_end = (b + 1) * cube.num_tets();
    stack.V.middleRows(body.vertex_begin, cube.num_vertices()) =
        cube.V.rowwise() + Eigen::RowVector3d(0, 0, 5e-4 - lowest + b * (0.05 + 5e-4));
    stack.T.middleRows(body.element_begin, cube.num_tets()) = cube.T.array() + body.vertex_begin;
    bodies.push_back(body);
  }
  SimulationSettings s;
  s.time_step = 0.01;
  s.num_steps = 1;
  s.d_hat = 1e-3;
  s.planes = {Plane{}};
  s.bodies = bodies;
  s.kappa = barrier_stiffness_from_energy(2500 * std::pow(0.05, 3) * n, std::sqrt(2 * 9.8 * 0.1), s.d_hat);
  Simulator sim(stack, MaterialField::uniform(stack.num_tets(), 1e10, 0.3, 2500), s);
  const Eigen::VectorXd q0 = sim.rest_positions();
  const Trajectory t = sim.run(q0, Eigen::VectorXd::Zero(q0.size()));
  int iterations = 0, extrapolations = 0;
  for (const StepStats& st : t.steps) {
    std::printf("step: %d Newton iterations, %d extrapolations, %d contact pairs\n", st.newton_iterations,
                st.extrapolations, st.active_pairs);
    iterations += st.newton_iterations;
    extrapolations += st.extrapolations;
  }
  EXPECT_GT(extrapolations, 0);
  EXPECT_LE(iterations, 25);  // 47 without extrapolation
  EXPECT_EQ(test::first_intersection(stack, s, t), "");
}

}  // namespace
}  // namespace rbaa
