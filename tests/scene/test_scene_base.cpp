// `base: FILE`: a config laid over another (mappings merge key by key, lists and numbers replace,
// the base's name is not inherited, --set applies last), parsing to the scene the same config
// written out in full would; relative paths resolve from the folder of the file that wrote them;
// every bad `base` a one-line error, and an error inside a base names the base's file and line,
// not the config that uses it.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "io/io_test_support.hpp"
#include "rbaa/error.hpp"
#include "rbaa/scene/scene.hpp"
#include "rbaa/scene/scene_fingerprint.hpp"

namespace rbaa {
namespace {

// A folder of this process's own (test::ScratchDir, made in the first test that asks, removed at
// exit): ctest runs these tests as separate processes side by side, and two of them writing one
// /tmp/over.yaml at once made one read a half-written file.
std::string path(const std::string& name) {
  static const test::ScratchDir folder;
  return (folder.path() / name).lexically_normal().string();
}

void write(const std::string& name, const std::string& text) { std::ofstream(path(name)) << text; }

std::string load_error(const std::string& name) {
  try {
    load_scene(path(name));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

const char* kBase =
    "name: base_scene\n"                          // 1
    "mesh: {shape: cube, target_tets: 300}\n"     // 2
    "object:\n"                                   // 3
    "  position: [0, 0, 0.5]\n"                   // 4
    "  velocity: [0, 0, -1]\n"                    // 5
    "obstacles:\n"                                // 6
    "  planes:\n"                                 // 7
    "    - {normal: [0, 0, 1], offset: 0}\n"      // 8
    "    - {normal: [0, -1, 0], offset: 2}\n"     // 9
    "time:\n"                                     // 10
    "  step: 0.01\n"                              // 11
    "  duration: 0.5\n"                           // 12
    "evaluation: {duration: 2.0}\n";              // 13

const char* kOver =
    "base: base_scene.yaml\n"
    "object: {velocity: [0, 0, -3]}\n"
    "obstacles:\n"
    "  planes: [{normal: [0, 0, 1], offset: -0.5}]\n"
    "time: {step: 0.005}\n";

// kOver on kBase, written out in full by hand.
const char* kWrittenOut =
    "mesh: {shape: cube, target_tets: 300}\n"
    "object:\n"
    "  position: [0, 0, 0.5]\n"
    "  velocity: [0, 0, -3]\n"
    "obstacles:\n"
    "  planes: [{normal: [0, 0, 1], offset: -0.5}]\n"
    "time:\n"
    "  step: 0.005\n"
    "  duration: 0.5\n"
    "evaluation: {duration: 2.0}\n";

TEST(SceneBase, MappingsMergeListsAndNumbersReplaceTheNameIsTheConfigsOwn) {
  write("base_scene.yaml", kBase);
  write("over.yaml", kOver);
  const Scene s = load_scene(path("over.yaml"));
  EXPECT_EQ(s.name, "over");  // its file's stem: the base's name is not inherited
  EXPECT_EQ(s.time_step, 0.005);
  EXPECT_EQ(s.duration, 0.5);  // time.duration from the base beside the overridden step
  EXPECT_EQ(s.position, Eigen::Vector3d(0, 0, 0.5));
  EXPECT_EQ(s.velocity, Eigen::Vector3d(0, 0, -3));
  ASSERT_EQ(s.planes.size(), 1u);  // the list replaced, not appended to
  EXPECT_EQ(s.planes[0].offset, -0.5);
  EXPECT_EQ(s.evaluation_duration, 2.0);
  EXPECT_EQ(s.source, path("over.yaml"));

  write("named.yaml", std::string(kOver) + "name: my_scene\n");
  EXPECT_EQ(load_scene(path("named.yaml")).name, "my_scene");
}

TEST(SceneBase, ParsesToTheSceneTheConfigWrittenInFullGives) {
  write("base_scene.yaml", kBase);
  write("over.yaml", kOver);
  write("over_in_full.yaml", kWrittenOut);
  Scene based = load_scene(path("over.yaml"));
  Scene full = load_scene(path("over_in_full.yaml"));
  full.name = based.name;  // named after their files
  EXPECT_EQ(scene_fingerprint_text(based), scene_fingerprint_text(full));
  EXPECT_EQ(based.evaluation_duration, full.evaluation_duration);
}

TEST(SceneBase, BasesChainAndTheCommandLinesSetAppliesLast) {
  write("base_scene.yaml", kBase);
  write("over.yaml", kOver);
  write("over_over.yaml", "base: over.yaml\ntime: {duration: 0.75}\n");
  const Scene chained = load_scene(path("over_over.yaml"));
  EXPECT_EQ(chained.time_step, 0.005);  // over.yaml's
  EXPECT_EQ(chained.duration, 0.75);    // its own
  EXPECT_EQ(chained.position, Eigen::Vector3d(0, 0, 0.5));  // base_scene.yaml's
  const Scene set = load_scene(path("over_over.yaml"), {"time.step=0.002", "object.position=[0, 0, 1]"});
  EXPECT_EQ(set.time_step, 0.002);
  EXPECT_EQ(set.position, Eigen::Vector3d(0, 0, 1));
  EXPECT_EQ(set.velocity, Eigen::Vector3d(0, 0, -3));
}

TEST(SceneBase, RelativePathsResolveFromTheFolderOfTheFileThatWritesThem) {
  std::filesystem::create_directories(path("shapes"));
  write("shapes/base_shape.yaml",
        "mesh: {surface: meshes/rock.obj}\n"
        "object: {position: [0, 0, 1]}\n"
        "bodies: [{name: pebble, mesh: {file: meshes/pebble.msh}, position: [0, 0, 3]}]\n");
  write("rock_scene.yaml",
        "base: shapes/base_shape.yaml\n"
        "object: {velocity: [0, 0, -1]}\n");
  const Scene inherited = load_scene(path("rock_scene.yaml"));
  EXPECT_EQ(inherited.mesh.surface_file, path("shapes/meshes/rock.obj"));
  ASSERT_EQ(inherited.bodies.size(), 1u);
  EXPECT_EQ(inherited.bodies[0].mesh.mesh_file, path("shapes/meshes/pebble.msh"));
  // Written over it, from the config's own folder; and a --set value from the config's too.
  write("own_bodies.yaml",
        "base: shapes/base_shape.yaml\n"
        "bodies: [{name: pebble, mesh: {file: pebble.msh}, materials: pebble.txt, position: [0, 0, 3]}]\n");
  const Scene own = load_scene(path("own_bodies.yaml"), {"mesh.surface=other.obj"});
  EXPECT_EQ(own.mesh.surface_file, path("other.obj"));
  ASSERT_EQ(own.bodies.size(), 1u);
  EXPECT_EQ(own.bodies[0].mesh.mesh_file, path("pebble.msh"));
  EXPECT_EQ(own.bodies[0].materials_file, path("pebble.txt"));
  // A base's own base is relative to the base's folder.
  write("shapes/over_shape.yaml", "base: base_shape.yaml\ntime: {step: 0.002}\n");
  write("twice.yaml", "base: shapes/over_shape.yaml\n");
  const Scene twice = load_scene(path("twice.yaml"));
  EXPECT_EQ(twice.mesh.surface_file, path("shapes/meshes/rock.obj"));
  EXPECT_EQ(twice.time_step, 0.002);
}

TEST(SceneBase, ErrorsNameTheFileAndLineTheyAreWrittenIn) {
  write("base_scene.yaml", kBase);
  // In the base: its own file and line, whichever config uses it.
  std::string bad_base = kBase;
  bad_base.replace(bad_base.find("duration: 0.5"), 13, "duration: -3");
  write("bad_base.yaml", bad_base);
  write("uses_bad_base.yaml", "# a comment\nbase: bad_base.yaml\ntime: {step: 0.005}\n");
  EXPECT_EQ(load_error("uses_bad_base.yaml"),
            path("bad_base.yaml") + ":12: key 'time.duration': value -3 is outside (0, 1e+06]");
  // In the config over it: its own.
  write("bad_over.yaml", "base: base_scene.yaml\n\ntime: {step: -1}\n");
  EXPECT_EQ(load_error("bad_over.yaml"),
            path("bad_over.yaml") + ":3: key 'time.step': value -1 is outside (0, 1]");
  write("unknown.yaml", "base: base_scene.yaml\ntime: {stepp: 1}\n");
  EXPECT_EQ(load_error("unknown.yaml"), path("unknown.yaml") + ":2: key 'time.stepp': unknown key");

  write("missing.yaml", "name: m\nbase: nothere.yaml\n");
  EXPECT_EQ(load_error("missing.yaml"),
            path("missing.yaml") + ":2: key 'base': " + path("nothere.yaml") +
                ": cannot read: No such file or directory");
  std::filesystem::create_directories(path("a_folder"));
  write("folder.yaml", "base: a_folder\n");
  EXPECT_EQ(load_error("folder.yaml"),
            path("folder.yaml") + ":1: key 'base': " + path("a_folder") + ": cannot read: is a directory");
  // The config itself, read by the same function.
  EXPECT_EQ(load_error("a_folder"), path("a_folder") + ": cannot read: is a directory");
  write("list.yaml", "base: [base_scene.yaml]\n");
  EXPECT_EQ(load_error("list.yaml"), path("list.yaml") + ":1: key 'base': expected a file name");
  write("cycle_a.yaml", "base: cycle_b.yaml\n");
  write("cycle_b.yaml", "mesh: {shape: cube}\nbase: cycle_a.yaml\n");
  EXPECT_EQ(load_error("cycle_a.yaml"),
            path("cycle_b.yaml") +
                ":2: key 'base': 'cycle_a.yaml' is already being read (cycle_a.yaml -> "
                "cycle_b.yaml -> cycle_a.yaml)");
  write("broken.yaml", "mesh: [1,\n");
  write("uses_broken.yaml", "base: broken.yaml\n");
  EXPECT_EQ(load_error("uses_broken.yaml").rfind(path("broken.yaml") + ":2: invalid YAML: ", 0), 0u)
      << load_error("uses_broken.yaml");
  write("scalar.yaml", "just text\n");
  write("uses_scalar.yaml", "base: scalar.yaml\n");
  EXPECT_EQ(load_error("uses_scalar.yaml"),
            path("uses_scalar.yaml") + ":1: key 'base': '" + path("scalar.yaml") +
                "' is not a mapping of keys");
}

TEST(SceneBase, TheAccurateConfigsAreTheirScenesLaidOver) {
  // configs/*_accurate.yaml name their plain scene as base and change the step, the attack's
  // start, length and fields, and the objective: every other key is the base's.
  const std::string configs = std::string(RBAA_SOURCE_DIR) + "/configs/";
  for (const char* name : {"ball", "bunny", "bat"}) {
    const Scene plain = load_scene(configs + name + ".yaml");
    Scene accurate = load_scene(configs + name + "_accurate.yaml");
    EXPECT_EQ(accurate.name, std::string(name) + "_accurate");
    EXPECT_GT(accurate.contact_substeps, 0) << name;
    EXPECT_TRUE(accurate.start_best_uniform) << name;
    // Undo what the accurate config says it changes; the rest must be the base's.
    accurate.name = plain.name;
    accurate.source = plain.source;
    accurate.time_step = plain.time_step;
    accurate.contact_substeps = plain.contact_substeps;
    accurate.start_best_uniform = plain.start_best_uniform;
    accurate.iterations = plain.iterations;
    accurate.polish_iterations = plain.polish_iterations;
    accurate.fields = plain.fields;  // bat_accurate: the solid bat
    accurate.objective = plain.objective;
    EXPECT_EQ(scene_fingerprint_text(accurate), scene_fingerprint_text(plain)) << name;
  }
}

}  // namespace
}  // namespace rbaa
