#include "rbaa/cli/scene_flags.hpp"

#include <gflags/gflags.h>

#include <sstream>

#include "rbaa/error.hpp"

DEFINE_string(config, "", "scene config (YAML), e.g. configs/ball.yaml");
DEFINE_string(set, "", "override config values: key.path=value[;key.path=value...], "
                       "e.g. --set='time.step=0.005;attack.iterations=10'; repeatable, in order: "
                       "--set=time.step=0.005 --set=attack.iterations=10");

namespace rbaa::cli {

std::vector<std::string> scene_flag_names() { return {"config", "set"}; }

Scene load_scene_from_flags() {
  if (FLAGS_config.empty()) throw InputError("--config is required");
  std::vector<std::string> overrides;
  std::stringstream ss(FLAGS_set);
  for (std::string item; std::getline(ss, item, ';');) {
    if (!item.empty()) overrides.push_back(item);
  }
  return load_scene(FLAGS_config, overrides);
}

}  // namespace rbaa::cli
