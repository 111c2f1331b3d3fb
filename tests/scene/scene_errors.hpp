#pragma once
// The one-line error a scene config gives, for the scene tests' bad-input cases: "" when it loads.

#include <string>
#include <vector>

#include "rbaa/error.hpp"
#include "rbaa/scene/scene.hpp"
#include "rbaa/scene/scene_mesh.hpp"
#include "rbaa/scene/scene_world.hpp"

namespace rbaa::test {

/// parse_scene's error (validation of the keys alone).
inline std::string scene_parse_error(const std::string& yaml,
                                     const std::vector<std::string>& overrides = {}) {
  try {
    parse_scene(yaml, "test.yaml", "", overrides);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// The error of parsing and then placing the scene's bodies (meshing, drives, stacking).
inline std::string scene_world_error(const std::string& yaml,
                                     const std::vector<std::string>& overrides = {}) {
  try {
    const Scene scene = parse_scene(yaml, "test.yaml", "", overrides);
    make_world(scene, make_scene_mesh(scene));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace rbaa::test
