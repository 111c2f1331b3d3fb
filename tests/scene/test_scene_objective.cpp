// The attack's objective and attacked body in a config (issue 16 item 4, issue 19's DesignSpace
// mask): `objective: {body, kind, component, value}` and `attack.body`; the undirected term of
// the object stays the default; bad input is one line naming the key and the value; the
// fingerprint sees a non-default objective and leaves older fingerprints alone.

#include <gtest/gtest.h>

#include <string>

#include "rbaa/error.hpp"
#include "rbaa/scene/scene.hpp"
#include "rbaa/scene/scene_fingerprint.hpp"
#include "scene/scene_errors.hpp"

namespace rbaa {
namespace {

std::string two_balls(const std::string& extra = "") {
  return "mesh: {shape: sphere, radius: 0.05, target_tets: 100}\n"
         "object: {position: [0, 0, 0.1], velocity: [2, 0, 0]}\n"
         "bodies:\n"
         "  - {name: target, mesh: {shape: sphere, radius: 0.06}, position: [0.2, 0, 0.1]}\n" +
         extra;
}


TEST(SceneObjective, DefaultsToTheUndirectedTermOfTheObject) {
  const Scene s = parse_scene(two_balls(), "test.yaml", "");
  EXPECT_EQ(s.attack_body, "object");
  EXPECT_EQ(s.objective.kind, ObjectiveSpec::Kind::kUndirected);
  EXPECT_EQ(s.objective.body, "");
}

TEST(SceneObjective, NamesABodyAKindAComponentAndAValue) {
  const Scene t = parse_scene(
      two_balls("objective: {body: target, kind: target, component: y, value: -0.25}\n"),
      "test.yaml", "");
  EXPECT_EQ(t.objective.kind, ObjectiveSpec::Kind::kTarget);
  EXPECT_EQ(t.objective.body, "target");
  EXPECT_EQ(t.objective.component, 1);
  EXPECT_EQ(t.objective.value, -0.25);
  const Scene a =
      parse_scene(two_balls("objective: {body: target, kind: away}\n"), "test.yaml", "");
  EXPECT_EQ(a.objective.kind, ObjectiveSpec::Kind::kAway);
  const Scene b =
      parse_scene(two_balls("attack: {body: target}\nobjective: {kind: away, body: object}\n"),
                  "test.yaml", "");
  EXPECT_EQ(b.attack_body, "target");
  EXPECT_EQ(b.objective.body, "object");
  // --set reaches it like any key.
  const Scene o =
      parse_scene(two_balls(), "test.yaml", "",
                  {"objective.kind=target", "objective.component=z", "objective.value=0.5"});
  EXPECT_EQ(o.objective.kind, ObjectiveSpec::Kind::kTarget);
  EXPECT_EQ(o.objective.component, 2);
}

TEST(SceneObjective, BadInputIsOneLineNamingTheKeyAndValue) {
  const struct {
    std::string extra, key, says;
  } cases[] = {
      {"objective: {body: ghost, kind: away}\n", "objective.body",
       "'ghost' is not one of: object, target"},
      {"objective: {body: target, kind: closer}\n", "objective.kind", "'closer'"},
      {"objective: {kind: target, component: w, value: 0}\n", "objective.component", "'w'"},
      {"objective: {kind: target, component: x, value: .nan}\n", "objective.value",
       ".nan is not finite"},
      {"objective: {kind: target, component: x, value: inf}\n", "objective.value",
       "inf is not finite"},
      {"objective: {kind: target, component: x}\n", "objective.value", "missing"},
      {"objective: {kind: target, value: 1}\n", "objective.component", "missing"},
      {"objective: {body: target}\n", "objective.kind", "missing"},
      {"objective: {kind: away, value: 1}\n", "objective.value", "only kind target"},
      {"objective: {kind: away, colour: red}\n", "objective.colour", "unknown key"},
      {"objective: target\n", "objective", "expected a mapping"},
      {"attack: {body: ghost}\n", "attack.body", "'ghost' is not one of: object, target"},
  };
  for (const auto& c : cases) {
    const std::string e = test::scene_parse_error(two_balls(c.extra));
    EXPECT_NE(e.find("key '" + c.key + "'"), std::string::npos) << c.extra << " -> " << e;
    EXPECT_NE(e.find(c.says), std::string::npos) << c.extra << " -> " << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    EXPECT_EQ(e.rfind("test.yaml:", 0), 0u) << e;
  }
  // An attacked body with a materials file: its materials would be ignored, so it is refused.
  const std::string m = test::scene_parse_error(
      "mesh: {shape: sphere, radius: 0.05}\nbodies:\n  - {name: b, mesh: {shape: cube}, "
      "position: [1, 0, 0], materials: b.csv}\nattack: {body: b}\n");
  EXPECT_NE(m.find("key 'attack.body'"), std::string::npos) << m;
  EXPECT_NE(m.find("materials file"), std::string::npos) << m;
}

TEST(SceneObjective, TheFingerprintSeesANonDefaultObjectiveOnly) {
  const std::string base = scene_fingerprint_text(parse_scene(two_balls(), "test.yaml", ""));
  EXPECT_EQ(base.find("objective"), std::string::npos);
  EXPECT_EQ(base.find("attack.body"), std::string::npos);
  const auto fp = [](const std::string& yaml) {
    return scene_fingerprint(parse_scene(yaml, "test.yaml", ""));
  };
  const std::string target =
      fp(two_balls("objective: {body: target, kind: target, component: x, value: 0}\n"));
  EXPECT_NE(target, fp(two_balls()));
  EXPECT_NE(target,
            fp(two_balls("objective: {body: target, kind: target, component: x, value: 0.1}\n")));
  EXPECT_NE(target,
            fp(two_balls("objective: {body: target, kind: target, component: y, value: 0}\n")));
  EXPECT_NE(fp(two_balls("objective: {body: target, kind: away}\n")), fp(two_balls()));
  EXPECT_NE(fp(two_balls("attack: {body: target}\n")), fp(two_balls()));
}

}  // namespace
}  // namespace rbaa
