// The paper's directed attack on a coarse bat (issue 16): a few dozen Adam iterations on the bat's
// materials move the struck ball's final x towards 0 while the bat keeps the reference bat's
// moments; the ball's own materials are not designed.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "rbaa/opt/attack.hpp"
#include "rbaa/scene/scene.hpp"

namespace rbaa {
namespace {

// configs/bat.yaml on coarse meshes (as tests/scene/test_bat_swing.cpp): a 600-tet bat whose
// drive takes the 14 vertices nearest the axis within 20 mm of the knob's end, a 200-tet ball,
// h = 2 ms, over the config's 0.45 s; 24 iterations, no polish.
const std::vector<std::string> kCoarseBat = {
    "mesh.target_tets=600", "object.driven.vertices.depth=0.02",
    "bodies=[{name: ball, mesh: {shape: sphere, radius: 0.0366, target_tets: 200}, "
    "position: [0.75, 1.25, 0.245], velocity: [0, -6, 0]}]",
    "time.step=0.002", "attack.iterations=24", "attack.polish_iterations=0"};

TEST(AttackBat, DrivesTheStruckBallsFinalXTowardsZero) {
  const Scene scene =
      load_scene(std::string(RBAA_SOURCE_DIR) + "/configs/bat.yaml", kCoarseBat);
  const AttackResult r = run_attack(scene, {});
  ASSERT_EQ(r.loop.progress.size(), 24u);
  EXPECT_EQ(r.attacked_body, "object");
  EXPECT_EQ(r.scored_body, "ball");
  const double x_ref = r.scored_com_reference.x();
  const double x_cont = r.scored_com_continuous.x();
  const double x_final = r.scored_com_final.x();
  std::printf("coarse bat: ball's final x %.4f m (reference bat) -> %.4f (continuous) -> %.4f "
              "(final object); objective %.2f -> %.2f; moments %.2e\n",
              x_ref, x_cont, x_final, r.objective_initial, r.objective_final,
              r.max_normalized_residual);
  // The reference bat sends the ball off towards +x: its final x is past its start (0.75 m).
  EXPECT_GT(x_ref, 0.75);
  // Measured once (2026-11-26, `rbaa attack --config=configs/bat.yaml` with these overrides, the
  // elements at the driven vertices held solid): 1.2211 -> 1.1856 m (continuous) -> 1.1873 m
  // (rounded, re-fit). Assert at least half of each move towards 0.
  EXPECT_GT(x_ref - x_cont, 0.5 * (1.2211 - 1.1856)) << x_ref << " -> " << x_cont;
  EXPECT_GT(x_ref - x_final, 0.5 * (1.2211 - 1.1873)) << x_ref << " -> " << x_final;
  EXPECT_LT(r.objective_final, r.objective_initial);
  // The bat's moments stay the reference bat's (projected steps, then the re-fit).
  double worst = 0;
  for (const ProgressRow& row : r.loop.progress) worst = std::max(worst, row.max_moment_residual);
  EXPECT_LT(worst, 1e-11);
  EXPECT_LE(r.max_normalized_residual, 1e-10);
  // Perceptually rigid: every material within the paper's bounds (Y >= 25 GPa).
  const MaterialField& m = r.post.solid.materials;
  EXPECT_GE(m.Y.minCoeff(), scene.Y_range.lo);
  EXPECT_LE(m.Y.maxCoeff(), scene.Y_range.hi);
  EXPECT_GE(scene.Y_range.lo, 2.5e10);
}

}  // namespace
}  // namespace rbaa
