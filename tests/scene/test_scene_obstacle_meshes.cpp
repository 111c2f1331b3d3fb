// obstacles.meshes: files read (OBJ, OFF; open surfaces), placed by scale, rotation and position;
// every bad input a one-line error naming the config's line and the file's; a body that starts
// within d_hat of a mesh obstacle or inside it refused, naming the obstacle; the kappa rule sees
// mesh floors; the fingerprint sees the file.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "io/io_test_support.hpp"
#include "rbaa/error.hpp"
#include "rbaa/scene/scene.hpp"
#include "rbaa/scene/scene_fingerprint.hpp"
#include "rbaa/scene/scene_mesh.hpp"
#include "rbaa/sim/barrier_stiffness.hpp"

namespace rbaa {
namespace {

// A folder of this process's own (test::ScratchDir, made in the first test that asks, removed at
// exit): ctest runs the tests as separate processes side by side.
std::string dir() {
  static const test::ScratchDir folder;
  return folder.path().lexically_normal().string();
}

void write(const std::string& name, const std::string& text) {
  std::ofstream(dir() + "/" + name) << text;
}

// One rectangle (a quad, fanned into two triangles) of 2 m x 1 m in the file's xy-plane.
const char* kRectangleObj =
    "# a backboard\n"
    "v -1 -0.5 0\n"
    "v 1 -0.5 0\n"
    "v 1 0.5 0\n"
    "v -1 0.5 0\n"
    "vn 0 0 1\n"
    "f 1//1 2//1 3//1 4//1\n";

std::string config(const std::string& mesh_entry, const std::string& object = "[0, 0, 0.5]") {
  return "mesh: {shape: cube, target_tets: 300}\n"  // 1
         "object: {position: " +
         object +
         "}\n"           // 2
         "obstacles:\n"  // 3
         "  meshes:\n"   // 4
         "    - " +
         mesh_entry + "\n";  // 5
}

TEST(SceneObstacleMeshes, ReadsAndPlacesAnOpenRectangle) {
  write("rect.obj", kRectangleObj);
  // Scaled by 2, turned 90 deg about x (the file's y becomes z), moved to (0, 1, 3).
  const Scene s = parse_scene(config("{file: rect.obj, scale: 2, rotation: {axis: [1, 0, 0], "
                                     "angle_deg: 90}, position: [0, 1, 3]}"),
                              "test.yaml", dir());
  ASSERT_EQ(s.obstacle_meshes.size(), 1u);
  const ObstacleMesh& m = s.obstacle_meshes[0];
  EXPECT_EQ(m.F.rows(), 2);
  EXPECT_EQ(m.V.rows(), 4);
  const Eigen::Vector3d v2 = m.V.row(2).transpose();  // file (1, 0.5, 0)
  EXPECT_LT((v2 - Eigen::Vector3d(2.0, 1.0, 4.0)).norm(), 1e-15) << v2.transpose();
  EXPECT_NE(m.name.find("obstacles.meshes[0]"), std::string::npos);
  EXPECT_NE(m.name.find("rect.obj"), std::string::npos);

  write("rect.off", "OFF\n4 1 0\n-1 -0.5 0\n1 -0.5 0\n1 0.5 0\n-1 0.5 0\n4 0 1 2 3\n");
  const Scene off = parse_scene(config("{file: rect.off}"), "test.yaml", dir());
  EXPECT_EQ(off.obstacle_meshes[0].F.rows(), 2);
}

TEST(SceneObstacleMeshes, BadInputIsOneLineNamingConfigFileAndLine) {
  write("rect.obj", kRectangleObj);
  write("bad_number.obj", "v 0 0 0\nv 1 0 0\nv 0 1 x\nf 1 2 3\n");
  write("bad_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  write("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
  write("empty.obj", "# nothing\n");
  write("short.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n");
  // What follows the announced faces, or a vertex's x y z, was dropped without a word.
  write("extra_face.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n");
  write("vertex_junk.off", "OFF\n3 1 0\n0 0 0 junk\n1 0 0\n0 1 0\n3 0 1 2\n");
  struct Case {
    std::string entry;
    std::vector<std::string> fragments;
  };
  const std::vector<Case> cases = {
      {"{file: missing.obj}",
       {"test.yaml:5: key 'obstacles.meshes[0].file'", "missing.obj: cannot open"}},
      {"{file: bad_number.obj}", {"test.yaml:5:", "bad_number.obj:3:", "vertex z", "'x'"}},
      {"{file: bad_index.obj}", {"bad_index.obj:4:", "refers to vertex 9"}},
      {"{file: flat.obj}", {"flat.obj:4:", "zero area"}},
      {"{file: empty.obj}", {"empty.obj: the file holds no triangles"}},
      {"{file: short.off}", {"short.off:4:", "unexpected end of file"}},
      {"{file: extra_face.off}", {"extra_face.off:8:", "more than the 4 vertices and 1 faces"}},
      {"{file: vertex_junk.off}", {"vertex_junk.off:3:", "vertex 0"}},
      {"{file: rect.obj, scal: 2}", {"test.yaml:5: key 'obstacles.meshes[0].scal': unknown key"}},
      {"{file: rect.obj, scale: -1}", {"obstacles.meshes[0].scale", "outside"}},
      {"{file: rect.obj, rotation: [0, 0, 1]}",
       {"obstacles.meshes[0].rotation", "expected a mapping"}},
      {"{position: [0, 0, 0]}", {"obstacles.meshes[0].file", "missing"}},
      {"{file: rect.obj, friction: -0.2}",
       {"test.yaml:5: key 'obstacles.meshes[0].friction'", "outside [0, inf]"}},
  };
  for (const Case& c : cases) {
    try {
      parse_scene(config(c.entry), "test.yaml", dir());
      ADD_FAILURE() << "no error for " << c.entry;
    } catch (const InputError& e) {
      const std::string what = e.what();
      for (const std::string& f : c.fragments)
        EXPECT_NE(what.find(f), std::string::npos) << c.entry << "\n  -> " << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
}

TEST(SceneObstacleMeshes, AStartWithinDHatOrInsideIsRefusedNamingTheObstacle) {
  write("rect.obj", kRectangleObj);
  // The cube (side 0.05) centred at z = 0.5 has its bottom at 0.475; d_hat = 1e-3.
  const auto scene_at = [&](double z) {
    return parse_scene(config("{file: rect.obj, position: [0, 0, " + std::to_string(z) + "]}"),
                       "test.yaml", dir());
  };
  EXPECT_NO_THROW(make_scene_mesh(scene_at(0.47)));
  for (const auto& [z, what] :
       std::vector<std::pair<double, std::string>>{{0.4745, "touching"}, {0.49, "intersecting"}}) {
    try {
      make_scene_mesh(scene_at(z));
      ADD_FAILURE() << "no error at z = " << z;
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("the object starts " + what + " obstacles.meshes[0] (" + dir()),
                std::string::npos)
          << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
  }
}

TEST(SceneObstacleMeshes, TheKappaRuleFallsToTheLowestMeshVertex) {
  write("rect.obj", kRectangleObj);
  Scene s = parse_scene(config("{file: rect.obj, position: [0, 0, 0.3]}"), "test.yaml", dir());
  s.velocity.setZero();
  // A fall of 0.5 - 0.3 = 0.2 m: v = sqrt(2 g 0.2).
  EXPECT_NEAR(barrier_design_speed(s.velocity.norm(), s.gravity, s.planes, s.obstacle_meshes,
                                   Eigen::Vector3d(0, 0, 0.5)), std::sqrt(2 * 9.8 * 0.2), 1e-12);
}

TEST(SceneObstacleMeshes, FingerprintReadsTheObstacleFile) {
  write("fp_rect.obj", kRectangleObj);
  const auto fp = [&] {
    return scene_fingerprint(parse_scene(config("{file: fp_rect.obj}"), "test.yaml", dir()));
  };
  const std::string before = fp();
  write("fp_rect.obj", std::string(kRectangleObj) + "v 5 5 5\n");
  EXPECT_NE(before, fp());
  std::remove((dir() + "/fp_rect.obj").c_str());
}

// obstacles.meshes[i].friction: its own coefficient, else contact.friction's; frictionless
// meshes fingerprint as before, a coefficient changes the fingerprint.
TEST(SceneObstacleMeshes, MeshesTakeTheirOwnFrictionOrTheContactDefault) {
  write("rect.obj", kRectangleObj);
  const std::string two = config("{file: rect.obj, friction: 0.6}") +
                          "    - {file: rect.obj, position: [0, 0, -1]}\n";
  const Scene own = parse_scene(two, "test.yaml", dir());
  ASSERT_EQ(own.obstacle_meshes.size(), 2u);
  EXPECT_EQ(own.obstacle_meshes[0].friction, 0.6);
  EXPECT_EQ(own.obstacle_meshes[1].friction, 0.0);
  const Scene defaulted = parse_scene(two + "contact: {friction: 0.25}\n", "test.yaml", dir());
  EXPECT_EQ(defaulted.obstacle_meshes[0].friction, 0.6);
  EXPECT_EQ(defaulted.obstacle_meshes[1].friction, 0.25);
  const Scene none = parse_scene(config("{file: rect.obj}"), "test.yaml", dir());
  const Scene zero = parse_scene(config("{file: rect.obj, friction: 0}"), "test.yaml", dir());
  const Scene some = parse_scene(config("{file: rect.obj, friction: 0.3}"), "test.yaml", dir());
  EXPECT_EQ(scene_fingerprint_text(none), scene_fingerprint_text(zero));
  EXPECT_NE(scene_fingerprint(none), scene_fingerprint(some));
}

}  // namespace
}  // namespace rbaa
