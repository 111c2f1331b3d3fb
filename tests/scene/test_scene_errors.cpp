// Every kind of config error names the file and the line of the value at fault: each case puts
// its bad value on a known line of an otherwise valid config and expects "test.yaml:LINE: ".

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "rbaa/error.hpp"
#include "rbaa/scene/scene.hpp"

namespace rbaa {
namespace {

// A valid config, one key per line (line numbers in the comments).
const std::vector<std::string> kValid = {
    "mesh: {shape: sphere, target_tets: 300}",                      // 1
    "object: {position: [0, 0, 0.5], velocity: [0, 0, -1]}",        // 2
    "obstacles: {planes: [{normal: [0, 0, 1], offset: 0}]}",        // 3
    "gravity: [0, 0, -9.8]",                                        // 4
    "time: {step: 0.01, duration: 0.1, integrator: bdf2}",          // 5
    "contact: {d_hat: 1.0e-3, kappa: auto}",                        // 6
    "reference_material: {Y: 1.0e13, nu: 0.28, rho: 2500}",         // 7
    "material_bounds: {Y: [2.5e9, 6.5e11], nu: [0.2, 0.4]}",        // 8
    "attack: {fields: [Y, nu, rho, alpha], iterations: 5}",         // 9
};

struct ErrorCase {
  int line;              // 1-based line whose text is replaced
  std::string text;      // the replacement
  std::string fragment;  // part of the message after the location
};

std::string config_with(const ErrorCase& c) {
  std::string yaml;
  for (int i = 0; i < static_cast<int>(kValid.size()); ++i) {
    yaml += (i + 1 == c.line ? c.text : kValid[i]) + "\n";
  }
  return yaml;
}

TEST(SceneErrors, ValidConfigParses) { EXPECT_NO_THROW(parse_scene(config_with({0, "", ""}), "test.yaml", "")); }

TEST(SceneErrors, EveryKindNamesItsLine) {
  const std::vector<ErrorCase> cases = {
      {4, "gravity: [0, 0]", "expected a list of 3 numbers"},
      {5, "time: {step: fast, duration: 0.1}", "expected a number, got 'fast'"},
      {5, "time: {step: .nan, duration: 0.1}", "is not finite"},
      {5, "time: {step: -0.01, duration: 0.1}", "time.step"},
      {5, "time: {step: 0.01, duration: 0.001}", "shorter than one time step"},
      {5, "time: {step: 0.01, duration: 0.1, integrator: rk4}", "'rk4' is not one of"},
      {5, "time: {step: 0.01, duration: 0.1, contact_substeps: 12}", "not 0 (off) or a power of two"},
      {5, "time: {step: 0.01, duration: 0.1, contact_substeps: 1}", "not 0 (off) or a power of two"},
      {5, "time: {step: 0.01, duration: 0.1, contact_substeps: 2048}", "contact_substeps"},
      {9, "attack: {iterations: 2.5}", "expected a whole number"},
      {9, "attack: {fields: [Y, Young]}", "'Young' is not one of Y, nu, rho, alpha"},
      {9, "attack: {fields: [Y, Y]}", "is listed twice"},
      {9, "attack: {fields: []}", "expected a non-empty list"},
      {8, "material_bounds: {Y: [6.5e11, 2.5e9]}", "min must be below max"},
      {8, "material_bounds: {Y: 3}", "expected a list [min, max]"},
      {6, "contact: {d_hat: 1.0e-3, kappaa: 1}", "unknown key"},
      {6, "contact: {d_hat: 1.0e-3, friction_iterations: 0}", "friction_iterations"},
      {6, "contact: {d_hat: 1.0e-3, friction_iterations: 101}", "friction_iterations"},
      {6, "contact: {d_hat: 1.0e-3, friction_iterations: 2.5}", "expected a whole number"},
      {3, "obstacles: {planes: {normal: [0, 0, 1]}}", "expected a list of planes"},
      {3, "obstacles: {planes: [{normal: [0, 0, 0], offset: 0}]}", "missing or zero normal"},
      {3, "obstacles: {planes: [{normal: [0, 0, 1], offset: 0, point: [0, 0, 0]}]}",
       "give exactly one of offset, point"},
      {1, "mesh: {shape: sphere, file: x.msh}", "give exactly one of shape, surface, file"},
      {2, "object: {position: [0, 0, 0.5], rotation: {axis: [0, 0, 0], angle_deg: 5}}",
       "axis must be non-zero"},
      {7, "reference_material: {Y: [1, 2], nu: 0.28, rho: 2500}", "expected a number"},
      {5, "time: {step: 0.01, duration: [0.1}", "invalid YAML"},
  };
  for (const ErrorCase& c : cases) {
    try {
      parse_scene(config_with(c), "test.yaml", "");
      ADD_FAILURE() << "no error for line " << c.line << ": " << c.text;
    } catch (const InputError& e) {
      const std::string what = e.what();
      const std::string location = "test.yaml:" + std::to_string(c.line) + ": ";
      EXPECT_EQ(what.rfind(location, 0), 0u) << c.text << "\n  -> " << what;
      EXPECT_NE(what.find(c.fragment), std::string::npos) << c.text << "\n  -> " << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
}

}  // namespace
}  // namespace rbaa
