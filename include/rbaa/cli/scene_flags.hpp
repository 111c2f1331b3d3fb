#pragma once
// The flags every scene-driven verb shares: --config=FILE and --set=key.path=value[;...].

#include <string>
#include <vector>

#include "rbaa/scene/scene.hpp"

namespace rbaa::cli {

/// Names of the shared scene flags, for a verb's flag list in its help.
std::vector<std::string> scene_flag_names();

/// Loads --config with the --set overrides applied; throws InputError if --config is missing.
Scene load_scene_from_flags();

}  // namespace rbaa::cli
