#include "rbaa/sweep/config_fingerprint.hpp"

#include <yaml-cpp/yaml.h>

#include <exception>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <system_error>
#include <vector>

#include "rbaa/scene/scene.hpp"
#include "rbaa/scene/scene_fingerprint.hpp"

namespace rbaa {
namespace {

namespace fs = std::filesystem;

// One line per file of the config's `base:` chain, the config's first. A base resolves against
// the folder of the file that names it, as the scene's loader does (scene.cpp, with_base); a
// cycle or an unreadable file ends the chain (loading the scene reports it).
void add_documents(const fs::path& file, std::set<std::string>& seen, std::ostream& text) {
  std::error_code ec;
  const fs::path canonical = fs::weakly_canonical(file, ec);
  if (!seen.insert(ec ? file.string() : canonical.string()).second) return;
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    text << "file unreadable " << file.string() << "\n";
    return;
  }
  std::stringstream bytes;
  bytes << in.rdbuf();
  YAML::Node doc;
  try {
    doc = YAML::Load(bytes.str());
  } catch (const YAML::Exception&) {
    text << "file bytes " << fingerprint_hex(bytes.str()) << "\n";
    return;
  }
  text << "file yaml " << fingerprint_hex(YAML::Dump(doc)) << "\n";
  if (doc.IsMap() && doc["base"] && doc["base"].IsScalar() && !doc["base"].Scalar().empty()) {
    fs::path base(doc["base"].Scalar());
    if (base.is_relative()) base = file.parent_path() / base;
    add_documents(base.lexically_normal(), seen, text);
  }
}

}  // namespace

std::string config_fingerprint_text(const SweepGrid& grid) {
  std::ostringstream text;
  text << "rbaa-sweep-config 1\n";
  std::set<std::string> seen;
  add_documents(grid.config, seen, text);
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

}  // namespace rbaa
