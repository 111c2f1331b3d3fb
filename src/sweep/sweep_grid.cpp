#include "rbaa/sweep/sweep_grid.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "rbaa/error.hpp"
#include "../scene/yaml_keys.hpp"

namespace rbaa {
namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kTopKeys = {"config",  "verb", "set",    "flags",
                                           "product", "rows", "report", "slurm"};
// Flags the sweep gives every row itself.
const std::set<std::string> kOwnFlags = {"config", "set", "out", "grid", "help", "flagfile"};

class GridReader {
 public:
  explicit GridReader(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void fail(const YAML::Node& at, const std::string& what) const {
    std::ostringstream msg;
    msg << source_;
    if (at && at.Mark().line >= 0) msg << ":" << at.Mark().line + 1;
    msg << ": " << what;
    throw InputError(msg.str());
  }

  int line(const YAML::Node& at) const {
    return at && at.Mark().line >= 0 ? at.Mark().line + 1 : 0;
  }

  std::string scalar(const YAML::Node& n, const std::string& what) const {
    if (!n.IsScalar()) fail(n, what + ": expected a single value");
    return n.Scalar();
  }

  // A --set value: a scalar or a flow list of scalars, as YAML text the scene parses back.
  std::string value_text(const YAML::Node& n, const std::string& key) const {
    std::string text;
    if (n.IsScalar()) {
      text = n.Scalar();
    } else if (n.IsSequence()) {
      for (const auto& item : n) {
        if (!item.IsScalar())
          fail(item, "key '" + key + "': expected a number, a word or a flat list");
      }
      YAML::Emitter out;
      out << YAML::Flow << n;
      text = out.c_str();
    } else {
      fail(n, "key '" + key + "': expected a number, a word or a flat list");
    }
    if (text.find(';') != std::string::npos) {
      fail(n, "key '" + key + "': value '" + text + "' contains ';', which separates --set items");
    }
    if (text.empty()) fail(n, "key '" + key + "': empty value");
    return text;
  }

  std::string key_text(const YAML::Node& k, const std::string& where) const {
    const std::string key = scalar(k, where);
    const bool ok = !key.empty() && key.front() != '.' && key.back() != '.' &&
                    key.find("..") == std::string::npos &&
                    std::all_of(key.begin(), key.end(), [](char c) {
                      return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.';
                    });
    if (!ok) fail(k, where + ": '" + key + "' is not a config key path (e.g. attack.seed)");
    return key;
  }

  // A mapping of key.path -> value (set:, one entry of rows:).
  std::vector<SweepOverride> assignments(const YAML::Node& n, const std::string& where) const {
    if (!n.IsMap()) fail(n, where + ": expected a mapping of key.path: value");
    std::vector<SweepOverride> out;
    for (const auto& kv : n) {
      const std::string key = key_text(kv.first, where);
      out.push_back({key, value_text(kv.second, key)});
    }
    return out;
  }

  const std::string& source() const { return source_; }

 private:
  std::string source_;
};

}  // namespace

const std::vector<std::string>& sweep_verbs() {
  static const std::vector<std::string> verbs = {"attack", "evaluate", "simulate", "study"};
  return verbs;
}

std::vector<std::string> default_report_columns(const std::string& verb) {
  if (verb == "attack") {
    return {"iterations",
            "gap.initial",
            "gap.continuous",
            "gap.final",
            "moments.max_normalized_residual",
            "occupancy.void_fraction",
            "timing.forward_s",
            "timing.adjoint_s",
            "timing.total_s"};
  }
  if (verb == "simulate") {
    return {"steps", "newton.total_iterations", "newton.max_iterations_in_a_step",
            "min_contact_distance", "timing.simulate_s"};
  }
  if (verb == "evaluate") {
    return {"attack_advantage", "deformable_vs_deformable.com_gap_m",
            "adversarial_vs_rigid.com_gap_m", "baseline_disagreement", "time_step_s"};
  }
  return {};
}

std::string row_folder_name(int index) {
  char name[32];
  std::snprintf(name, sizeof(name), "row-%03d", index);
  return name;
}

std::vector<std::string> row_arguments(const SweepGrid& grid, const SweepRow& row) {
  std::vector<std::string> args = {grid.verb, "--config=" + grid.config};
  std::string set;
  for (const auto* list : {&grid.fixed, &row.overrides}) {
    for (const SweepOverride& o : *list) set += (set.empty() ? "" : ";") + o.key + "=" + o.value;
  }
  if (!set.empty()) args.push_back("--set=" + set);
  for (const SweepFlag& f : grid.flags) args.push_back("--" + f.name + "=" + f.value);
  return args;
}

SweepGrid parse_sweep_grid(const std::string& yaml_text, const std::string& source,
                           const std::string& base_dir) {
  GridReader r(source);
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw InputError(source + ":" + std::to_string(e.mark.line + 1) + ": invalid YAML: " + e.msg);
  }
  if (!root || !root.IsMap())
    r.fail(root, "expected a mapping with config, verb and product or rows");
  // yaml-cpp keeps both entries of a repeated key, a lookup finds the first and a loop sees both:
  // a second product: block was dropped and flags: {vtu_every: 0, vtu_every: 1} gave both.
  check_keys(root, source, "");
  for (const auto& kv : root) {
    const std::string key = kv.first.Scalar();
    if (std::find(kTopKeys.begin(), kTopKeys.end(), key) == kTopKeys.end()) {
      std::string list;
      for (const auto& k : kTopKeys) list += (list.empty() ? "" : ", ") + k;
      r.fail(kv.first, "unknown key '" + key + "' (a grid has: " + list + ")");
    }
  }

  SweepGrid g;
  g.source = source;

  if (!root["verb"])
    r.fail(root, "missing key 'verb' (" + std::string("attack, evaluate, simulate or study)"));
  g.verb = r.scalar(root["verb"], "verb");
  const auto& verbs = sweep_verbs();
  if (std::find(verbs.begin(), verbs.end(), g.verb) == verbs.end()) {
    r.fail(root["verb"], "verb '" + g.verb + "' is not one of: attack, evaluate, simulate, study");
  }

  if (!root["config"]) r.fail(root, "missing key 'config' (the base scene config)");
  const std::string config = r.scalar(root["config"], "config");
  fs::path config_path(config);
  if (config_path.is_relative() && !base_dir.empty())
    config_path = fs::path(base_dir) / config_path;
  config_path = fs::absolute(config_path).lexically_normal();
  if (!fs::is_regular_file(config_path)) {
    r.fail(root["config"], "config '" + config + "': no such file (" + config_path.string() + ")");
  }
  g.config = config_path.string();

  if (root["set"]) g.fixed = r.assignments(root["set"], "set");

  if (const YAML::Node flags = root["flags"]) {
    if (!flags.IsMap()) r.fail(flags, "flags: expected a mapping of flag: value");
    for (const auto& kv : flags) {
      const std::string name = r.scalar(kv.first, "flags");
      if (kOwnFlags.count(name)) {
        r.fail(kv.first, "flags: --" + name + " is set by the sweep itself" +
                             (name == "set" ? " (use the grid's set:)" : ""));
      }
      g.flags.push_back({name, r.scalar(kv.second, "flags: " + name), r.line(kv.first)});
    }
  }

  // Explicit rows, then the product's combinations; with both, each row takes every combination.
  std::vector<std::vector<SweepOverride>> explicit_rows;
  if (const YAML::Node rows = root["rows"]) {
    if (!rows.IsSequence()) r.fail(rows, "rows: expected a list of mappings key.path: value");
    if (rows.size() == 0) r.fail(rows, "rows: empty list");
    for (size_t i = 0; i < rows.size(); ++i) {
      explicit_rows.push_back(r.assignments(rows[i], "rows[" + std::to_string(i) + "]"));
    }
  }
  std::vector<std::vector<SweepOverride>> combinations = {{}};
  if (const YAML::Node product = root["product"]) {
    if (!product.IsMap()) r.fail(product, "product: expected a mapping of key.path: [values]");
    if (product.size() == 0) r.fail(product, "product: empty (give key.path: [values])");
    for (const auto& kv : product) {
      const std::string key = r.key_text(kv.first, "product");
      const YAML::Node values = kv.second;
      if (!values.IsSequence())
        r.fail(values, "product: key '" + key + "': expected a list of values");
      if (values.size() == 0) r.fail(values, "product: key '" + key + "': empty list");
      std::vector<std::vector<SweepOverride>> next;
      for (const auto& c : combinations) {
        for (const auto& v : values) {
          auto row = c;
          row.push_back({key, r.value_text(v, key)});
          next.push_back(std::move(row));
        }
      }
      combinations = std::move(next);
    }
  }
  if (explicit_rows.empty()) {
    if (!root["product"]) r.fail(root, "no rows: give product (lists to combine) or rows (a list)");
    explicit_rows.push_back({});
  }
  for (size_t e = 0; e < explicit_rows.size(); ++e) {
    for (const auto& c : combinations) {
      SweepRow row;
      row.index = static_cast<int>(g.rows.size());
      row.overrides = explicit_rows[e];
      for (const auto& o : c) {
        for (const auto& existing : row.overrides) {
          if (existing.key == o.key) {
            r.fail(root["rows"][e],
                   "rows[" + std::to_string(e) + "]: key '" + o.key + "' is also in product");
          }
        }
        row.overrides.push_back(o);
      }
      g.rows.push_back(std::move(row));
    }
  }
  for (const SweepRow& row : g.rows) {
    for (const SweepOverride& o : row.overrides) {
      if (std::find(g.swept_keys.begin(), g.swept_keys.end(), o.key) == g.swept_keys.end()) {
        g.swept_keys.push_back(o.key);
      }
    }
  }

  g.report_columns = default_report_columns(g.verb);
  if (const YAML::Node report = root["report"]) {
    if (!report.IsSequence())
      r.fail(report, "report: expected a list of report.json paths (e.g. gap.final)");
    for (const auto& item : report) {
      const std::string path = r.key_text(item, "report");
      if (std::find(g.report_columns.begin(), g.report_columns.end(), path) ==
          g.report_columns.end()) {
        g.report_columns.push_back(path);
      }
    }
  }

  if (const YAML::Node slurm = root["slurm"]) {
    if (!slurm.IsMap()) r.fail(slurm, "slurm: expected a mapping of sbatch option: value");
    for (const auto& kv : slurm) {
      const std::string name = r.scalar(kv.first, "slurm");
      if (name == "array" || name == "output" || name == "dependency") {
        r.fail(kv.first, "slurm: --" + name + " is written by the sweep itself");
      }
      g.slurm_options.emplace_back(name, r.scalar(kv.second, "slurm: " + name));
    }
  }
  return g;
}

SweepGrid load_sweep_grid(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read the grid file");
  std::stringstream text;
  text << in.rdbuf();
  return parse_sweep_grid(text.str(), path, fs::path(path).parent_path().string());
}

}  // namespace rbaa
