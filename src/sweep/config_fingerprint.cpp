#include "rbaa/sweep/config_fingerprint.hpp"

#include <yaml-cpp/yaml.h>

#include <exception>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>
#include <vector>

#include "rbaa/scene/scene.hpp"
#include "rbaa/scene/scene_fingerprint.hpp"

namespace rbaa {
namespace {

namespace fs = std::filesystem;

// One line per file a value names, with its bytes' fingerprint: `names` are the value's words
// (a --set value's scalar or the items of its flat list; a flag's value as it is), each resolved
// against `folder` as the row's process resolves it. Words that name no regular file (numbers,
// keywords, files not made yet) print nothing: they count by the row's arguments.
void add_named_files(const std::string& what, const std::vector<std::string>& names,
                     const fs::path& folder, std::ostream& text) {
  for (const std::string& name : names) {
    if (name.empty()) continue;
    fs::path path(name);
    if (path.is_relative()) path = folder / path;
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) continue;
    std::ifstream in(path, std::ios::binary);
    std::stringstream bytes;
    bytes << in.rdbuf();
    text << what << " names " << name << ": bytes " << fingerprint_hex(bytes.str()) << "\n";
  }
}

std::vector<std::string> set_value_words(const std::string& value) {
  try {
    const YAML::Node node = YAML::Load(value);
    if (node.IsScalar()) return {node.Scalar()};
    std::vector<std::string> words;
    if (node.IsSequence()) {
      for (const auto& item : node) {
        if (item.IsScalar()) words.push_back(item.Scalar());
      }
    }
    return words;
  } catch (const YAML::Exception&) {
    return {value};  // the row fails on it with the scene's error
  }
}

}  // namespace

std::string config_fingerprint_text(const SweepGrid& grid) {
  std::ostringstream text;
  text << "rbaa-sweep-config 2\n";
  // The config with the files it builds on (base:) merged in, as the scene's loader reads it.
  try {
    text << "config yaml " << fingerprint_hex(merged_config_text(grid.config)) << "\n";
  } catch (const std::exception&) {
    text << "config unloadable\n";  // its rows fail with the loader's error
  }
  std::vector<std::string> overrides;
  for (const SweepOverride& o : grid.fixed) overrides.push_back(o.key + "=" + o.value);
  try {
    text << "scene " << scene_fingerprint(load_scene(grid.config, overrides)) << "\n";
  } catch (const std::exception&) {
    text << "scene unloadable\n";
  }
  return text.str();
}

std::string config_fingerprint(const SweepGrid& grid) {
  return fingerprint_hex(config_fingerprint_text(grid));
}

std::string row_files_text(const SweepGrid& grid, const SweepRow& row) {
  std::ostringstream text;
  // The scene resolves a --set path against the config's folder (scene.cpp, add_command_line);
  // the row's process runs in this process's folder, where a flag's path resolves.
  const fs::path config_folder = fs::path(grid.config).parent_path();
  for (const SweepOverride& o : row.overrides) {
    add_named_files("set " + o.key, set_value_words(o.value), config_folder, text);
  }
  std::error_code ec;
  const fs::path here = fs::current_path(ec);
  for (const SweepFlag& f : grid.flags) add_named_files("flag --" + f.name, {f.value}, here, text);
  return text.str();
}

std::string row_config_fingerprint(const std::string& config_fingerprint, const SweepGrid& grid,
                                   const SweepRow& row) {
  const std::string files = row_files_text(grid, row);
  // A row that names no file keeps the grid's fingerprint, as markers written before hold it.
  return files.empty() ? config_fingerprint : fingerprint_hex(config_fingerprint + "\n" + files);
}

}  // namespace rbaa
