#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

#include "rbaa/error.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/scene/scene.hpp"
#include "rbaa/scene/scene_fingerprint.hpp"
#include "rbaa/scene/scene_mesh.hpp"
#include "rbaa/scene/scene_world.hpp"
#include "rbaa/sim/simulator.hpp"

namespace rbaa {
namespace {

const std::string kConfigs = std::string(RBAA_SOURCE_DIR) + "/configs/";

// Expects an InputError whose one-line message contains every fragment.
void expect_error(const std::string& yaml, const std::vector<std::string>& fragments,
                  const std::vector<std::string>& overrides = {}) {
  try {
    parse_scene(yaml, "test.yaml", "", overrides);
    FAIL() << "no error for:\n" << yaml;
  } catch (const InputError& e) {
    const std::string what = e.what();
    for (const auto& f : fragments) EXPECT_NE(what.find(f), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

TEST(Scene, ShippedConfigsLoad) {
  const Scene ball = load_scene(kConfigs + "ball.yaml");
  EXPECT_EQ(ball.mesh.shape, "sphere");
  EXPECT_EQ(ball.mesh.target_tets, 9056);
  ASSERT_EQ(ball.planes.size(), 1u);
  EXPECT_NEAR(ball.planes[0].normal.y(), -1.0, 0);
  EXPECT_DOUBLE_EQ(ball.time_step, 0.01);
  EXPECT_DOUBLE_EQ(ball.gravity.z(), -9.8);
  EXPECT_EQ(ball.kappa, 0.0);  // auto

  const Scene star = load_scene(kConfigs + "star.yaml");
  EXPECT_EQ(star.planes.size(), 2u);
  EXPECT_EQ(star.gravity.norm(), 0.0);
  EXPECT_NEAR(star.time_step, 1.0 / 30.0, 1e-15);
  EXPECT_EQ(star.fields, (std::vector<std::string>{"Y", "nu", "rho"}));
  EXPECT_DOUBLE_EQ(star.Y_range.lo, 5e9);

  const Scene cube = load_scene(kConfigs + "cube.yaml");
  ASSERT_EQ(cube.planes.size(), 2u);
  EXPECT_NEAR(cube.planes[1].offset, -0.1, 1e-15);  // ceiling z = 0.1 facing down: -z >= -0.1
  EXPECT_DOUBLE_EQ(cube.duration, 1.5);

  const Scene bunny = load_scene(kConfigs + "bunny.yaml");
  EXPECT_EQ(bunny.mesh.shape, "bunny");

  // The ball's scene attacked where it is accurate (issue 20): the same scene as ball.yaml.
  const Scene accurate = load_scene(kConfigs + "ball_accurate.yaml");
  EXPECT_EQ(accurate.mesh.target_tets, ball.mesh.target_tets);
  EXPECT_EQ(accurate.position, ball.position);
  EXPECT_EQ(accurate.velocity, ball.velocity);
  EXPECT_EQ(accurate.contact_substeps, 1024);
  EXPECT_EQ(accurate.objective.kind, ObjectiveSpec::Kind::kAway);
  EXPECT_TRUE(accurate.start_best_uniform);
  EXPECT_TRUE(accurate.occupancy_repair_in_loop);

  // And the bunny's: the scene of bunny.yaml with the same recipe.
  const Scene bunny_accurate = load_scene(kConfigs + "bunny_accurate.yaml");
  EXPECT_EQ(bunny_accurate.mesh.shape, bunny.mesh.shape);
  EXPECT_EQ(bunny_accurate.mesh.target_tets, bunny.mesh.target_tets);
  EXPECT_EQ(bunny_accurate.position, bunny.position);
  EXPECT_EQ(bunny_accurate.velocity, bunny.velocity);
  EXPECT_EQ(bunny_accurate.time_step, bunny.time_step);
  EXPECT_EQ(bunny_accurate.duration, bunny.duration);
  EXPECT_EQ(bunny_accurate.contact_substeps, 1024);
  EXPECT_EQ(bunny_accurate.objective.kind, ObjectiveSpec::Kind::kAway);
  EXPECT_TRUE(bunny_accurate.start_best_uniform);
}

TEST(Scene, PlacesTheObjectAtItsInitialPose) {
  const Scene star = load_scene(kConfigs + "star.yaml");
  const TetMesh mesh = make_scene_mesh(star);
  const Eigen::Vector3d c = compute_moments(mesh, 1.0).centre_of_mass();
  EXPECT_LT((c - star.position).norm(), 1e-12);
  for (const Plane& p : star.planes) EXPECT_GT((mesh.V * p.normal).minCoeff() - p.offset, star.d_hat);
}

// The README's object.position is the centre of mass: with a non-uniform material (a materials
// file, an adversarial .msh) the mesh is moved so that rho alpha V weights put it there.
TEST(Scene, NonUniformMaterialPutsTheCentreOfMassAtThePosition) {
  const Scene star = load_scene(kConfigs + "star.yaml");
  const TetMesh uniform = make_scene_mesh(star);
  std::srand(7);
  const Eigen::VectorXd density =
      (Eigen::VectorXd::Random(uniform.num_tets()).array() * 5000.0 + 6000.0).matrix();
  const Eigen::Vector3d before = compute_moments(uniform, density).centre_of_mass();
  std::printf("random density: centre of mass %.3e m from object.position before placing\n",
              (before - star.position).norm());
  ASSERT_GT((before - star.position).norm(), 1e-3);  // the defect: millimetres off

  const TetMesh placed = place_centre_of_mass(star, uniform, density, "random.csv");
  const Eigen::Vector3d c = compute_moments(placed, density).centre_of_mass();
  EXPECT_LT((c - star.position).norm(), 1e-12 * star.position.norm());
  // A translation: the shape is unchanged.
  const Eigen::RowVector3d shift = placed.V.row(0) - uniform.V.row(0);
  EXPECT_LT((placed.V - (uniform.V.rowwise() + shift)).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_EQ(placed.T, uniform.T);

  // Uniform density (any value): the mesh is returned bit for bit.
  const TetMesh same = place_centre_of_mass(
      star, uniform, Eigen::VectorXd::Constant(uniform.num_tets(), 1234.5), "u");
  EXPECT_EQ(std::memcmp(same.V.data(), uniform.V.data(), sizeof(double) * uniform.V.size()), 0);
  EXPECT_EQ(same.T, uniform.T);

  // Non-uniform with the uniform object's moments (what an attack produces): its centre of mass
  // is there already and the mesh is returned bit for bit too, so that its rigid twin's hull is
  // the reference's.
  const Eigen::MatrixXd S = moment_operator(uniform);
  const Eigen::VectorXd r = density - Eigen::VectorXd::Constant(uniform.num_tets(), 2500.0);
  const Eigen::VectorXd matched = Eigen::VectorXd::Constant(uniform.num_tets(), 2500.0) + r -
                                  S.transpose() * (S * S.transpose()).ldlt().solve(S * r);
  const Eigen::Vector3d c_matched = compute_moments(uniform, matched).centre_of_mass();
  EXPECT_LT((c_matched - star.position).norm(), 1e-12 * star.position.norm());
  EXPECT_GT((c_matched - star.position).norm(),
            0.0);  // not exactly there: the check means something
  const TetMesh kept = place_centre_of_mass(star, uniform, matched, "matched.msh");
  EXPECT_EQ(std::memcmp(kept.V.data(), uniform.V.data(), sizeof(double) * uniform.V.size()), 0);
}

TEST(Scene, PlacingTheCentreOfMassIntoAnObstacleIsAnError) {
  // Heavy elements on the floor side pull the centre of mass down; moving it up to the position
  // is fine, but a light floor side moves the object into the floor.
  const Scene cube = load_scene(kConfigs + "cube.yaml", {"object.position=[0, 0, 0.0265]"});
  const TetMesh mesh = make_scene_mesh(cube);
  Eigen::VectorXd density(mesh.num_tets());
  for (int e = 0; e < mesh.num_tets(); ++e) {
    double z = 0;
    for (int k = 0; k < 4; ++k) z += mesh.V(mesh.T(e, k), 2) / 4;
    density[e] = z > cube.position.z() ? 11300 : 800;
  }
  try {
    place_centre_of_mass(cube, mesh, density, "heavy_top.csv");
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("heavy_top.csv"), std::string::npos) << what;
    EXPECT_NE(what.find("obstacles.planes[0]"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

TEST(Scene, OverridesApplyBeforeValidation) {
  const Scene s = load_scene(kConfigs + "ball.yaml", {"time.step=0.005", "object.velocity=[0, 1, 2]",
                                                     "attack.iterations=3", "contact.kappa=1e7"});
  EXPECT_DOUBLE_EQ(s.time_step, 0.005);
  EXPECT_DOUBLE_EQ(s.velocity.z(), 2.0);
  EXPECT_EQ(s.iterations, 3);
  EXPECT_DOUBLE_EQ(s.kappa, 1e7);
  EXPECT_THROW(load_scene(kConfigs + "ball.yaml", {"time.stepp=0.1"}), InputError);
  EXPECT_THROW(load_scene(kConfigs + "ball.yaml", {"no equals sign"}), InputError);
}

TEST(Scene, StartingInContactIsAnError) {
  const Scene s = load_scene(kConfigs + "cube.yaml", {"object.position=[0, 0, 0.02]"});
  try {
    make_scene_mesh(s);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("intersecting obstacles.planes[0]"), std::string::npos) << e.what();
  }
  const Scene touching = load_scene(kConfigs + "cube.yaml", {"object.position=[0, 0, 0.0255]"});
  EXPECT_THROW(make_scene_mesh(touching), InputError);
}

const char* kMinimal = "mesh: {shape: cube}\n";

TEST(Scene, EvaluationSettingsDefaultToTheAttacksAndCanBeSet) {
  const Scene plain = parse_scene(kMinimal, "test.yaml", "");
  EXPECT_TRUE(plain.evaluation_search_step);  // refine the attack's step until the baseline agrees
  EXPECT_EQ(plain.evaluation_duration, 0.0);  // evaluate uses 4 x time.duration
  EXPECT_DOUBLE_EQ(plain.evaluation_baseline_tolerance, 0.005);
  const Scene set = parse_scene(std::string(kMinimal) + "evaluation: {time_step: 0.001, duration: 2}\n",
                                "test.yaml", "", {"evaluation.duration=3"});
  EXPECT_FALSE(set.evaluation_search_step);
  EXPECT_DOUBLE_EQ(set.evaluation_time_step, 0.001);
  EXPECT_DOUBLE_EQ(set.evaluation_duration, 3.0);
  const Scene searched = parse_scene(std::string(kMinimal) + "evaluation: {time_step: auto, max_refinements: 1}\n",
                                     "test.yaml", "");
  EXPECT_TRUE(searched.evaluation_search_step);
  EXPECT_EQ(searched.evaluation_max_refinements, 1);
}

// What YAML would read without complaint but rbaa would then lose: a key given twice (yaml-cpp
// keeps both, every read finds the first), a key with no value (null, which reads as absent: the
// built-in default), a key that is not a name, an empty --set value, and a size the mesh source
// does not use. Each is a one-line error naming the file (and line, or the --set) and the key.
TEST(Scene, InputThatWouldBeLostIsRefused) {
  expect_error(std::string(kMinimal) + "time: {step: 0.01, duration: 0.5, step: 0.002}\n",
               {"test.yaml:2", "'time.step'", "given twice"});
  expect_error(std::string(kMinimal) + "time: {step: 0.01}\ngravity: off\ntime: {step: 0.002}\n",
               {"test.yaml:4", "'time'", "given twice"});
  expect_error(std::string(kMinimal) + "bodies:\n  - {name: a, name: b, mesh: {shape: cube}}\n",
               {"test.yaml:3", "'bodies[0].name'", "given twice"});
  expect_error(std::string(kMinimal) + "time: {? [a]: 1}\n", {"test.yaml:2", "under 'time'", "must be a name"});
  expect_error(std::string(kMinimal) + "time:\n  step:\n  duration: 0.5\n",
               {"test.yaml:3", "'time.step'", "has no value"});
  expect_error(kMinimal, {"--set time.step", "no value"}, {"time.step="});
  expect_error(kMinimal, {"test.yaml (--set time): key 'time.step'", "given twice"},
               {"time={step: 1, step: 2}"});
  // A --set value's error names the config and the --set, not a line of the config.
  expect_error("\n" + std::string(kMinimal), {"test.yaml (--set time.step): key 'time.step'", "outside"},
               {"time.step=-1"});
  try {
    parse_scene("\n" + std::string(kMinimal), "test.yaml", "", {"time.step=-1"});
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).find("test.yaml:"), std::string::npos) << e.what();
  }
  expect_error("mesh: {shape: cube, radius: 0.5}\n", {"test.yaml:1", "'mesh.radius'", "does not apply to shape cube"});
  expect_error("mesh: {shape: sphere, side: 0.5}\n", {"'mesh.side'", "does not apply to shape sphere"});
  expect_error("mesh: {shape: star, volume: 1}\n", {"'mesh.volume'", "does not apply to shape star"});
  expect_error("mesh: {file: cube.msh, target_tets: 500}\n", {"'mesh.target_tets'", "a tet mesh file"});
  expect_error("mesh: {shape: cube}\nbodies:\n  - {name: b, mesh: {shape: cube, radius: 1}}\n",
               {"'bodies[0].mesh.radius'", "does not apply"});
  // What each source does use is still read.
  EXPECT_EQ(parse_scene("mesh: {shape: sphere, radius: 0.2}\n", "test.yaml", "").mesh.radius, 0.2);
  EXPECT_EQ(parse_scene("mesh: {shape: cube, side: 0.1, target_tets: 500}\n", "test.yaml", "").mesh.side, 0.1);
}

TEST(Scene, BadInputNamesFileLineAndKey) {
  expect_error(std::string(kMinimal) + "tiem:\n  step: 0.01\n", {"test.yaml:2", "'tiem'", "unknown key"});
  expect_error(std::string(kMinimal) + "time:\n  step: fast\n", {"test.yaml:3", "time.step", "expected a number"});
  expect_error(std::string(kMinimal) + "time:\n  step: .nan\n", {"time.step", "not finite"});
  expect_error(std::string(kMinimal) + "time:\n  step: -0.01\n", {"time.step", "outside"});
  expect_error(std::string(kMinimal) + "time: {step: 0.1, duration: 0.01}\n", {"time.duration", "shorter"});
  expect_error(std::string(kMinimal) + "attack: {Y0: 2.5e9}\n", {"attack.Y0", "outside (2.5e+09"});
  expect_error(std::string(kMinimal) + "attack: {nu0: 0.45}\n", {"attack.nu0", "outside"});
  expect_error(std::string(kMinimal) + "evaluation: {time_step: 0}\n", {"evaluation.time_step", "outside"});
  expect_error(std::string(kMinimal) + "evaluation: {time_step: 0.01, duration: 0.001}\n",
               {"evaluation.duration", "shorter"});
  expect_error(std::string(kMinimal) + "evaluation: {step: 0.01}\n", {"'evaluation.step'", "unknown key"});
  expect_error(std::string(kMinimal) + "material_bounds: {Y: [1.0e9, 1.0e11]}\n",
               {"material_bounds.Y", "outside [2.5e+09"});
  expect_error(std::string(kMinimal) + "material_bounds: {nu: [0.3, 0.25]}\n", {"material_bounds.nu", "below max"});
  expect_error(std::string(kMinimal) + "object: {velocity: [1, 2]}\n", {"object.velocity", "3 numbers"});
  expect_error(std::string(kMinimal) + "obstacles: {planes: [{normal: [0, 0, 0], offset: 0}]}\n",
               {"obstacles.planes[0].normal"});
  expect_error(std::string(kMinimal) + "obstacles: {planes: [{normal: [0, 0, 1]}]}\n",
               {"obstacles.planes[0]", "exactly one of offset, point"});
  expect_error(std::string(kMinimal) + "attack: {fields: [Y, E]}\n", {"attack.fields", "'E'"});
  expect_error(std::string(kMinimal) + "time: {integrator: rk4}\n", {"time.integrator", "'rk4'"});
  expect_error(std::string(kMinimal) + "newton: {max_iterations: 2.5}\n", {"newton.max_iterations", "whole number"});
  expect_error(std::string(kMinimal) + "newton: {rigid_predictor: maybe}\n", {"newton.rigid_predictor", "'maybe'"});
  EXPECT_FALSE(parse_scene(std::string(kMinimal) + "newton: {rigid_predictor: false}\n", "t.yaml", "").newton_rigid_predictor);
  EXPECT_TRUE(parse_scene(kMinimal, "t.yaml", "").newton_rigid_predictor);
  EXPECT_FALSE(simulation_settings(parse_scene(kMinimal, "t.yaml", "", {"newton.rigid_predictor=false"}), 1.0).rigid_predictor);
  expect_error(std::string(kMinimal) + "newton: {chord_start: 1}\n", {"newton.chord_start", "'1'"});
  EXPECT_TRUE(simulation_settings(parse_scene(kMinimal, "t.yaml", ""), 1.0).newton_chord_start);
  EXPECT_FALSE(simulation_settings(parse_scene(kMinimal, "t.yaml", "", {"newton.chord_start=false"}), 1.0).newton_chord_start);
  expect_error(std::string(kMinimal) + "attack: {polish_iterations: -1}\n", {"attack.polish_iterations"});
  expect_error(std::string(kMinimal) + "attack: {polish_iterations: 2.5}\n", {"attack.polish_iterations", "whole number"});
  expect_error(std::string(kMinimal) + "attack: {refinement_factor: -2}\n", {"attack.refinement_factor"});
  expect_error(std::string(kMinimal) + "attack: {smoothing_gamma: 0}\n", {"attack.smoothing_gamma", "outside (0"});
  // The occupancy penalty: a weight and a ramp, each named in its one-line error.
  expect_error(std::string(kMinimal) + "attack: {occupancy_penalty: {weight: -1}}\n",
               {"attack.occupancy_penalty.weight", "outside"});
  expect_error(std::string(kMinimal) + "attack: {occupancy_penalty: {weight: .nan}}\n",
               {"attack.occupancy_penalty.weight", "not finite"});
  expect_error(std::string(kMinimal) + "attack: {occupancy_penalty: {connectivity_weight: -0.5}}\n",
               {"attack.occupancy_penalty.connectivity_weight", "outside"});
  expect_error(std::string(kMinimal) + "attack: {occupancy_penalty: {ramp_start: 1.5}}\n",
               {"attack.occupancy_penalty.ramp_start", "outside"});
  expect_error(std::string(kMinimal) + "attack: {occupancy_penalty: {ramp_start: 0.6, ramp_end: 0.4}}\n",
               {"attack.occupancy_penalty.ramp_end", "below ramp_start"});
  expect_error(std::string(kMinimal) + "attack: {occupancy_penalty: {repair_in_loop: yes}}\n",
               {"attack.occupancy_penalty.repair_in_loop", "'yes'"});
  expect_error(std::string(kMinimal) + "attack: {occupancy_penalty: {wieght: 1}}\n",
               {"attack.occupancy_penalty.wieght", "unknown key"});
  expect_error(std::string(kMinimal) + "attack: {occupancy_penalty: 2}\n",
               {"attack.occupancy_penalty", "expected a mapping"});
  expect_error(std::string(kMinimal) + "material_bounds: {alpha_min: 0.5}\nattack: {round_threshold: 0.4}\n",
               {"attack.round_threshold", "alpha_min"});
  {
    const Scene s = parse_scene(std::string(kMinimal) + "attack: {occupancy_penalty: {weight: 2, ramp_end: 0.5}}\n",
                                "t.yaml", "");
    EXPECT_EQ(s.occupancy_weight, 2.0);
    EXPECT_EQ(s.occupancy_ramp_start, 0.2);
    EXPECT_EQ(s.occupancy_ramp_end, 0.5);
    EXPECT_EQ(parse_scene(kMinimal, "t.yaml", "").occupancy_weight, 0.0);  // off by default
    EXPECT_EQ(parse_scene(kMinimal, "t.yaml", "", {"attack.occupancy_penalty={weight: 3}"}).occupancy_weight, 3.0);
  }
  expect_error(std::string(kMinimal) + "attack: {refinement_factor: 1.5}\n", {"attack.refinement_factor", "whole number"});
  expect_error("mesh: {shape: cube, file: a.msh}\n", {"mesh", "exactly one of shape, surface, file"});
  expect_error("time: {step: 0.01}\n", {"mesh", "missing"});
  expect_error("mesh: [1, 2\n", {"test.yaml", "invalid YAML"});
  expect_error(kMinimal, {"--set", "key.path=value"}, {"oops"});
}

// The --resume fingerprint is over the parsed settings: spelling, comments, order, name and the
// settings that only bound or extend the work leave it alone.
TEST(Scene, FingerprintIgnoresWhatChangesNoResult) {
  const std::string base =
      "name: a\nmesh: {shape: cube, target_tets: 500}\ntime: {step: 0.01, duration: 0.05}\n"
      "contact: {d_hat: 1.0e-3}\nattack: {iterations: 12, seed: 3}\n";
  const std::string fp = scene_fingerprint(parse_scene(base, "a.yaml", ""));
  EXPECT_EQ(fp.size(), 16u);
  const std::string respelled =
      "# the same scene, written differently\nattack: {seed: 3, iterations: 40, polish_iterations: 7}\n"
      "contact: {d_hat: 0.001}   # 1 mm\ntime: {duration: 5.0e-2, step: 1e-2}\nname: b\n"
      "mesh: {target_tets: 500, shape: cube}\nnewton: {max_iterations: 400}\n"
      "evaluation: {time_step: 0.001, duration: 3}\n";
  EXPECT_EQ(scene_fingerprint(parse_scene(respelled, "elsewhere/b.yaml", "")), fp)
      << scene_fingerprint_text(parse_scene(respelled, "b.yaml", "")) << "\nvs\n"
      << scene_fingerprint_text(parse_scene(base, "a.yaml", ""));
  EXPECT_EQ(scene_fingerprint(parse_scene(base, "a.yaml", "", {"attack.polish_iterations=30",
                                                                "newton.max_iterations=300",
                                                                "attack.refinement_factor=4"})),
            fp);
}

// Every setting that changes an attack's result changes the fingerprint.
TEST(Scene, FingerprintSeesEverySettingThatChangesAResult) {
  const std::string base = "mesh: {shape: cube, target_tets: 500}\nobstacles: {planes: [{normal: [0, 0, 1], offset: 0}]}\n";
  const std::string fp = scene_fingerprint(parse_scene(base, "a.yaml", ""));
  for (const std::string o :
       {"mesh.target_tets=600", "mesh.side=0.06", "object.position=[0, 0, 1]", "object.velocity=[0, 0, -1]",
        "object.angular_velocity=[0, 1, 0]", "object.rotation={axis: [0, 1, 0], angle_deg: 10}",
        "obstacles.planes=[{normal: [0, 0, 1], offset: 0.001}]", "gravity=off", "time.step=0.005",
        "time.duration=0.3", "time.integrator=bdf1", "time.mass=lumped", "contact.d_hat=0.002",
        "contact.kappa=1e6", "newton.tolerance=1e-7", "reference_material={Y: 1e12}",
        "material_bounds={Y: [3e9, 6e11]}", "material_bounds={nu: [0.25, 0.4]}",
        "material_bounds={rho: [900, 11300]}", "material_bounds={alpha_min: 0.01}", "attack.fields=[Y, rho]",
        "attack.learning_rate=0.1", "attack.beta=1e3", "attack.adam_beta1=0.9", "attack.adam_beta2=0.99",
        "attack.seed=2", "attack.perturbation=0.2", "attack.alpha0=0.9", "attack.Y0=1e10", "attack.nu0=0.3",
        "attack.smoothing_gamma=2", "attack.boundary=vertices", "attack.round_threshold=0.4",
        "attack.project_moments=false", "attack.start=best_uniform",
        "attack.occupancy_penalty={weight: 1}", "attack.occupancy_penalty={connectivity_weight: 1}",
        "attack.occupancy_penalty={repair_in_loop: true}", "newton.rigid_predictor=false",
        "newton.chord_start=false", "contact.friction_iterations=2"}) {
    EXPECT_NE(scene_fingerprint(parse_scene(base, "a.yaml", "", {o})), fp) << o;
  }
}

// attack.start is `given` (default) or `best_uniform`; best_uniform chooses Y0 and nu0 itself.
TEST(Scene, AttackStartIsGivenOrBestUniform) {
  const std::string base = "mesh: {shape: cube, target_tets: 500}\n";
  EXPECT_FALSE(parse_scene(base, "a.yaml", "").start_best_uniform);
  EXPECT_TRUE(parse_scene(base, "a.yaml", "", {"attack.start=best_uniform"}).start_best_uniform);
  expect_error(base, {"attack.start", "bogus", "best_uniform"}, {"attack.start=bogus"});
  expect_error(base, {"attack.start", "Y0"}, {"attack.start=best_uniform", "attack.Y0=1e10"});
}

// A tet mesh file enters by its content: editing it changes the fingerprint, moving it does not.
TEST(Scene, FingerprintReadsTheMeshFile) {
  const std::string dir = ::testing::TempDir();
  auto write = [](const std::string& path, const std::string& text) { std::ofstream(path) << text; };
  write(dir + "/fp_a.node", "one\n");
  write(dir + "/fp_b.node", "one\n");
  const auto fp = [&](const std::string& file) {
    return scene_fingerprint(parse_scene("mesh: {file: " + file + "}\n", "a.yaml", dir));
  };
  EXPECT_EQ(fp("fp_a.node"), fp("fp_b.node"));
  write(dir + "/fp_b.node", "two\n");
  EXPECT_NE(fp("fp_a.node"), fp("fp_b.node"));
  std::remove((dir + "/fp_a.node").c_str());
  std::remove((dir + "/fp_b.node").c_str());
}

TEST(Scene, MissingFileIsAnError) {
  EXPECT_THROW(load_scene("/nonexistent/scene.yaml"), InputError);
}

}  // namespace
}  // namespace rbaa
