#include "rbaa/scene/scene.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "rbaa/error.hpp"
#include "rbaa/io/text_reader.hpp"
#include "rbaa/io/triangle_soup.hpp"
#include "rbaa/mesh/tetrahedralize.hpp"
#include "yaml_keys.hpp"

namespace rbaa {
namespace {

std::string resolve(const std::string& path, const std::string& base_dir) {
  namespace fs = std::filesystem;
  if (path.empty() || fs::path(path).is_absolute() || base_dir.empty()) return path;
  return (fs::path(base_dir) / path).lexically_normal().string();
}

// Which file each node of a config was written in: the config itself, or a file it builds on
// through `base:` (the merged document keeps every node's own line), so that an error names the
// file and line a person has to open, and a relative path resolves from the folder of the file
// that wrote it.
class ConfigOrigin {
 public:
  ConfigOrigin(std::string file, std::string folder) : top_{std::move(file), std::move(folder)} {}

  // Records every node (keys included) of a base document read from `file` in `folder`.
  void add(const YAML::Node& node, const std::string& file, const std::string& folder) {
    if (!node) return;
    nodes_.emplace_back(node, Where{file, folder});
    if (node.IsMap()) {
      for (const auto& kv : node) {
        add(kv.first, file, folder);
        add(kv.second, file, folder);
      }
    } else if (node.IsSequence()) {
      for (const auto& item : node) add(item, file, folder);
    }
  }

  // Records every node of a --set value, named by the config and `what` ("ball.yaml (--set
  // time.step)"); its paths resolve from the config's folder, and it has no line of its own.
  void add_command_line(const YAML::Node& node, const std::string& what) {
    const std::size_t first = nodes_.size();
    add(node, top_.file + " " + what, top_.folder);
    for (std::size_t i = first; i < nodes_.size(); ++i) nodes_[i].second.command_line = true;
  }

  const std::string& file_of(const YAML::Node& node) const { return where(node).file; }
  const std::string& folder_of(const YAML::Node& node) const { return where(node).folder; }
  bool from_command_line(const YAML::Node& node) const { return where(node).command_line; }

 private:
  struct Where {
    std::string file, folder;
    bool command_line = false;
  };

  const Where& where(const YAML::Node& node) const {
    if (node) {
      for (const auto& [base_node, at] : nodes_) {
        if (node.is(base_node)) return at;
      }
    }
    return top_;
  }

  Where top_;
  std::vector<std::pair<YAML::Node, Where>> nodes_;  // a few hundred at most: searched linearly
};

// Reads one YAML mapping against a fixed set of keys: every read names the key it consumes, and
// finish() rejects whatever was not consumed, so a misspelt key is an error rather than silently
// ignored. Errors read "FILE:LINE: key 'a.b': what is wrong".
class MapReader {
 public:
  MapReader(YAML::Node node, const ConfigOrigin& source, std::string prefix)
      : node_(std::move(node)), source_(&source), prefix_(std::move(prefix)) {
    if (node_ && !node_.IsNull() && !node_.IsMap()) fail(node_, "", "expected a mapping of keys");
  }

  bool has(const std::string& key) {
    seen_.insert(key);
    if (!node_ || !node_.IsMap() || !node_[key]) return false;
    const YAML::Node n = node_[key];
    // A key written with nothing after it (`step:`) is YAML's null: an error, not the default.
    // (Nodes yaml-cpp makes up while reading have no line.)
    if (n.IsNull() && n.Mark().line >= 0) {
      for (const auto& kv : node_) {  // the key's line: an empty value's is the next token's
        if (kv.first.Scalar() == key) fail(kv.first, key, "has no value");
      }
      fail(n, key, "has no value");
    }
    return !n.IsNull();
  }

  YAML::Node child(const std::string& key) {
    seen_.insert(key);
    return node_ && node_.IsMap() ? node_[key] : YAML::Node();
  }

  [[noreturn]] void fail(const YAML::Node& at, const std::string& key, const std::string& what) const {
    std::ostringstream msg;
    msg << source_->file_of(at);
    if (at && at.Mark().line >= 0 && !source_->from_command_line(at)) msg << ":" << at.Mark().line + 1;
    msg << ": ";
    if (!key.empty() || !prefix_.empty()) msg << "key '" << full(key) << "': ";
    msg << what;
    throw InputError(msg.str());
  }

  const ConfigOrigin& source() const { return *source_; }
  std::string full(const std::string& key) const {
    if (prefix_.empty()) return key;
    return key.empty() ? prefix_ : prefix_ + "." + key;
  }

  double number(const std::string& key, double fallback, double lo, double hi,
                bool lo_open = false, bool hi_open = false) {
    if (!has(key)) return fallback;
    const YAML::Node n = node_[key];
    return to_number(n, key, lo, hi, lo_open, hi_open);
  }

  double to_number(const YAML::Node& n, const std::string& key, double lo, double hi, bool lo_open,
                   bool hi_open) const {
    if (!n.IsScalar()) fail(n, key, "expected a number");
    const std::string text = n.Scalar();
    // YAML spells non-finite floats .nan / .inf; they are as wrong here as nan / inf.
    static const std::set<std::string> kYamlNonFinite = {".nan", ".NaN", ".NAN", ".inf", ".Inf",
                                                         ".INF", "+.inf", "-.inf", "-.Inf", "+.Inf"};
    if (kYamlNonFinite.count(text)) fail(n, key, "value " + text + " is not finite");
    double value = 0;
    try {
      size_t used = 0;
      value = std::stod(text, &used);
      if (used != text.size()) throw std::invalid_argument(text);
    } catch (const std::exception&) {
      fail(n, key, "expected a number, got '" + text + "'");
    }
    if (!std::isfinite(value)) fail(n, key, "value " + text + " is not finite");
    const bool below = lo_open ? value <= lo : value < lo;
    const bool above = hi_open ? value >= hi : value > hi;
    if (below || above) {
      std::ostringstream range;
      range << "value " << text << " is outside " << (lo_open ? "(" : "[") << lo << ", " << hi
            << (hi_open ? ")" : "]");
      fail(n, key, range.str());
    }
    return value;
  }

  int integer(const std::string& key, int fallback, int lo, int hi) {
    if (!has(key)) return fallback;
    const YAML::Node n = node_[key];
    const double v = to_number(n, key, lo, hi, false, false);
    if (v != std::floor(v)) fail(n, key, "expected a whole number, got " + n.Scalar());
    return static_cast<int>(v);
  }

  std::string text(const std::string& key, const std::string& fallback,
                   const std::set<std::string>& allowed = {}) {
    if (!has(key)) return fallback;
    const YAML::Node n = node_[key];
    if (!n.IsScalar()) fail(n, key, "expected a string");
    const std::string value = n.Scalar();
    if (!allowed.empty() && !allowed.count(value)) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      fail(n, key, "'" + value + "' is not one of: " + list);
    }
    return value;
  }

  // A file name, relative to the folder of the config (or base) that wrote it; "" when absent.
  std::string path(const std::string& key) {
    const std::string name = text(key, "");
    return name.empty() ? name : resolve(name, source_->folder_of(node_[key]));
  }

  Eigen::Vector3d vector3(const std::string& key, const Eigen::Vector3d& fallback) {
    if (!has(key)) return fallback;
    const YAML::Node n = node_[key];
    if (!n.IsSequence() || n.size() != 3) fail(n, key, "expected a list of 3 numbers [x, y, z]");
    Eigen::Vector3d v;
    const double inf = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 3; ++i) v[i] = to_number(n[i], key, -inf, inf, false, false);
    return v;
  }

  Range range(const std::string& key, const Range& fallback, const Range& limits) {
    if (!has(key)) return fallback;
    const YAML::Node n = node_[key];
    if (!n.IsSequence() || n.size() != 2) fail(n, key, "expected a list [min, max]");
    Range r{to_number(n[0], key, limits.lo, limits.hi, false, false),
            to_number(n[1], key, limits.lo, limits.hi, false, false)};
    if (!(r.lo < r.hi)) fail(n, key, "min must be below max");
    return r;
  }

  void finish() const {
    if (!node_ || !node_.IsMap()) return;
    for (const auto& kv : node_) {
      const std::string key = kv.first.as<std::string>();
      if (!seen_.count(key)) fail(kv.first, key, "unknown key");
    }
  }


 private:
  YAML::Node node_;
  const ConfigOrigin* source_;  // outlives the reader: parse_scene's
  std::string prefix_;
  std::set<std::string> seen_;
};

// Applies "a.b.c=value" to the document; the value is parsed as YAML (so lists work).
void apply_override(YAML::Node& root, const std::string& assignment, ConfigOrigin& origin) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw InputError("--set: expected key.path=value, got '" + assignment + "'");
  }
  const std::string path = assignment.substr(0, eq);
  YAML::Node value;
  try {
    value = YAML::Load(assignment.substr(eq + 1));
  } catch (const YAML::Exception& e) {
    throw InputError("--set " + path + ": cannot parse value: " + e.msg);
  }
  // An empty value would read as YAML's null, which the reader takes for an absent key: the
  // built-in default would then replace both the config's value and the one meant here.
  if (!value || value.IsNull()) throw InputError("--set " + path + ": no value after '='");
  check_keys(value, origin.file_of(YAML::Node()) + " (--set " + path + ")", path, false);
  origin.add_command_line(value, "(--set " + path + ")");
  std::vector<std::string> parts;
  std::stringstream ss(path);
  for (std::string part; std::getline(ss, part, '.');) parts.push_back(part);
  std::vector<YAML::Node> chain{root};
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    YAML::Node next = chain.back()[parts[i]];
    if (next && !next.IsNull() && !next.IsMap()) {
      throw InputError("--set " + path + ": '" + parts[i] + "' is not a mapping");
    }
    chain.push_back(next);
  }
  // A new entry rather than an assignment to the old one: assigning re-points the old node,
  // which ConfigOrigin may hold as a base's (its file and folder would then be claimed for the
  // command line's value).
  chain.back().remove(parts.back());
  chain.back()[parts.back()] = value;
}


YAML::Node load_yaml(const std::string& text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    std::ostringstream msg;
    msg << source << ":" << e.mark.line + 1 << ": invalid YAML: " << e.msg;
    throw InputError(msg.str());
  }
  if (!root || root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
  check_keys(root, source, "");
  return root;
}

// `over` laid over `under`: mappings merge key by key, anything else (a number, a list such as
// `bodies`) replaces what it lands on. A new document: neither input's nodes are changed, so
// every node keeps the identity ConfigOrigin recorded.
YAML::Node merged(const YAML::Node& under, const YAML::Node& over) {
  if (!under.IsMap() || !over.IsMap()) return over;
  YAML::Node out(YAML::NodeType::Map);
  for (const auto& kv : under) {
    const YAML::Node mine = over[kv.first.as<std::string>()];
    if (!mine) out[kv.first] = kv.second;
  }
  for (const auto& kv : over) {
    const YAML::Node theirs = under[kv.first.as<std::string>()];
    out[kv.first] = theirs ? merged(theirs, kv.second) : kv.second;
  }
  return out;
}

// The mapping `map` but for `key` (a new map of the same nodes).
YAML::Node without(const YAML::Node& map, const std::string& key) {
  YAML::Node out(YAML::NodeType::Map);
  for (const auto& kv : map) {
    if (kv.first.as<std::string>() != key) out[kv.first] = kv.second;
  }
  return out;
}

// A config's top-level `base: FILE` (relative to the config's folder): the config is FILE's
// document (with its own base, if any) with this one's keys laid over it; relative paths written
// in FILE resolve from FILE's folder. The base's `name` is not inherited (a config without one is
// named after its own file). `chain` holds the files being read, to refuse a cycle.
YAML::Node with_base(const YAML::Node& root, ConfigOrigin& origin, std::vector<std::string>& chain) {
  if (!root.IsMap() || !root["base"]) return root;
  const YAML::Node ref = root["base"];
  const std::string file = origin.file_of(ref);  // a copy: origin grows below
  const auto fail = [&](const std::string& what) {
    std::ostringstream msg;
    msg << file << ":" << ref.Mark().line + 1 << ": key 'base': " << what;
    throw InputError(msg.str());
  };
  if (!ref.IsScalar() || ref.Scalar().empty()) fail("expected a file name");
  const std::string name = ref.Scalar();
  const std::string path = resolve(name, origin.folder_of(ref));
  for (const auto& reading : chain) {
    if (std::filesystem::weakly_canonical(reading) == std::filesystem::weakly_canonical(path)) {
      std::string cycle;
      for (const auto& c : chain) cycle += std::filesystem::path(c).filename().string() + " -> ";
      fail("'" + name + "' is already being read (" + cycle + name + ")");
    }
  }
  std::string text;
  try {
    text = read_whole_file(path);
  } catch (const InputError& e) {
    fail(e.what());
  }
  chain.push_back(path);
  const YAML::Node base_doc = load_yaml(text, path);
  if (!base_doc.IsMap()) fail("'" + path + "' is not a mapping of keys");
  origin.add(base_doc, path, std::filesystem::path(path).parent_path().string());
  YAML::Node under = with_base(base_doc, origin, chain);
  chain.pop_back();
  return merged(without(under, "name"), without(root, "base"));
}

const std::set<std::string> kFields = {"Y", "nu", "rho", "alpha"};

// A mesh source (the top-level `mesh` or a body's): exactly one of shape, surface, file.
MeshSource read_mesh_source(const YAML::Node& node, const ConfigOrigin& source,
                            const std::string& key) {
  const double inf = std::numeric_limits<double>::infinity();
  MapReader m(node, source, key);
  MeshSource mesh;
  mesh.shape = m.text("shape", "", {"sphere", "cube", "star", "bat", "bunny"});
  mesh.surface_file = m.path("surface");
  mesh.mesh_file = m.path("file");
  const int sources = !mesh.shape.empty() + !mesh.surface_file.empty() + !mesh.mesh_file.empty();
  if (sources != 1) m.fail(node, "", "give exactly one of shape, surface, file");
  mesh.target_tets = m.integer("target_tets", 0, 10, 10000000);
  mesh.radius = m.number("radius", 0, 0, inf, true);
  mesh.side = m.number("side", 0, 0, inf, true);
  mesh.volume = m.number("volume", 0, 0, inf, true);
  // A size that the source does not use is an error, not ignored (a cube's radius, a file's
  // target_tets).
  const std::string what = !mesh.shape.empty()        ? "shape " + mesh.shape
                           : !mesh.surface_file.empty() ? std::string("a surface")
                                                        : std::string("a tet mesh file");
  auto unused = [&](const char* name, bool given, bool used) {
    if (given && !used) m.fail(m.child(name), name, std::string("does not apply to ") + what);
  };
  const std::string size = mesh.mesh_file.empty() ? mesh_size_key(mesh.shape) : "";
  unused("radius", mesh.radius > 0, size == "radius");
  unused("side", mesh.side > 0, size == "side");
  unused("volume", mesh.volume > 0, size == "volume");
  unused("target_tets", mesh.target_tets > 0, mesh.mesh_file.empty());
  m.finish();
  return mesh;
}

// A body's initial state: position, velocity, angular_velocity and rotation {axis, angle_deg}.
void read_pose(MapReader& o, Eigen::Vector3d& position, Eigen::Vector3d& velocity,
               Eigen::Vector3d& angular_velocity, Eigen::Vector3d& rotation_axis,
               double& rotation_angle_deg) {
  const double inf = std::numeric_limits<double>::infinity();
  position = o.vector3("position", position);
  velocity = o.vector3("velocity", velocity);
  angular_velocity = o.vector3("angular_velocity", angular_velocity);
  if (o.has("rotation")) {
    MapReader r(o.child("rotation"), o.source(), o.full("rotation"));
    rotation_axis = r.vector3("axis", rotation_axis);
    if (!(rotation_axis.norm() > 0)) r.fail(o.child("rotation"), "axis", "axis must be non-zero");
    rotation_axis.normalize();
    rotation_angle_deg = r.number("angle_deg", 0, -inf, inf);
    r.finish();
  }
}

// A body's `driven` mapping (DriveSpec, scene.hpp), read from the body's reader `pose` after its
// pose (a driven body may not set its own velocity or angular velocity).
DriveSpec read_drive(MapReader& pose) {
  const double inf = std::numeric_limits<double>::infinity();
  DriveSpec d;
  if (!pose.has("driven")) return d;
  const YAML::Node node = pose.child("driven");
  d.enabled = true;
  d.key = pose.full("driven");
  MapReader r(node, pose.source(), d.key);
  const char* kSelectors = "give a list of vertex ids or {toward: [x, y, z], depth: m, count: n}";
  if (!r.has("vertices")) r.fail(node, "vertices", std::string("missing (") + kSelectors + ")");
  const YAML::Node v = r.child("vertices");
  if (v.IsSequence()) {
    if (v.size() == 0) r.fail(v, "vertices", "the list is empty");
    for (const auto& item : v) {
      const double id = r.to_number(item, "vertices", 0, 1e9, false, false);
      if (id != std::floor(id))
        r.fail(item, "vertices", "vertex id " + item.Scalar() + " is not a whole number");
      d.vertices.push_back(static_cast<int>(id));
    }
    std::sort(d.vertices.begin(), d.vertices.end());
    const auto twice = std::adjacent_find(d.vertices.begin(), d.vertices.end());
    if (twice != d.vertices.end())
      r.fail(v, "vertices", "vertex " + std::to_string(*twice) + " is listed twice");
  } else if (v.IsMap()) {
    MapReader sel(v, pose.source(), d.key + ".vertices");
    d.toward = sel.vector3("toward", Eigen::Vector3d::Zero());
    if (!(d.toward.norm() > 0))
      sel.fail(v, "toward", "missing or zero direction (the end to select from)");
    d.toward.normalize();
    d.depth = sel.number("depth", -1, 0.0, inf);
    d.count = sel.integer("count", 0, 1, 1000000000);
    sel.finish();  // a misspelt key first: it explains a missing depth or count
    if (d.depth < 0 && d.count == 0) sel.fail(v, "", "give depth, count or both besides toward");
  } else {
    r.fail(v, "vertices",
           "'" + (v.IsScalar() ? v.Scalar() : std::string("?")) +
               "' is not a vertex selector: " + kSelectors);
  }
  d.motion.axis = r.vector3("axis", Eigen::Vector3d::UnitZ());
  if (!(d.motion.axis.norm() > 0))
    r.fail(r.child("axis"), "axis", "value [0, 0, 0] is not a direction (zero axis)");
  d.motion.axis.normalize();
  d.motion.centre = r.vector3("centre", Eigen::Vector3d::Zero());
  d.motion.velocity = r.vector3("velocity", Eigen::Vector3d::Zero());
  if (r.has("angular_velocity")) {
    const YAML::Node w = r.child("angular_velocity");
    if (w.IsSequence()) {
      if (w.size() == 0) r.fail(w, "angular_velocity", "the table is empty");
      for (std::size_t i = 0; i < w.size(); ++i) {
        if (!w[i].IsSequence() || w[i].size() != 2)
          r.fail(w[i], "angular_velocity", "expected rows [t, omega] (s, rad/s)");
        const Eigen::Vector2d row(
            r.to_number(w[i][0], "angular_velocity", -inf, inf, false, false),
            r.to_number(w[i][1], "angular_velocity", -inf, inf, false, false));
        if (i > 0 && !(row[0] > d.motion.angular_velocity_table.back()[0])) {
          r.fail(w[i], "angular_velocity",
                 "time " + w[i][0].Scalar() + " s does not follow the previous row's");
        }
        d.motion.angular_velocity_table.push_back(row);
      }
    } else {
      d.motion.angular_velocity = r.number("angular_velocity", 0, -inf, inf);
    }
  }
  r.finish();
  for (const char* key : {"velocity", "angular_velocity"}) {
    if (pose.has(key)) {
      pose.fail(pose.child(key), key,
                "a driven body starts with its drive's motion; remove this key");
    }
  }
  return d;
}

}  // namespace

const char* predicate_kind_name(PredicateSpec::Kind kind) {
  switch (kind) {
    case PredicateSpec::Kind::kNone:
      return "none";
    case PredicateSpec::Kind::kThroughHoop:
      return "through_hoop";
    case PredicateSpec::Kind::kInsideBox:
      return "inside_box";
    case PredicateSpec::Kind::kStands:
      return "stands";
  }
  return "?";
}

const char* objective_kind_name(ObjectiveSpec::Kind kind) {
  switch (kind) {
    case ObjectiveSpec::Kind::kUndirected:
      return "undirected";
    case ObjectiveSpec::Kind::kTarget:
      return "target";
    case ObjectiveSpec::Kind::kAway:
      return "away";
  }
  return "?";
}

Scene parse_scene(const std::string& yaml_text, const std::string& source_name,
                  const std::string& base_dir, const std::vector<std::string>& overrides) {
  ConfigOrigin source(source_name, base_dir);
  std::vector<std::string> chain{source_name};
  YAML::Node root = with_base(load_yaml(yaml_text, source_name), source, chain);
  for (const auto& o : overrides) apply_override(root, o, source);

  const double inf = std::numeric_limits<double>::infinity();
  Scene s;
  s.source = source_name;
  MapReader top(root, source, "");
  s.name = top.text("name", std::filesystem::path(source_name).stem().string());

  if (!top.has("mesh")) top.fail(root, "mesh", "missing (give shape, surface or file)");
  s.mesh = read_mesh_source(top.child("mesh"), source, "mesh");
  {
    MapReader o(top.child("object"), source, "object");
    read_pose(o, s.position, s.velocity, s.angular_velocity, s.rotation_axis, s.rotation_angle_deg);
    s.driven = read_drive(o);
    o.finish();
  }
  std::set<std::string> names{"object"};  // every body's, for attack.body and objective.body
  if (top.has("bodies")) {
    const YAML::Node bodies = top.child("bodies");
    if (!bodies.IsSequence()) top.fail(bodies, "bodies", "expected a list of bodies");
    for (size_t i = 0; i < bodies.size(); ++i) {
      const std::string key = "bodies[" + std::to_string(i) + "]";
      MapReader b(bodies[i], source, key);
      BodySpec body;
      body.name = b.text("name", key);
      if (!names.insert(body.name).second) b.fail(bodies[i], "name", "'" + body.name + "' names two bodies");
      if (!b.has("mesh")) b.fail(bodies[i], "mesh", "missing (give shape, surface or file)");
      body.mesh = read_mesh_source(b.child("mesh"), source, key + ".mesh");
      read_pose(b, body.position, body.velocity, body.angular_velocity, body.rotation_axis,
                body.rotation_angle_deg);
      body.materials_file = b.path("materials");
      body.driven = read_drive(b);
      b.finish();
      s.bodies.push_back(std::move(body));
    }
  }
  {
    MapReader ob(top.child("obstacles"), source, "obstacles");
    if (ob.has("planes")) {
      const YAML::Node planes = ob.child("planes");
      if (!planes.IsSequence()) ob.fail(planes, "planes", "expected a list of planes");
      for (size_t i = 0; i < planes.size(); ++i) {
        MapReader p(planes[i], source, "obstacles.planes[" + std::to_string(i) + "]");
        Plane plane;
        plane.normal = p.vector3("normal", Eigen::Vector3d::Zero());
        if (!(plane.normal.norm() > 0)) p.fail(planes[i], "normal", "missing or zero normal");
        plane.normal.normalize();
        const bool has_offset = p.has("offset"), has_point = p.has("point");
        if (has_offset == has_point) p.fail(planes[i], "", "give exactly one of offset, point");
        plane.offset = has_offset ? p.number("offset", 0, -inf, inf)
                                  : plane.normal.dot(p.vector3("point", Eigen::Vector3d::Zero()));
        // NaN: contact.friction's, filled in below.
        plane.friction = p.number("friction", std::numeric_limits<double>::quiet_NaN(), 0.0, inf);
        p.finish();
        s.planes.push_back(plane);
      }
    }
    if (ob.has("meshes")) {
      const YAML::Node meshes = ob.child("meshes");
      if (!meshes.IsSequence()) ob.fail(meshes, "meshes", "expected a list of obstacle meshes");
      for (size_t i = 0; i < meshes.size(); ++i) {
        const std::string key = "obstacles.meshes[" + std::to_string(i) + "]";
        MapReader m(meshes[i], source, key);
        ObstacleMesh o;
        if (!m.has("file")) m.fail(meshes[i], "file", "missing (an OBJ, OFF, STL or PLY surface)");
        o.file = m.path("file");
        o.name = key + " (" + o.file + ")";
        o.position = m.vector3("position", o.position);
        if (m.has("rotation")) {
          MapReader r(m.child("rotation"), source, key + ".rotation");
          o.rotation_axis = r.vector3("axis", o.rotation_axis);
          if (!(o.rotation_axis.norm() > 0)) r.fail(m.child("rotation"), "axis", "axis must be non-zero");
          o.rotation_axis.normalize();
          o.rotation_angle_deg = r.number("angle_deg", 0, -inf, inf);
          r.finish();
        }
        o.scale = m.number("scale", o.scale, 0.0, inf, true);
        // NaN: contact.friction's, filled in below.
        o.friction = m.number("friction", std::numeric_limits<double>::quiet_NaN(), 0.0, inf);
        m.finish();
        SurfaceMesh surface;
        try {
          surface = read_triangle_soup(o.file);
        } catch (const InputError& e) {
          std::ostringstream msg;
          msg << source.file_of(meshes[i]) << ":" << meshes[i].Mark().line + 1 << ": key '" << key
              << ".file': " << e.what();
          throw InputError(msg.str());
        }
        // x = position + R (scale x_file)
        const Eigen::Matrix3d R =
            Eigen::AngleAxisd(o.rotation_angle_deg * M_PI / 180.0, o.rotation_axis).toRotationMatrix();
        o.V.resize(surface.V.rows(), 3);
        for (Eigen::Index v = 0; v < surface.V.rows(); ++v) {
          o.V.row(v) = (o.position + R * (o.scale * surface.V.row(v).transpose())).transpose();
        }
        o.F = surface.F;
        s.obstacle_meshes.push_back(std::move(o));
      }
    }
    ob.finish();
  }
  if (top.has("gravity")) {
    const YAML::Node g = top.child("gravity");
    if (g.IsScalar() && (g.Scalar() == "off" || g.Scalar() == "false")) {
      s.gravity.setZero();
    } else {
      s.gravity = top.vector3("gravity", s.gravity);
    }
  }
  {
    MapReader t(top.child("time"), source, "time");
    s.time_step = t.number("step", s.time_step, 0.0, 1.0, true);
    s.duration = t.number("duration", s.duration, 0.0, 1e6, true);
    if (s.duration < s.time_step) t.fail(top.child("time"), "duration", "shorter than one time step");
    s.integrator = t.text("integrator", "bdf2", {"bdf1", "bdf2"}) == "bdf1" ? Integrator::kBdf1
                                                                             : Integrator::kBdf2;
    s.mass = t.text("mass", "consistent", {"consistent", "lumped"}) == "lumped"
                 ? MassModel::kLumped
                 : MassModel::kConsistent;
    s.contact_substeps = t.integer("contact_substeps", 0, 0, 1024);
    if (s.contact_substeps == 1 || (s.contact_substeps & (s.contact_substeps - 1)) != 0) {
      t.fail(t.child("contact_substeps"), "contact_substeps", "not 0 (off) or a power of two from 2 to 1024");
    }
    t.finish();
  }
  {
    MapReader e(top.child("evaluation"), source, "evaluation");
    const bool auto_step = !e.has("time_step") || (e.child("time_step").IsScalar() && e.child("time_step").Scalar() == "auto");
    s.evaluation_search_step = auto_step;
    if (!auto_step) s.evaluation_time_step = e.number("time_step", s.evaluation_time_step, 0.0, 1.0, true);
    s.evaluation_baseline_tolerance = e.number("baseline_tolerance", s.evaluation_baseline_tolerance, 0.0, 1.0, true);
    s.evaluation_max_refinements = e.integer("max_refinements", s.evaluation_max_refinements, 0, 10);
    s.evaluation_duration = e.number("duration", s.evaluation_duration, 0.0, 1e6, true);
    s.evaluation_body = e.text("body", "");
    if (!s.evaluation_body.empty() && s.evaluation_body != "object" &&
        std::none_of(s.bodies.begin(), s.bodies.end(),
                     [&](const BodySpec& b) { return b.name == s.evaluation_body; })) {
      std::string names = "object";
      for (const BodySpec& b : s.bodies) names += ", " + b.name;
      e.fail(e.child("body"), "body",
             "'" + s.evaluation_body + "' names no body (the bodies are: " + names + ")");
    }
    const double step = s.evaluation_time_step > 0 ? s.evaluation_time_step : s.time_step;
    if (s.evaluation_duration > 0 && s.evaluation_duration < step) {
      e.fail(top.child("evaluation"), "duration", "shorter than one time step");
    }
    e.finish();
  }
  {
    MapReader c(top.child("contact"), source, "contact");
    s.d_hat = c.number("d_hat", s.d_hat, 0.0, 1.0, true);
    if (c.has("kappa")) {
      const YAML::Node k = c.child("kappa");
      if (k.IsScalar() && k.Scalar() == "auto") s.kappa = 0;
      else s.kappa = c.number("kappa", 0, 0.0, inf, true);
    }
    s.friction = c.number("friction", s.friction, 0.0, inf);
    s.friction_eps_v = c.number("friction_eps_v", s.friction_eps_v, 0.0, inf, true);
    s.friction_iterations = c.integer("friction_iterations", s.friction_iterations, 1, 100);
    if (c.has("pairs")) {
      // [{bodies: [name, name], friction: mu}]: names are "object" and the bodies' names.
      const YAML::Node pairs = c.child("pairs");
      if (!pairs.IsSequence()) {
        c.fail(pairs, "pairs", "expected a list of {bodies: [a, b], friction}");
      }
      std::vector<std::string> names{"object"};
      for (const BodySpec& b : s.bodies) names.push_back(b.name);
      for (size_t i = 0; i < pairs.size(); ++i) {
        const std::string key = "contact.pairs[" + std::to_string(i) + "]";
        MapReader p(pairs[i], source, key);
        const YAML::Node bodies = p.child("bodies");
        if (!bodies || !bodies.IsSequence() || bodies.size() != 2 || !bodies[0].IsScalar() ||
            !bodies[1].IsScalar()) {
          p.fail(bodies ? bodies : pairs[i], "bodies", "expected two body names [a, b]");
        }
        int index[2];
        for (int k = 0; k < 2; ++k) {
          const std::string name = bodies[k].Scalar();
          const auto it = std::find(names.begin(), names.end(), name);
          if (it == names.end()) {
            std::string list;
            for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
            p.fail(bodies[k], "bodies", "'" + name + "' names no body (bodies: " + list + ")");
          }
          index[k] = static_cast<int>(it - names.begin());
        }
        if (index[0] == index[1]) p.fail(bodies, "bodies", "a body has no friction with itself");
        BodyPairFriction f;
        f.a = std::min(index[0], index[1]);
        f.b = std::max(index[0], index[1]);
        const bool given = p.has("friction");
        f.friction = p.number("friction", 0.0, 0.0, inf);
        p.finish();
        if (!given) p.fail(pairs[i], "friction", "missing (the Coulomb coefficient)");
        for (const BodyPairFriction& g : s.friction_pairs) {
          if (g.a == f.a && g.b == f.b) {
            p.fail(bodies, "bodies", "this pair of bodies is listed twice");
          }
        }
        s.friction_pairs.push_back(f);
      }
    }
    c.finish();
    for (Plane& plane : s.planes) {
      if (std::isnan(plane.friction)) plane.friction = s.friction;
    }
    for (ObstacleMesh& mesh : s.obstacle_meshes) {
      if (std::isnan(mesh.friction)) mesh.friction = s.friction;
    }
  }
  {
    MapReader n(top.child("newton"), source, "newton");
    s.newton_tolerance = n.number("tolerance", s.newton_tolerance, 0.0, 1.0, true);
    s.newton_max_iterations = n.integer("max_iterations", s.newton_max_iterations, 1, 100000);
    s.newton_rigid_predictor = n.text("rigid_predictor", "true", {"true", "false"}) == "true";
    s.newton_chord_start =
        n.text("chord_start", s.newton_chord_start ? "true" : "false", {"true", "false"}) == "true";
    n.finish();
  }
  {
    MapReader r(top.child("reference_material"), source, "reference_material");
    s.reference_Y = r.number("Y", s.reference_Y, 0.0, inf, true);
    s.reference_nu = r.number("nu", s.reference_nu, -1.0, 0.5, true, true);
    s.reference_rho = r.number("rho", s.reference_rho, 0.0, inf, true);
    r.finish();
  }
  {
    // Perceptually rigid ranges (SPEC section 1); scenes may narrow them, never widen them.
    MapReader b(top.child("material_bounds"), source, "material_bounds");
    s.Y_range = b.range("Y", s.Y_range, {2.5e9, 6.5e11});
    s.nu_range = b.range("nu", s.nu_range, {0.2, 0.4});
    s.rho_range = b.range("rho", s.rho_range, {800.0, 11300.0});
    s.alpha_min = b.number("alpha_min", s.alpha_min, 0.0, 1.0, true, true);
    b.finish();
  }
  {
    MapReader a(top.child("attack"), source, "attack");
    if (a.has("fields")) {
      const YAML::Node f = a.child("fields");
      if (!f.IsSequence() || f.size() == 0) a.fail(f, "fields", "expected a non-empty list of Y, nu, rho, alpha");
      s.fields.clear();
      std::set<std::string> seen;
      for (const auto& item : f) {
        const std::string name = item.IsScalar() ? item.Scalar() : "";
        if (!kFields.count(name)) a.fail(item, "fields", "'" + name + "' is not one of Y, nu, rho, alpha");
        if (!seen.insert(name).second) a.fail(item, "fields", "'" + name + "' is listed twice");
        s.fields.push_back(name);
      }
    }
    s.iterations = a.integer("iterations", s.iterations, 0, 1000000);
    s.learning_rate = a.number("learning_rate", s.learning_rate, 0.0, inf, true);
    s.beta = a.number("beta", s.beta, 0.0, inf);
    s.adam_beta1 = a.number("adam_beta1", s.adam_beta1, 0.0, 1.0, false, true);
    s.adam_beta2 = a.number("adam_beta2", s.adam_beta2, 0.0, 1.0, false, true);
    s.seed = static_cast<unsigned>(a.integer("seed", static_cast<int>(s.seed), 0, 2147483647));
    s.perturbation = a.number("perturbation", s.perturbation, 0.0, 10.0);
    s.alpha0 = a.number("alpha0", s.alpha0, s.alpha_min, 1.0, true, true);
    // Strictly inside the bounds: the tanh map reaches a bound only at theta = +-infinity.
    if (a.has("Y0")) s.Y0 = a.number("Y0", 0, s.Y_range.lo, s.Y_range.hi, true, true);
    if (a.has("nu0")) s.nu0 = a.number("nu0", 0, s.nu_range.lo, s.nu_range.hi, true, true);
    s.start_best_uniform = a.text("start", "given", {"given", "best_uniform"}) == "best_uniform";
    if (s.start_best_uniform && (a.has("Y0") || a.has("nu0"))) {
      a.fail(a.child("start"), "start",
             "best_uniform chooses Y0 and nu0 itself (remove attack.Y0 and attack.nu0, or use "
             "start: given)");
    }
    // Open at 0: the smoother's K = Mt - gamma Lt needs gamma > 0 (GradientSmoother refuses 0,
    // after the reference run), and "gamma -> 0" (SPEC section 4) is a limit, not a setting.
    s.smoothing_gamma = a.number("smoothing_gamma", s.smoothing_gamma, 0.0, inf, true);
    s.boundary_by_vertex = a.text("boundary", "faces", {"faces", "vertices"}) == "vertices";
    s.round_threshold = a.number("round_threshold", s.round_threshold, 0.0, 1.0, true, true);
    if (s.round_threshold <= s.alpha_min) {
      a.fail(a.child("round_threshold"), "round_threshold",
             "value " + std::to_string(s.round_threshold) +
                 " must lie above material_bounds.alpha_min");
    }
    if (a.has("occupancy_penalty")) {
      MapReader o(a.child("occupancy_penalty"), source, "attack.occupancy_penalty");
      s.occupancy_weight = o.number("weight", s.occupancy_weight, 0.0, inf);
      s.occupancy_connectivity_weight =
          o.number("connectivity_weight", s.occupancy_connectivity_weight, 0.0, inf);
      s.occupancy_ramp_start = o.number("ramp_start", s.occupancy_ramp_start, 0.0, 1.0);
      s.occupancy_ramp_end = o.number("ramp_end", s.occupancy_ramp_end, 0.0, 1.0);
      s.occupancy_repair_in_loop =
          o.text("repair_in_loop", s.occupancy_repair_in_loop ? "true" : "false",
                 {"true", "false"}) == "true";
      if (s.occupancy_ramp_end < s.occupancy_ramp_start) {
        o.fail(o.child("ramp_end"), "ramp_end",
               "value " + std::to_string(s.occupancy_ramp_end) + " is below ramp_start (" +
                   std::to_string(s.occupancy_ramp_start) + ")");
      }
      o.finish();
    }
    s.project_moments = a.text("project_moments", "true", {"true", "false"}) == "true";
    s.polish_iterations = a.integer("polish_iterations", s.polish_iterations, 0, 1000000);
    s.refinement_factor = a.integer("refinement_factor", s.refinement_factor, 0, 64);
    s.attack_body = a.text("body", s.attack_body, names);
    for (const BodySpec& body : s.bodies) {
      if (body.name == s.attack_body && !body.materials_file.empty()) {
        a.fail(a.child("body"), "body",
               "'" + body.name +
                   "' has a materials file, but the attacked body is designed "
                   "from the uniform reference material (remove bodies[].materials)");
      }
    }
    a.finish();
  }
  if (top.has("objective")) {
    const YAML::Node node = top.child("objective");
    MapReader o(node, source, "objective");
    if (!o.has("kind")) o.fail(node, "kind", "missing (undirected, target or away)");
    const std::string kind = o.text("kind", "", {"undirected", "target", "away"});
    s.objective.kind = kind == "target" ? ObjectiveSpec::Kind::kTarget
                       : kind == "away" ? ObjectiveSpec::Kind::kAway
                                        : ObjectiveSpec::Kind::kUndirected;
    s.objective.body = o.text("body", "", names);
    if (s.objective.kind == ObjectiveSpec::Kind::kTarget) {
      if (!o.has("component")) o.fail(node, "component", "missing (x, y or z) for kind target");
      const std::string c = o.text("component", "", {"x", "y", "z"});
      s.objective.component = c == "x" ? 0 : c == "y" ? 1 : 2;
      if (!o.has("value"))
        o.fail(node, "value", "missing (the target coordinate, m) for kind target");
      s.objective.value = o.number("value", 0, -inf, inf);
    } else {
      for (const char* key : {"component", "value"}) {
        if (o.has(key)) o.fail(o.child(key), key, "only kind target takes it, not kind " + kind);
      }
    }
    o.finish();
  }
  if (top.has("demonstration")) {
    const YAML::Node node = top.child("demonstration");
    MapReader d(node, source, "demonstration");
    DemonstrationSpec& demo = s.demonstration;
    demo.enabled = true;
    const std::string default_body = s.evaluation_body.empty() ? "object" : s.evaluation_body;
    if (d.has("predicate")) {
      const YAML::Node pn = d.child("predicate");
      MapReader p(pn, source, "demonstration.predicate");
      if (!p.has("kind")) p.fail(pn, "kind", "missing (through_hoop, inside_box or stands)");
      const std::string kind = p.text("kind", "", {"through_hoop", "inside_box", "stands"});
      PredicateSpec& pred = demo.predicate;
      auto require = [&](const char* key, const std::string& what) {
        if (!p.has(key)) p.fail(pn, key, "missing (" + what + ") for kind " + kind);
      };
      if (kind == "through_hoop" || kind == "inside_box") {
        pred.body = p.text("body", default_body, names);
      }
      if (kind == "through_hoop") {
        pred.kind = PredicateSpec::Kind::kThroughHoop;
        require("centre", "the hoop's centre [x, y, z], m");
        require("radius", "the opening's radius, m");
        pred.centre = p.vector3("centre", pred.centre);
        pred.axis = p.vector3("axis", pred.axis);
        if (!(pred.axis.norm() > 0))
          p.fail(p.child("axis"), "axis", "value [0, 0, 0] is not a direction");
        pred.axis.normalize();
        pred.radius = p.number("radius", 0, 0.0, inf, true);
      } else if (kind == "inside_box") {
        pred.kind = PredicateSpec::Kind::kInsideBox;
        require("min", "the box's lowest corner [x, y, z], m");
        require("max", "the box's highest corner [x, y, z], m");
        pred.min = p.vector3("min", pred.min);
        pred.max = p.vector3("max", pred.max);
        for (int i = 0; i < 3; ++i) {
          if (!(pred.min[i] < pred.max[i]))
            p.fail(p.child("max"), "max", "must exceed min in every coordinate");
        }
        pred.stays_below_top = p.text("stays_below_top", "false", {"true", "false"}) == "true";
      } else {
        pred.kind = PredicateSpec::Kind::kStands;
        require("bodies", "a list of body names");
        const YAML::Node b = p.child("bodies");
        if (!b.IsSequence() || b.size() == 0)
          p.fail(b, "bodies", "expected a non-empty list of body names");
        for (const auto& item : b) {
          const std::string name = item.IsScalar() ? item.Scalar() : "";
          if (!names.count(name)) {
            std::string list;
            for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
            p.fail(item, "bodies", "'" + name + "' names no body (the bodies are: " + list + ")");
          }
          if (std::count(pred.bodies.begin(), pred.bodies.end(), name))
            p.fail(item, "bodies", "'" + name + "' is listed twice");
          pred.bodies.push_back(name);
        }
        pred.max_tilt_deg = p.number("max_tilt_deg", pred.max_tilt_deg, 0.0, 180.0, true);
        require("min_height", "m: one height, or one per body");
        const YAML::Node h = p.child("min_height");
        if (h.IsSequence()) {
          if (h.size() != pred.bodies.size()) {
            p.fail(h, "min_height",
                   "expected one height or " + std::to_string(pred.bodies.size()) +
                       " (one per body), got " + std::to_string(h.size()));
          }
          for (const auto& item : h)
            pred.min_height.push_back(p.to_number(item, "min_height", -inf, inf, false, false));
        } else {
          pred.min_height.push_back(p.number("min_height", 0, -inf, inf));
        }
      }
      p.finish();
    }
    demo.figure = d.text("figure", "", {"angle"});
    demo.figure_body = d.text("figure_body", default_body, names);
    demo.figure_against_own_simulator =
        d.text("figure_against", "rigid_reference", {"rigid_reference", "own_simulator"}) ==
        "own_simulator";
    demo.figure_horizontal =
        d.text("figure_projection", "none", {"none", "horizontal"}) == "horizontal";
    if (demo.figure_horizontal && s.gravity.norm() == 0) {
      d.fail(d.child("figure_projection"), "figure_projection",
             "horizontal needs gravity (the plane normal to it); this scene has none");
    }
    if (d.has("object_copies")) {
      // Bodies that are copies of each run's object (with_object_copies, scene_world.hpp). An
      // empty list is none (--set=demonstration.object_copies=[] turns them off).
      const YAML::Node c = d.child("object_copies");
      if (!c.IsSequence()) d.fail(c, "object_copies", "expected a list of body names");
      for (const auto& item : c) {
        const std::string name = item.IsScalar() ? item.Scalar() : "";
        if (name == "object") {
          d.fail(item, "object_copies",
                 "'object' is the object itself (list the bodies that are to be its copies)");
        }
        const auto body = std::find_if(s.bodies.begin(), s.bodies.end(),
                                       [&](const BodySpec& b) { return b.name == name; });
        if (body == s.bodies.end()) {
          std::string list;
          for (const BodySpec& b : s.bodies) list += (list.empty() ? "" : ", ") + b.name;
          d.fail(item, "object_copies",
                 "'" + name + "' names no body (the bodies are: " +
                     (list.empty() ? "none" : list) + ")");
        }
        if (std::count(demo.object_copies.begin(), demo.object_copies.end(), name))
          d.fail(item, "object_copies", "'" + name + "' is listed twice");
        if (!body->materials_file.empty()) {
          d.fail(item, "object_copies",
                 "'" + name + "' has a materials file, but a copy takes each run's object's "
                 "materials (remove its materials)");
        }
        if (body->driven.enabled) {
          d.fail(item, "object_copies",
                 "'" + name + "' is driven; a copy of the object cannot be (remove its driven)");
        }
        demo.object_copies.push_back(name);
      }
    }
    d.finish();
    if (demo.predicate.kind == PredicateSpec::Kind::kNone && demo.figure.empty()) {
      d.fail(node, "", "give a predicate, a figure or both");
    }
  }
  top.finish();
  return s;
}

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  const std::string base = std::filesystem::path(path).parent_path().string();
  return parse_scene(read_whole_file(path), path, base, overrides);
}

std::string merged_config_text(const std::string& path) {
  ConfigOrigin origin(path, std::filesystem::path(path).parent_path().string());
  std::vector<std::string> chain{path};
  return YAML::Dump(with_base(load_yaml(read_whole_file(path), path), origin, chain));
}

std::string body_name(const Scene& scene, int index) {
  return index == 0 ? scene.object_name : scene.bodies.at(index - 1).name;
}

void check_keys(const YAML::Node& node, const std::string& source, const std::string& prefix,
                bool lines) {
  auto where = [&](const YAML::Node& at) {
    std::ostringstream msg;
    msg << source;
    if (lines && at.Mark().line >= 0) msg << ":" << at.Mark().line + 1;
    return msg.str();
  };
  if (node.IsMap()) {
    std::set<std::string> names;
    for (const auto& kv : node) {
      if (!kv.first.IsScalar()) {
        throw InputError(where(kv.first) + ": " + (prefix.empty() ? "" : "under '" + prefix + "': ") +
                         "a key must be a name, not a list or mapping");
      }
      const std::string name = kv.first.Scalar();
      const std::string full = prefix.empty() ? name : prefix + "." + name;
      if (!names.insert(name).second) {
        throw InputError(where(kv.first) + ": key '" + full +
                         "' is given twice in this mapping (only one value can hold)");
      }
      check_keys(kv.second, source, full, lines);
    }
  } else if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i) {
      check_keys(node[i], source, prefix + "[" + std::to_string(i) + "]", lines);
    }
  }
}

}  // namespace rbaa
