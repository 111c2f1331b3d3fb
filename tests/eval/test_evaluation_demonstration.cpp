// `rbaa evaluate` on a demonstration scene (issue 17): every run, rigid and deformable, reference,
// adversarial and soft control, gets its predicate and figure in an outcome table, in
// report.json and summary.md; an adversarial object placed at another pose (its attack config's)
// is moved to the demonstration's. A coarse ball dropped through a hoop with no rim (the
// predicate needs no obstacle).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>

#include "io/io_test_support.hpp"
#include "rbaa/error.hpp"
#include "rbaa/eval/evaluation.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/scene/scene.hpp"
#include "rbaa/scene/scene_mesh.hpp"

namespace rbaa {
namespace {

// The ball (radius 0.1) falls from z = 1 drifting at 0.2 m/s along x and crosses z = 0.5 at
// t ~ 0.32 s, x ~ 0.064 m.
Scene dropped_ball(double hoop_x) {
  return parse_scene(
      "mesh: {shape: sphere, radius: 0.1, target_tets: 300}\n"
      "object: {position: [0, 0, 1], velocity: [0.2, 0, 0]}\n"
      "time: {step: 0.01, duration: 0.4}\n"
      "evaluation: {time_step: 0.01, duration: 0.4}\n"
      "contact: {kappa: 1.0e5}\n"
      "demonstration:\n"
      "  predicate: {kind: through_hoop, centre: [" +
          std::to_string(hoop_x) +
          ", 0, 0.5], radius: 0.3}\n"
          "  figure: angle\n",
      "dropped_ball.yaml", "");
}

TEST(EvaluationDemonstration, EveryRunGetsItsPredicateAndFigureInTheReportAndSummary) {
  const Scene scene = dropped_ball(0.0);
  const TetMesh mesh = make_scene_mesh(scene);
  // The attack's object comes placed elsewhere (1 m along x): it is moved to the release.
  TetMesh elsewhere = mesh;
  elsewhere.V.col(0).array() += 1.0;
  const MaterialField soft =
      MaterialField::uniform(mesh.num_tets(), 5e9, 0.3, scene.reference_rho, 1.0);
  const Evaluation ev = evaluate(scene, mesh, elsewhere, soft);

  ASSERT_EQ(ev.outcomes.size(), 6u);
  for (const DemonstrationOutcome& o : ev.outcomes) {
    EXPECT_TRUE(o.has_predicate);
    EXPECT_TRUE(o.predicate.holds) << o.run << ": " << o.predicate.detail;
    // Free fall: every run leaves in the rigid reference's direction.
    EXPECT_LT(o.figure, 1e-3) << o.run;
  }
  EXPECT_EQ(ev.outcomes[0].run, "rigid reference");
  EXPECT_EQ(ev.outcomes[4].simulator, "deformable");
  EXPECT_EQ(ev.outcomes[4].object, "adversarial");
  EXPECT_LT((ev.deformable_adversarial.centre.front() - Eigen::Vector3d(0, 0, 1)).norm(), 1e-9);

  const test::ScratchDir scratch;
  const std::string dir = scratch.path().string();
  write_evaluation(ev, scene, dir);
  std::ifstream in(dir + "/report.json");
  const auto report = nlohmann::json::parse(in);
  ASSERT_TRUE(report["outcomes"].is_object());
  EXPECT_EQ(report["outcomes"]["predicate"], "through_hoop");
  ASSERT_EQ(report["outcomes"]["runs"].size(), 6u);
  EXPECT_EQ(report["outcomes"]["runs"][5]["object"], "soft control");
  EXPECT_EQ(report["outcomes"]["runs"][5]["predicate"], true);
  std::ifstream md(dir + "/summary.md");
  std::stringstream text;
  text << md.rdbuf();
  EXPECT_NE(text.str().find("| deformable adversarial | true |"), std::string::npos) << text.str();

  // Round trip: scripts/outcome_table.py reads this report as evaluate wrote it (its keys).
  const std::string table = dir + "/table.md";
  const std::string command = "python3 " RBAA_SOURCE_DIR "/scripts/outcome_table.py demo=" + dir +
                              " --out=" + table;
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  std::ifstream tin(table);
  std::string line;
  int simulators = 0;
  while (std::getline(tin, line)) {
    for (const std::string simulator : {"rigid", "deformable"}) {
      if (line.rfind("| demo | through_hoop | " + simulator + " | ", 0) != 0) continue;
      ++simulators;
      int yes = 0;
      for (size_t at = line.find("**yes**"); at != std::string::npos;
           at = line.find("**yes**", at + 1)) {
        ++yes;
      }
      EXPECT_EQ(yes, 3) << line;  // reference, adversarial and soft control all pass through
      EXPECT_NE(line.find(simulator == "rigid" ? "twins " : "h = 0.01 s, baseline strays "),
                std::string::npos)
          << line;
    }
  }
  EXPECT_EQ(simulators, 2);
}

TEST(EvaluationDemonstration, AHoopTheBallMissesIsFalseForEveryRun) {
  // Crossing at x ~ 0.064: 0.29 m from a hoop at x = 0.35, more than 0.3 - 0.1.
  const Scene scene = dropped_ball(0.35);
  const TetMesh mesh = make_scene_mesh(scene);
  EvaluationOptions options;
  options.soft_control = false;
  const MaterialField same = MaterialField::uniform(mesh.num_tets(), scene.reference_Y,
                                                    scene.reference_nu, scene.reference_rho, 1.0);
  const Evaluation ev = evaluate(scene, mesh, mesh, same, options);
  ASSERT_EQ(ev.outcomes.size(), 4u);  // no soft control
  for (const DemonstrationOutcome& o : ev.outcomes)
    EXPECT_FALSE(o.predicate.holds) << o.run << ": " << o.predicate.detail;
}

TEST(EvaluationDemonstration, TheRigidTwinSlidesWithEachSurfacesOwnFriction) {
  // A cube sliding at 1 m/s on a floor with mu decelerates at mu g: after 0.2 s it moves at
  // 1 - 0.2 mu g m/s, in Bullet as on the FEM mesh. The floor has contact.friction's 0.4, or
  // its own 0.3 (0.412 m/s after 0.2 s, where 0.4 leaves 0.216 m/s).
  const std::string yaml =
      "mesh: {shape: cube, side: 0.1, target_tets: 200}\n"
      "object: {position: [0, 0, 0.0515], velocity: [0, 1, 0]}\n"
      "obstacles: {planes: [{normal: [0, 0, 1], offset: 0}]}\n"
      "time: {step: 0.01, duration: 0.2}\n"
      "evaluation: {time_step: 0.005, duration: 0.2}\n"
      "contact: {kappa: 1.0e5, friction: FRICTION}\n"
      "reference_material: {Y: 1.0e10, nu: 0.3, rho: 1000}\n"
      "demonstration: {figure: angle}\n";
  auto with = [&](const std::string& friction, const std::string& plane_friction) {
    std::string text = yaml;
    text.replace(text.find("FRICTION"), 8, friction);
    if (!plane_friction.empty()) text.replace(text.find("offset: 0}"), 10, "offset: 0, friction: " + plane_friction + "}");
    return parse_scene(text, "sliding_cube.yaml", "");
  };
  const Scene scene = with("0.4", "");
  const TetMesh mesh = make_scene_mesh(scene);
  const MaterialField same = MaterialField::uniform(mesh.num_tets(), scene.reference_Y, scene.reference_nu,
                                                    scene.reference_rho, 1.0);
  EvaluationOptions options;
  options.soft_control = false;
  for (const auto& [plane_friction, mu] : {std::pair<std::string, double>{"", 0.4}, {"0.3", 0.3}}) {
    const Scene s = with("0.4", plane_friction);
    const Evaluation ev = evaluate(s, mesh, mesh, same, options);
    ASSERT_EQ(ev.rigid_friction.size(), 1u);
    EXPECT_EQ(ev.rigid_friction[0].name, "plane 0");
    EXPECT_EQ(ev.rigid_friction[0].contact, RestitutionContact::kPlane);
    EXPECT_EQ(ev.rigid_friction[0].plane, 0);
    EXPECT_DOUBLE_EQ(ev.rigid_friction[0].friction, mu);
    const double expected = 1.0 - mu * 9.8 * 0.2;
    std::printf("floor mu = %.1f: after 0.2 s rigid %.4f m/s, deformable %.4f m/s (Coulomb %.4f)\n", mu,
                ev.rigid_reference.velocity.back().y(), ev.deformable_reference.velocity.back().y(), expected);
    EXPECT_NEAR(ev.rigid_reference.velocity.back().y(), expected, 0.03);
    EXPECT_NEAR(ev.deformable_reference.velocity.back().y(), expected, 0.03);
    // report.json's rigid.friction: every contact with its coefficient, named as the calibrations.
    const test::ScratchDir scratch;
    const std::string dir = scratch.path().string();
    write_evaluation(ev, s, dir);
    std::ifstream in(dir + "/report.json");
    const auto report = nlohmann::json::parse(in);
    const nlohmann::json& friction = report["rigid"]["friction"];
    ASSERT_EQ(friction.size(), 1u) << friction.dump();
    EXPECT_EQ(friction[0]["contact"], "plane 0");
    EXPECT_EQ(friction[0]["kind"], "plane");
    EXPECT_EQ(friction[0]["plane"], 0);
    EXPECT_DOUBLE_EQ(friction[0]["friction"].get<double>(), mu);
    EXPECT_EQ(report["friction_iterations"], 1);
    EXPECT_EQ(test::read_text(dir + "/summary.md").find("re-lagged"), std::string::npos);
  }
  // Friction re-lagged within each step (contact.friction_iterations): the same Coulomb on a
  // steady slide, and both reports say how the deformable runs lagged it.
  Scene relagged = with("0.4", "");
  relagged.friction_iterations = 2;
  const Evaluation ev = evaluate(relagged, mesh, mesh, same, options);
  EXPECT_NEAR(ev.deformable_reference.velocity.back().y(), 1.0 - 0.4 * 9.8 * 0.2, 0.03);
  const test::ScratchDir scratch;
  const std::string dir = scratch.path().string();
  write_evaluation(ev, relagged, dir);
  std::ifstream in(dir + "/report.json");
  EXPECT_EQ(nlohmann::json::parse(in)["friction_iterations"], 2);
  const std::string summary = test::read_text(dir + "/summary.md");
  EXPECT_NE(summary.find("deformable friction re-lagged up to 2 times per step"), std::string::npos);
}

}  // namespace
}  // namespace rbaa

namespace rbaa {
namespace {

// A demonstration that turns its object (the cube stack's striker, 45 deg about x) takes an
// attack's object that was designed unturned (its attack config's pose): evaluate turns it by the
// demonstration's rotation about its middle and moves it into place, materials and all. An object
// that matches neither way is still refused.
TEST(EvaluationDemonstration, AnUnturnedAttackObjectIsTurnedIntoTheDemonstrationsPose) {
  const std::string cube =
      "mesh: {shape: cube, side: 0.1, target_tets: 200}\n"
      "time: {step: 0.01, duration: 0.05}\n"
      "evaluation: {time_step: 0.01, duration: 0.05}\n"
      "contact: {kappa: 1.0e5}\n"
      "gravity: off\n";
  const Scene attack = parse_scene(cube + "object: {position: [0, 0, 1], velocity: [0, 0, -1]}\n",
                                   "attack.yaml", "");
  const Scene demo = parse_scene(cube +
                                     "object: {position: [2, 0, 1], velocity: [0, 0, -1], "
                                     "rotation: {axis: [1, 0, 0], angle_deg: 45}}\n"
                                     "demonstration: {figure: angle}\n",
                                 "demo.yaml", "");
  const TetMesh attacked = make_scene_mesh(attack);
  const TetMesh reference = make_scene_mesh(demo);
  // Heavier elements on the +y side, so that turning the materials with the mesh matters.
  MaterialField materials = MaterialField::uniform(attacked.num_tets(), 5e9, 0.3, 1000, 1.0);
  for (int e = 0; e < attacked.num_tets(); ++e) {
    double y = 0;
    for (int k = 0; k < 4; ++k) y += attacked.V(attacked.T(e, k), 1) / 4;
    if (y > 0) materials.rho[e] = 3000;
  }
  const Evaluation ev = evaluate(demo, reference, attacked, materials);
  // Where each element's vertices went: the demonstration's 45 deg turn about the cube's middle.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::RowVector3d from = 0.5 * (attacked.V.colwise().minCoeff() + attacked.V.colwise().maxCoeff());
  // Its middle: the reference's, then moved so that its centre of mass (heavier on one side) sits
  // at object.position as the reference's does.
  const Eigen::RowVector3d to =
      0.5 * (ev.adversarial_mesh.V.colwise().minCoeff() + ev.adversarial_mesh.V.colwise().maxCoeff());
  ASSERT_EQ(ev.adversarial_mesh.num_vertices(), attacked.num_vertices());
  double worst = 0;
  for (int i = 0; i < attacked.num_vertices(); ++i) {
    const Eigen::RowVector3d expected = (attacked.V.row(i) - from) * R.transpose() + to;
    worst = std::max(worst, (ev.adversarial_mesh.V.row(i) - expected).norm());
  }
  EXPECT_LT(worst, 1e-9);
  // The heavy half now lies towards +y +z (turned 45 deg about x): the centre of mass relative to
  // the middle is turned with it.
  const Eigen::Vector3d c_attack = compute_moments(attacked, materials.effective_density()).centre_of_mass() - from.transpose();
  const Eigen::Vector3d c_demo = ev.adversarial_moments.centre_of_mass() - to.transpose();
  EXPECT_GT(c_attack.y(), 1e-3);
  EXPECT_LT((c_demo - R * c_attack).norm(), 1e-9);
  EXPECT_LT((ev.adversarial_moments.centre_of_mass() - demo.position).norm(), 1e-12);

  // A shape that is neither the reference's as it is nor turned: refused.
  TetMesh stretched = attacked;
  stretched.V.col(0) *= 1.1;
  try {
    evaluate(demo, reference, stretched, materials);
    FAIL() << "a different shape was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bounding box differs"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rbaa
