// The `demonstration` block (issue 17): a predicate (through_hoop, inside_box, stands) and a
// figure; each bad input is one line naming the file, the line and the key. The shipped
// demonstration configs load.

#include <gtest/gtest.h>

#include <string>

#include "rbaa/error.hpp"
#include "rbaa/scene/scene.hpp"
#include "scene/scene_errors.hpp"

namespace rbaa {
namespace {

std::string two_cubes(const std::string& demo) {
  return "mesh: {shape: cube, side: 0.05, target_tets: 100}\n"
         "object: {position: [0, 0, 0.3], velocity: [0, 0, -1]}\n"
         "bodies:\n"
         "  - {name: low, mesh: {shape: cube, side: 0.05}, position: [0, 0, 0.026]}\n"
         "obstacles: {planes: [{normal: [0, 0, 1], offset: 0}]}\n"
         "demonstration:\n" +
         demo;
}


TEST(SceneDemonstration, NoBlockNoDemonstration) {
  const Scene s = parse_scene("mesh: {shape: sphere}\n", "test.yaml", "");
  EXPECT_FALSE(s.demonstration.enabled);
}

TEST(SceneDemonstration, ReadsEachPredicate) {
  Scene s = parse_scene(
      two_cubes("  predicate: {kind: through_hoop, centre: [0, -0.38, 3.048], radius: 0.2286}\n"
                "  figure: angle\n"),
      "test.yaml", "");
  ASSERT_TRUE(s.demonstration.enabled);
  const PredicateSpec& hoop = s.demonstration.predicate;
  EXPECT_EQ(hoop.kind, PredicateSpec::Kind::kThroughHoop);
  EXPECT_EQ(hoop.body, "object");
  EXPECT_DOUBLE_EQ(hoop.centre.y(), -0.38);
  EXPECT_EQ(hoop.axis, Eigen::Vector3d::UnitZ());
  EXPECT_DOUBLE_EQ(hoop.radius, 0.2286);
  EXPECT_EQ(s.demonstration.figure, "angle");
  EXPECT_EQ(s.demonstration.figure_body, "object");

  s = parse_scene(
      two_cubes("  predicate: {kind: inside_box, body: low, min: [-1, -1, 0], max: [1, 1, 1],"
                " stays_below_top: true}\n"),
      "test.yaml", "");
  EXPECT_EQ(s.demonstration.predicate.kind, PredicateSpec::Kind::kInsideBox);
  EXPECT_EQ(s.demonstration.predicate.body, "low");
  EXPECT_TRUE(s.demonstration.predicate.stays_below_top);
  EXPECT_TRUE(s.demonstration.figure.empty());

  s = parse_scene(
      two_cubes("  predicate: {kind: stands, bodies: [low, object], min_height: [0.02, 0.05]}\n"),
      "test.yaml", "");
  EXPECT_EQ(s.demonstration.predicate.kind, PredicateSpec::Kind::kStands);
  EXPECT_EQ(s.demonstration.predicate.bodies.size(), 2u);
  EXPECT_DOUBLE_EQ(s.demonstration.predicate.max_tilt_deg, 10.0);
  EXPECT_DOUBLE_EQ(s.demonstration.predicate.min_height[1], 0.05);

  // evaluation.body is the default body of the predicate and the figure.
  s = parse_scene(two_cubes("  figure: angle\n") + "evaluation: {body: low}\n", "test.yaml", "");
  EXPECT_EQ(s.demonstration.figure_body, "low");
}

TEST(SceneDemonstration, BadInputIsOneLineNamingFileLineAndKey) {
  struct Case {
    std::string demo, fragment;
  };
  const std::vector<Case> cases = {
      {"  figure: angle\n  predicate: {kind: hoop}\n",
       "key 'demonstration.predicate.kind': 'hoop' is not one of"},
      {"  predicate: {centre: [0, 0, 1], radius: 1}\n",
       "key 'demonstration.predicate.kind': missing"},
      {"  predicate: {kind: through_hoop, radius: 0.2}\n",
       "key 'demonstration.predicate.centre': missing"},
      {"  predicate: {kind: through_hoop, centre: [0, 0, 1], radius: -0.2}\n",
       "value -0.2 is outside"},
      {"  predicate: {kind: through_hoop, centre: [0, 0, 1], radius: 0.2, axis: [0, 0, 0]}\n",
       "is not a direction"},
      {"  predicate: {kind: through_hoop, centre: [0, 0], radius: 0.2}\n",
       "expected a list of 3 numbers"},
      {"  predicate: {kind: through_hoop, centre: [0, 0, 1], radius: 0.2, body: ghost}\n",
       "'ghost' is not one of"},
      {"  predicate: {kind: through_hoop, centre: [0, 0, 1], radius: 0.2, min: [0, 0, 0]}\n",
       "key 'demonstration.predicate.min': unknown key"},
      {"  predicate: {kind: inside_box, min: [0, 0, 0], max: [1, -1, 1]}\n", "must exceed min"},
      {"  predicate: {kind: inside_box, min: [0, 0, 0]}\n",
       "key 'demonstration.predicate.max': missing"},
      {"  predicate: {kind: inside_box, min: [0, 0, 0], max: [1, 1, 1], stays_below_top: maybe}\n",
       "'maybe' is not one of"},
      {"  predicate: {kind: stands, bodies: [low, ghost], min_height: 0}\n",
       "'ghost' names no body"},
      {"  predicate: {kind: stands, bodies: [low, low], min_height: 0}\n", "'low' is listed twice"},
      {"  predicate: {kind: stands, bodies: [], min_height: 0}\n", "expected a non-empty list"},
      {"  predicate: {kind: stands, bodies: [low]}\n",
       "key 'demonstration.predicate.min_height': missing"},
      {"  predicate: {kind: stands, bodies: [low, object], min_height: [0, 0, 0]}\n",
       "expected one height or 2"},
      {"  predicate: {kind: stands, bodies: [low], min_height: 0, max_tilt_deg: 0}\n",
       "value 0 is outside"},
      {"  figure: separation\n", "key 'demonstration.figure': 'separation' is not one of"},
      {"  figure: angle\n  figure_against: deformable\n",
       "key 'demonstration.figure_against': 'deformable' is not one of"},
      {"  figure: angle\n  figure_projection: vertical\n",
       "key 'demonstration.figure_projection': 'vertical' is not one of"},
      {"  figure: angle\n  figure_body: ghost\n", "'ghost' is not one of"},
      {"  figures: angle\n", "key 'demonstration.figures': unknown key"},
      {"  {}\n", "give a predicate, a figure or both"},
  };
  for (const Case& c : cases) {
    const std::string what = test::scene_parse_error(two_cubes(c.demo));
    EXPECT_NE(what.find(c.fragment), std::string::npos) << c.demo << " -> " << what;
    EXPECT_EQ(what.rfind("test.yaml:", 0), 0u) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

TEST(SceneDemonstration, HorizontalFigureNeedsGravity) {
  const std::string what = test::scene_parse_error(
      "mesh: {shape: sphere}\ngravity: off\n"
      "demonstration: {figure: angle, figure_projection: horizontal}\n");
  EXPECT_NE(what.find("key 'demonstration.figure_projection': horizontal needs gravity"),
            std::string::npos)
      << what;
  const Scene s = parse_scene(two_cubes("  figure: angle\n  figure_against: own_simulator\n"
                                        "  figure_projection: horizontal\n"),
                              "test.yaml", "");
  EXPECT_TRUE(s.demonstration.figure_against_own_simulator);
  EXPECT_TRUE(s.demonstration.figure_horizontal);
  EXPECT_FALSE(parse_scene(two_cubes("  figure: angle\n"), "test.yaml", "")
                   .demonstration.figure_against_own_simulator);
}

TEST(SceneDemonstration, TheShippedDemonstrationsLoad) {
  for (const char* name : {"ball_hoop", "bunny_bin", "cube_stack"}) {
    const Scene s = load_scene(std::string(RBAA_SOURCE_DIR) + "/configs/demos/" + name + ".yaml");
    EXPECT_TRUE(s.demonstration.enabled) << name;
    EXPECT_NE(s.demonstration.predicate.kind, PredicateSpec::Kind::kNone) << name;
  }
  // The star and the bat have a figure and no predicate (the paper reports their angles).
  const Scene star = load_scene(std::string(RBAA_SOURCE_DIR) + "/configs/demos/star.yaml");
  EXPECT_EQ(star.demonstration.figure, "angle");
  EXPECT_TRUE(star.demonstration.figure_against_own_simulator);
  EXPECT_EQ(star.planes.size(), 2u);
  EXPECT_DOUBLE_EQ(star.evaluation_duration, 1.0);
  const Scene bat = load_scene(std::string(RBAA_SOURCE_DIR) + "/configs/demos/bat.yaml");
  EXPECT_EQ(bat.demonstration.figure_body, "ball");
  EXPECT_TRUE(bat.demonstration.figure_horizontal);
  EXPECT_DOUBLE_EQ(bat.evaluation_duration, 2.0);
  // The same scene as the attack's, so that its objects fit and the figure means the attack's;
  // configs/bat_accurate.yaml attacks it at the discretisation the demonstration evaluates at
  // (h = 1 ms with contact-resolving steps).
  const Scene attack = load_scene(std::string(RBAA_SOURCE_DIR) + "/configs/bat.yaml");
  const Scene accurate = load_scene(std::string(RBAA_SOURCE_DIR) + "/configs/bat_accurate.yaml");
  for (const Scene* s : {&bat, &accurate}) {
    EXPECT_EQ(s->position, attack.position) << s->name;
    EXPECT_EQ(s->bodies.at(0).position, attack.bodies.at(0).position) << s->name;
    EXPECT_EQ(s->driven.motion.centre, attack.driven.motion.centre) << s->name;
    EXPECT_EQ(s->rotation_angle_deg, attack.rotation_angle_deg) << s->name;
    EXPECT_EQ(s->kappa, attack.kappa) << s->name;
  }
  EXPECT_GT(bat.contact_substeps, 0);
  EXPECT_EQ(bat.contact_substeps, accurate.contact_substeps);
  EXPECT_DOUBLE_EQ(bat.evaluation_time_step, accurate.time_step);
}

}  // namespace
}  // namespace rbaa
