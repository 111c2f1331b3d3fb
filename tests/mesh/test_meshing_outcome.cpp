#include <gtest/gtest.h>

#include <string>

#include "rbaa/mesh/meshing_outcome.hpp"
#include "rbaa/mesh/tetrahedralize.hpp"

namespace rbaa {
namespace {

MeshingOutcome outcome(int target, int tets, std::vector<MeshingAttempt> attempts) {
  MeshingOutcome o;
  o.target_tets = target;
  o.tolerance = 0.05;
  o.tets = tets;
  o.attempts = std::move(attempts);
  return o;
}

bool has(const std::string& text, const std::string& piece) {
  return text.find(piece) != std::string::npos;
}

TEST(MeshingOutcome, SaysWhyTheTargetWasMissed) {
  EXPECT_TRUE(outcome(1000, 1040, {{0.1, 1040, ""}}).within_tolerance());
  EXPECT_EQ(outcome(1000, 1040, {{0.1, 1040, ""}}).shortfall(), "");

  // Cells twice as large should give ~8x fewer tets; 640 -> 578 is a floor.
  const std::string floor = outcome(200, 578, {{0.19, 640, ""}, {0.38, 578, ""}}).shortfall();
  EXPECT_TRUE(has(floor, "the surface's detail sets a floor")) << floor;
  EXPECT_TRUE(has(floor, "640 to 578 tets")) << floor;
  // Every coarser size failed to mesh: a floor as well, with the fault.
  const std::string failed =
      outcome(100, 582, {{0.44, 0, "star: tet 74 is degenerate"}, {0.25, 582, ""}}).shortfall();
  EXPECT_TRUE(has(failed, "floor")) << failed;
  EXPECT_TRUE(has(failed, "tet 74 is degenerate")) << failed;
  // Neighbouring sizes on both sides of the band.
  const std::string jump = outcome(100, 123, {{0.0186, 123, ""}, {0.0197, 64, ""}}).shortfall();
  EXPECT_TRUE(has(jump, "jumps across the target")) << jump;
  EXPECT_TRUE(has(jump, "123 tets")) << jump;
  EXPECT_TRUE(has(jump, "64 at")) << jump;
  // Still falling as size^-3 when the attempts ran out.
  const std::string slow = outcome(100, 400, {{0.1, 3200, ""}, {0.2, 400, ""}}).shortfall();
  EXPECT_TRUE(has(slow, "ran out")) << slow;
  for (const std::string& s : {floor, failed, jump, slow}) EXPECT_FALSE(has(s, "\n")) << s;
}

// The star's sharp edges keep about 580 tets at any cell size.
TEST(MeshingOutcome, TheStarCannotBeMeshedCoarserThanItsFloor) {
  MeshingOutcome o;
  const TetMesh mesh = mesh_shape("star", 200, {}, &o);
  EXPECT_EQ(o.target_tets, 200);
  EXPECT_EQ(o.tets, mesh.num_tets());
  EXPECT_GT(mesh.num_tets(), 400);
  EXPECT_FALSE(o.within_tolerance());
  EXPECT_TRUE(has(o.shortfall(), "floor")) << o.shortfall();

  MeshingOutcome met;
  mesh_shape("star", 1506, {}, &met);
  EXPECT_TRUE(met.within_tolerance()) << met.tets;
  EXPECT_EQ(met.shortfall(), "");
}

}  // namespace
}  // namespace rbaa
