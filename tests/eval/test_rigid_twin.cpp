// The rigid twin of a scene (eval/rigid_twin.hpp): its world carries the scene's friction per
// plane, obstacle mesh and pair of bodies, as the deformable simulator has it.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "rbaa/eval/rigid_twin.hpp"
#include "rbaa/rigid/rigid_simulation.hpp"
#include "rbaa/scene/scene.hpp"

namespace rbaa {
namespace {

// Three bodies over a floor with its own coefficient and a wall with contact.friction's; the
// bodies have contact.friction's 0.2 except the pairs contact.pairs names.
TEST(RigidTwin, TheWorldCarriesTheScenesFrictionPerPlaneAndPairOfBodies) {
  const Scene scene = parse_scene(
      "mesh: {shape: cube, side: 0.1, target_tets: 300}\n"
      "object: {position: [0, 0, 0.2]}\n"
      "bodies:\n"
      "  - {name: second, mesh: {shape: cube, side: 0.05, target_tets: 100}, position: [0.3, 0, "
      "0.2]}\n"
      "  - {name: third, mesh: {shape: cube, side: 0.05, target_tets: 100}, position: [0, 0.3, "
      "0.2]}\n"
      "obstacles:\n"
      "  planes:\n"
      "    - {normal: [0, 0, 1], offset: 0, friction: 0.7}\n"
      "    - {normal: [1, 0, 0], offset: -1}\n"
      "contact:\n"
      "  friction: 0.2\n"
      "  pairs:\n"
      "    - {bodies: [second, object], friction: 0.6}\n"
      "    - {bodies: [third, second], friction: 0}\n",
      "test.yaml", "");
  const RigidWorld world = rigid_world(scene, std::vector<RigidBody>(3));
  using Side = RigidContactSide;
  auto mu = [&](Side x, Side y) { return rigid_friction(world, x, y); };
  const Side object{Side::Kind::kBody, 0}, second{Side::Kind::kBody, 1},
      third{Side::Kind::kBody, 2};
  EXPECT_EQ(mu(object, {Side::Kind::kPlane, 0}), 0.7);
  EXPECT_EQ(mu(third, {Side::Kind::kPlane, 0}), 0.7);
  EXPECT_EQ(mu(second, {Side::Kind::kPlane, 1}), 0.2);
  EXPECT_EQ(mu(object, second), 0.6);
  EXPECT_EQ(mu(second, object), 0.6);
  EXPECT_EQ(mu(second, third), 0.0);
  EXPECT_EQ(mu(object, third), 0.2);  // the default
  EXPECT_THROW(mu(object, {Side::Kind::kBody, 3}), std::out_of_range);
}

}  // namespace
}  // namespace rbaa
