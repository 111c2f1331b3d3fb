// The rigid twin of a scene (eval/rigid_twin.hpp): its world carries the scene's friction per
// plane, obstacle mesh and pair of bodies, as the deformable simulator has it, and objects equal
// up to round-off get identical twins.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <ostream>
#include <string>
#include <vector>

#include "rbaa/eval/rigid_twin.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/material/material_field.hpp"
#include "rbaa/rigid/rigid_simulation.hpp"
#include "rbaa/scene/scene.hpp"
#include "rbaa/scene/scene_mesh.hpp"

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

// An object and a copy with the same surface and moments up to round-off, each twin built from its
// own mesh as rbaa evaluate builds the reference's and the adversarial's: the hoop demo's object
// turned about the world's origin and back (other last bits in every coordinate, as an attack's
// object placed by another sequence of turns and moves has). Issue 17's bar: the twins stay
// identical to 1e-9 m over the scene, here among the backboard's and rim's triangle meshes.
// Before the collision shape was fitted to rounded surface vertices, Bullet's hull computer
// (which truncates to 1/10216 of the extent) put the ball's twins up to 9e-6 m apart and a turned
// cube's up to 2 m.
struct RoundOffCopy {
  std::string name;
  std::vector<std::string> overrides;  ///< on configs/demos/ball_hoop.yaml
  friend void PrintTo(const RoundOffCopy& c, std::ostream* out) { *out << c.name; }
};

class RoundOffCopyTwin : public testing::TestWithParam<RoundOffCopy> {};

TEST_P(RoundOffCopyTwin, StaysWithinANanometreOfTheOriginalsTwinAmongTriangleMeshes) {
  const Scene scene = load_scene(std::string(RBAA_SOURCE_DIR) + "/configs/demos/ball_hoop.yaml",
                                 GetParam().overrides);
  const TetMesh original = make_scene_mesh(scene);
  const Eigen::VectorXd density =
      MaterialField::uniform(original.num_tets(), scene.reference_Y, scene.reference_nu,
                             scene.reference_rho, 1.0)
          .effective_density();
  auto twin = [&](const TetMesh& mesh, std::vector<RigidTouch>* touches) {
    return simulate_rigid_bodies(rigid_mass_properties(compute_moments(mesh, density)),
                                 rigid_shape_from_surface(mesh), scene, RigidSettings{},
                                 scene.duration, {}, touches)
        .front();
  };
  std::vector<RigidTouch> touches;
  const std::vector<RigidState> reference = twin(original, &touches);
  // The twin meets the triangle meshes (or the comparison would test free flight only).
  EXPECT_TRUE(std::any_of(touches.begin(), touches.end(), [](const RigidTouch& t) {
    return t.second.kind == RigidContactSide::Kind::kMesh;
  }));
  for (const double angle : {0.7, 1.3, 2.1}) {
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(angle, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    TetMesh copy = original;
    copy.V = (original.V * R.transpose()) * R;
    ASSERT_LE((copy.V - original.V).cwiseAbs().maxCoeff(), 1e-14);
    const std::vector<RigidState> states = twin(copy, nullptr);
    ASSERT_EQ(states.size(), reference.size());
    double gap = 0;
    for (size_t k = 0; k < states.size(); ++k) {
      gap = std::max(gap, (states[k].position - reference[k].position).norm());
    }
    EXPECT_LE(gap, 1e-9) << GetParam().name << " turned by " << angle << " rad and back";
  }
}

INSTANTIATE_TEST_SUITE_P(
    Shapes, RoundOffCopyTwin,
    testing::Values(RoundOffCopy{"Sphere", {"mesh.target_tets=1500"}},
                    RoundOffCopy{"TurnedCube",
                                 {"mesh.target_tets=1500", "mesh.shape=cube", "mesh.side=0.2",
                                  "object.rotation={axis: [1, 1, 0], angle_deg: 30}"}}),
    [](const testing::TestParamInfo<RoundOffCopy>& info) { return info.param.name; });

}  // namespace
}  // namespace rbaa
