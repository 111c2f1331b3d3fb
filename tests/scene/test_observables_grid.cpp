// Observables of a run with contact-resolving steps sit on the grid of h, and an impact shorter
// than a step of h still shows in them: a grid position's contact distances are the smallest
// over the sub-steps since the previous one, so the bounce is found and its restitution read.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "rbaa/scene/simulate.hpp"
#include "rbaa/sim/barrier_stiffness.hpp"
#include "rbaa/sim/observables.hpp"
#include "sim/mesh_fixtures.hpp"
#include "support/intersection_free.hpp"

namespace rbaa {
namespace {

TEST(ObservablesOnTheGrid, AnImpactBetweenGridPositionsIsABounce) {
  const double r = 0.121, h = 0.01, speed = 5.0, gap = 0.03;
  const TetMesh mesh = test::ball_mesh(r, 3, Eigen::Vector3d(0, 0, r + gap));
  SimulationSettings s;
  s.time_step = h;
  s.num_steps = 6;
  s.gravity.setZero();
  s.planes = {Plane{}};
  s.contact_substeps = 256;
  s.kappa = barrier_stiffness_from_energy(2500 * 4.0 / 3.0 * M_PI * r * r * r, speed, s.d_hat);
  Simulator sim(mesh, MaterialField::uniform(mesh.num_tets(), 1e13, 0.28, 2500), s);
  const Eigen::VectorXd q0 = test::positions(mesh);
  const Trajectory t = sim.run(q0, rigid_velocities(q0, Eigen::Vector3d(0, 0, r + gap),
                                                    Eigen::Vector3d(0, 0, -speed),
                                                    Eigen::Vector3d::Zero()));
  EXPECT_EQ(test::first_intersection(mesh, s, t), "");  // every sub-step
  const std::vector<StepObservables> o = compute_observables(sim, t);
  ASSERT_EQ(o.size(), static_cast<std::size_t>(s.num_steps + 1));
  // The ball meets the plane within the first step (it flies 5 cm of the 3 cm gap) and is gone
  // again before its end: no position of the grid is itself within d_hat.
  int grid_in_contact = 0, any_in_contact = 0;
  for (int k : t.grid_frames()) grid_in_contact += t.steps.empty() || k == 0 ? 0 : t.steps[k - 1].active_pairs > 0;
  for (const StepStats& st : t.steps) any_in_contact += st.active_pairs > 0;
  std::vector<std::vector<double>> distances;
  std::vector<Eigen::Vector3d> velocities;
  for (const StepObservables& x : o) {
    EXPECT_NEAR(x.time, std::round(x.time / h) * h, 1e-12);
    distances.push_back(x.plane_distance);
    velocities.push_back(x.com_velocity);
  }
  std::printf("grid positions in contact %d, sub-steps in contact %d, first grid distance %.3e m\n",
              grid_in_contact, any_in_contact, o[1].plane_distance[0]);
  ASSERT_GT(any_in_contact, 0);
  EXPECT_EQ(grid_in_contact, 0) << "the scene no longer tests an impact between grid positions";
  EXPECT_LT(o[1].plane_distance[0], s.d_hat);
  const std::vector<Bounce> b = find_bounces(distances, velocities, s.planes, s.d_hat, s.gravity, h);
  ASSERT_EQ(b.size(), 1u);
  EXPECT_EQ(b[0].kind, BounceKind::kBounce) << b[0].note;
  const double e = o.back().com_velocity.z() / speed;
  std::printf("restitution: bounce %.4f, final velocity %.4f\n", b[0].restitution, e);
  EXPECT_NEAR(b[0].restitution, e, 1e-9);
  EXPECT_GT(e, 0.9);
}

}  // namespace
}  // namespace rbaa
