// demonstration.object_copies: bodies that are copies of each run's object (the cube stack of the
// paper, whose four cubes are all adversarial). Bad input is one line naming the file, the line and
// the key; with_object_copies marks them; make_world gives each the object's mesh at the body's
// pose and materials() the object's materials; the PolyFEM export writes them so.

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <string>
#include <vector>

#include "rbaa/error.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/scene/polyfem_model.hpp"
#include "rbaa/scene/scene.hpp"
#include "rbaa/scene/scene_mesh.hpp"
#include "rbaa/scene/scene_world.hpp"
#include "scene/scene_errors.hpp"

namespace rbaa {
namespace {

// The object, a cube turned 45 deg about x, above a ground; `low`, a sphere, turned 30 deg about
// z; `high`, a small cube at height high_z; `extra` more bodies.
std::string scene_text(const std::string& copies, const std::string& extra = "",
                       double high_z = 0.05) {
  return "mesh: {shape: cube, side: 0.05, target_tets: 100}\n"
         "object: {position: [0, 0, 0.3], velocity: [0, 0, -1], rotation: {axis: [1, 0, 0], "
         "angle_deg: 45}}\n"
         "bodies:\n"
         "  - {name: low, mesh: {shape: sphere, radius: 0.03, target_tets: 100}, position: [0.2, "
         "0, 0.05], velocity: [0, 1, 0], rotation: {axis: [0, 0, 1], angle_deg: 30}}\n"
         "  - {name: high, mesh: {shape: cube, side: 0.02, target_tets: 50}, position: [-0.2, 0, " +
         std::to_string(high_z) + "]}\n" + extra +
         "obstacles: {planes: [{normal: [0, 0, 1], offset: 0}]}\n"
         "demonstration:\n  figure: angle\n" +
         copies;
}

// `spare` with a materials file, `arm` driven (for the bad-input cases: neither is meshed).
const char* kMoreBodies =
    "  - {name: spare, mesh: {shape: cube, side: 0.02}, position: [0.5, 0, 0.05], materials: "
    "spare.csv}\n"
    "  - {name: arm, mesh: {shape: cube, side: 0.02}, position: [-0.5, 0, 0.05], driven: "
    "{vertices: [0]}}\n";

TEST(SceneObjectCopies, AreReadAndMarkedByWithObjectCopies) {
  const Scene s = parse_scene(scene_text("  object_copies: [high]\n", kMoreBodies), "test.yaml", "");
  ASSERT_EQ(s.demonstration.object_copies, (std::vector<std::string>{"high"}));
  // Parsing alone marks nothing: only the verbs that want copies ask for them.
  for (const BodySpec& b : s.bodies) EXPECT_FALSE(b.object_copy) << b.name;
  const Scene c = with_object_copies(s);
  EXPECT_FALSE(c.bodies[0].object_copy);
  EXPECT_TRUE(c.bodies[1].object_copy);
  EXPECT_FALSE(c.bodies[2].object_copy);
  EXPECT_FALSE(c.bodies[3].object_copy);
  EXPECT_EQ(with_object_copies(parse_scene(scene_text("  object_copies: [high, low]\n"),
                                           "test.yaml", ""))
                .bodies[0]
                .object_copy,
            true);
  // None, and an empty list (what --set=demonstration.object_copies=[] gives), are none.
  EXPECT_TRUE(parse_scene(scene_text(""), "test.yaml", "").demonstration.object_copies.empty());
  EXPECT_TRUE(parse_scene(scene_text("  object_copies: []\n"), "test.yaml", "")
                  .demonstration.object_copies.empty());
  EXPECT_TRUE(parse_scene(scene_text("  object_copies: [low]\n"), "test.yaml", "",
                          {"demonstration.object_copies=[]"})
                  .demonstration.object_copies.empty());
}

TEST(SceneObjectCopies, BadInputIsOneLineNamingFileLineAndKey) {
  struct Case {
    std::string copies, fragment;
  };
  const std::vector<Case> cases = {
      {"  object_copies: [low, ghost]\n",
       "'ghost' names no body (the bodies are: low, high, spare, arm)"},
      {"  object_copies: [object]\n", "'object' is the object itself"},
      {"  object_copies: [low, high, low]\n", "'low' is listed twice"},
      {"  object_copies: low\n", "expected a list of body names"},
      {"  object_copies: [[low]]\n", "'' names no body"},
      {"  object_copies: [spare]\n", "'spare' has a materials file"},
      {"  object_copies: [arm]\n", "'arm' is driven"},
  };
  for (const Case& c : cases) {
    const std::string text = scene_text(c.copies, kMoreBodies);
    const std::string what = test::scene_parse_error(text);
    EXPECT_NE(what.find(c.fragment), std::string::npos) << c.copies << " -> " << what;
    EXPECT_NE(what.find("key 'demonstration.object_copies'"), std::string::npos) << what;
    // The line of object_copies, the last.
    const auto line = std::count(text.begin(), text.end(), '\n');
    EXPECT_EQ(what.rfind("test.yaml:" + std::to_string(line) + ": ", 0), 0u) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

TEST(SceneObjectCopies, AnAttackOnAnotherBodyCannotTakeTheObjectsPlace) {
  const Scene s = parse_scene(scene_text("  object_copies: [high]\n"), "test.yaml", "");
  EXPECT_EQ(swap_object(s, "object").object_name, "object");  // the object itself: no swap
  try {
    swap_object(s, "low");
    FAIL() << "swap_object accepted a scene with object_copies";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("test.yaml: key 'demonstration.object_copies': ", 0), 0u) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

TetMesh body_mesh(const SceneWorld& w, int i) {
  const Body& b = w.bodies.at(i);
  TetMesh m;
  m.V = w.mesh.V.middleRows(b.vertex_begin, b.num_vertices());
  m.T = w.mesh.T.middleRows(b.element_begin, b.num_elements()).array() - b.vertex_begin;
  return m;
}

TEST(SceneObjectCopies, ACopyIsTheObjectsMeshAtItsOwnPoseWithTheObjectsMaterials) {
  const Scene s = with_object_copies(
      parse_scene(scene_text("  object_copies: [low, high]\n"), "test.yaml", ""));
  const TetMesh object = make_scene_mesh(s);
  const SceneWorld w = make_world(s, object);
  ASSERT_EQ(w.bodies.size(), 3u);
  EXPECT_EQ(w.copies, (std::vector<int>{1, 2}));
  const auto R = [](const Eigen::Vector3d& axis, double deg) {
    return Eigen::AngleAxisd(deg * M_PI / 180, axis.normalized()).toRotationMatrix();
  };
  const Eigen::Matrix3d Ro = R(s.rotation_axis, s.rotation_angle_deg);
  for (int i : {1, 2}) {
    const BodySpec& spec = s.bodies[i - 1];
    const Body& b = w.bodies[i];
    const TetMesh copy = body_mesh(w, i);
    ASSERT_EQ(copy.num_tets(), object.num_tets()) << spec.name;
    ASSERT_EQ(copy.num_vertices(), object.num_vertices()) << spec.name;
    EXPECT_EQ(copy.T, object.T) << spec.name;
    // Turned from the object's rotation to the body's, moved to its position.
    const Eigen::Matrix3d Rb = R(spec.rotation_axis, spec.rotation_angle_deg);
    for (int v = 0; v < copy.num_vertices(); ++v) {
      const Eigen::Vector3d expected =
          Rb * Ro.transpose() * (object.V.row(v).transpose() - s.position) + spec.position;
      ASSERT_LT((copy.V.row(v).transpose() - expected).norm(), 1e-15) << spec.name << " " << v;
    }
    EXPECT_LT((compute_moments(copy, 1.0).centre_of_mass() - spec.position).norm(), 1e-15);
    // Its own pose and motion.
    EXPECT_EQ(b.centre, spec.position);
    EXPECT_EQ(b.velocity, spec.velocity);
  }
  // `high` is not turned: the object's cube turned back is axis-aligned again, side 0.05 m.
  const TetMesh high = body_mesh(w, 2);
  const Eigen::RowVector3d extent = high.V.colwise().maxCoeff() - high.V.colwise().minCoeff();
  EXPECT_NEAR(extent.maxCoeff(), 0.05, 1e-12);
  EXPECT_NEAR(extent.minCoeff(), 0.05, 1e-12);

  // The copies' elements take the object's materials; the others keep theirs.
  MaterialField field = MaterialField::uniform(object.num_tets(), 3e9, 0.25, 900, 1.0);
  for (int e = 0; e < field.size(); ++e) {
    field.Y[e] = 1e9 + e;
    field.rho[e] = 800 + e;
    field.alpha[e] = e % 2 ? 1.0 : 0.5;
  }
  const MaterialField all = w.materials(field);
  for (int i : {1, 2}) {
    const Body& b = w.bodies[i];
    EXPECT_EQ(all.Y.segment(b.element_begin, b.num_elements()), field.Y);
    EXPECT_EQ(all.nu.segment(b.element_begin, b.num_elements()), field.nu);
    EXPECT_EQ(all.rho.segment(b.element_begin, b.num_elements()), field.rho);
    EXPECT_EQ(all.alpha.segment(b.element_begin, b.num_elements()), field.alpha);
  }
}

TEST(SceneObjectCopies, ACopyStartingInTheGroundIsRefusedNamingIt) {
  // `high` at z = 0.02: its own 0.02 m cube clears the ground, the object's 0.05 m one does not.
  const Scene own = parse_scene(scene_text("  object_copies: [high]\n", "", 0.02), "test.yaml", "");
  EXPECT_NO_THROW(make_world(own, make_scene_mesh(own)));
  const Scene copies = with_object_copies(own);
  try {
    make_world(copies, make_scene_mesh(copies));
    FAIL() << "a copy in the ground was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("test.yaml: body 'high' (a copy of the object) starts intersecting "
                        "obstacles.planes[0]"),
              std::string::npos)
        << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

TEST(SceneObjectCopies, ThePolyfemExportWritesTheCopiesWithTheObjectsMaterials) {
  const Scene s = with_object_copies(
      parse_scene(scene_text("  object_copies: [high]\n"), "test.yaml", ""));
  ExportObject object = reference_export_object(s);
  object.materials.Y.setConstant(4e9);
  object.materials.rho.setConstant(1500);
  const PolyfemScene model = polyfem_model(s, object);
  ASSERT_EQ(model.bodies.size(), 3u);
  const Body& copy = model.bodies[2];
  EXPECT_EQ(copy.num_elements(), object.mesh.num_tets());
  EXPECT_TRUE((model.E.segment(copy.element_begin, copy.num_elements()).array() == 4e9).all());
  EXPECT_TRUE((model.rho.segment(copy.element_begin, copy.num_elements()).array() == 1500).all());
  const Body& low = model.bodies[1];
  EXPECT_TRUE((model.E.segment(low.element_begin, low.num_elements()).array() == s.reference_Y).all());
}

// An attack's object designed unturned is turned into a scene that turns its object (evaluate
// and the PolyFEM export call this); one already turned, or a scene that turns nothing, is left
// as it is, bit for bit.
TEST(ScenePose, AnUnturnedAttackObjectIsTurnedIntoATurnedScenesPose) {
  const std::string cube = "mesh: {shape: cube, side: 0.1, target_tets: 200}\ngravity: off\n";
  const Scene plain = parse_scene(cube + "object: {position: [0, 0, 1]}\n", "plain.yaml", "");
  const Scene turned = parse_scene(
      cube + "object: {position: [0, 0, 1], rotation: {axis: [1, 0, 0], angle_deg: 45}}\n",
      "turned.yaml", "");
  const TetMesh unturned_mesh = make_scene_mesh(plain);
  const TetMesh turned_mesh = make_scene_mesh(turned);
  const TetMesh t = turn_into_scene_pose(turned, turned_mesh, unturned_mesh);
  // Both turned about the same middle (the cube's centroid is its middle): the same vertices.
  EXPECT_LT((t.V - turned_mesh.V).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_TRUE(turn_into_scene_pose(turned, turned_mesh, turned_mesh).V == turned_mesh.V);
  EXPECT_TRUE(turn_into_scene_pose(plain, unturned_mesh, unturned_mesh).V == unturned_mesh.V);
  // A shape that matches neither way is returned unchanged (the caller's surface check refuses it).
  TetMesh stretched = unturned_mesh;
  stretched.V.col(0) *= 1.1;
  EXPECT_TRUE(turn_into_scene_pose(turned, turned_mesh, stretched).V == stretched.V);
}

}  // namespace
}  // namespace rbaa
