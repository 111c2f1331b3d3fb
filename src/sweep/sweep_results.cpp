#include "rbaa/sweep/sweep_results.hpp"

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "rbaa/error.hpp"
#include "rbaa/io/atomic_file.hpp"
#include "rbaa/sweep/config_fingerprint.hpp"

namespace rbaa {
namespace {

namespace fs = std::filesystem;

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) {
    if (c == '"') q += '"';
    q += (c == '\n' || c == '\r') ? ' ' : c;
  }
  return q + "\"";
}

std::string joined(const std::vector<std::string>& args) {
  std::string s;
  for (const auto& a : args) s += (s.empty() ? "" : " ") + a;
  return s;
}

// report.json's value at a dotted path as CSV text: numbers in their JSON (round-tripping) form,
// strings as they are, lists and objects as JSON; empty when absent or null.
std::string figure(const nlohmann::json& report, const std::string& dotted) {
  const nlohmann::json* node = &report;
  std::stringstream ss(dotted);
  for (std::string part; std::getline(ss, part, '.');) {
    if (!node->is_object() || !node->contains(part)) return "";
    node = &(*node)[part];
  }
  if (node->is_null()) return "";
  if (node->is_string()) return node->get<std::string>();
  return node->dump();
}

}  // namespace

std::vector<RowOutcome> read_sweep_outcomes(const SweepGrid& grid, const std::string& out_dir) {
  // The arguments name the config and the files a row names by their paths; their contents are
  // in the fingerprint.
  const std::string grid_fingerprint = config_fingerprint(grid);
  std::vector<RowOutcome> outcomes;
  for (const SweepRow& row : grid.rows) {
    const std::string fingerprint = row_config_fingerprint(grid_fingerprint, grid, row);
    const std::string dir = (fs::path(out_dir) / row_folder_name(row.index)).string();
    RowOutcome o = read_row_outcome(dir, row.index);
    const auto args = row_arguments(grid, row);
    const std::string that_row = grid.source + "'s row " + std::to_string(row.index);
    if (o.status != RowStatus::kPending && o.arguments != args) {
      throw InputError(dir + " holds a run of other settings (" + joined(o.arguments) + ") than " +
                       that_row + " (" + joined(args) +
                       "): use another --out, or remove that folder");
    }
    // Only a finished row's results stand for the config it ran on. A failed or interrupted row
    // runs again, on the config as it is now: its failure may be what the edit mended (a
    // mesh.file created since). An attack row among them resumes its checkpoint, and rbaa attack
    // refuses a checkpoint of another scene itself (attack_loop.cpp, load_checkpoint), so that row
    // fails naming both fingerprints rather than going on from another scene's design.
    if (o.status == RowStatus::kOk && !o.config_fingerprint.empty() &&
        o.config_fingerprint != fingerprint) {
      const std::string files = fingerprint == grid_fingerprint
                                    ? " or a file it builds on"
                                    : ", a file it builds on or one the row's values name";
      throw InputError(dir + " holds a run of other settings than " + that_row + ": " +
                       grid.config + files + " changed since (config fingerprint " +
                       o.config_fingerprint + ", now " + fingerprint +
                       "): use another --out, or remove that folder");
    }
    o.arguments = args;
    o.config_fingerprint = fingerprint;
    outcomes.push_back(std::move(o));
  }
  return outcomes;
}

std::string sweep_results_csv(const SweepGrid& grid, const std::string& out_dir,
                              const std::vector<RowOutcome>& outcomes) {
  std::ostringstream out;
  std::vector<std::string> header = {"row", "status"};
  header.insert(header.end(), grid.swept_keys.begin(), grid.swept_keys.end());
  header.insert(header.end(), grid.report_columns.begin(), grid.report_columns.end());
  header.insert(header.end(), {"seconds", "error", "folder"});
  for (size_t i = 0; i < header.size(); ++i) out << (i ? "," : "") << csv_field(header[i]);
  out << "\n";
  for (const SweepRow& row : grid.rows) {
    const RowOutcome& o = outcomes.at(static_cast<size_t>(row.index));
    const std::string folder = row_folder_name(row.index);
    std::vector<std::string> cells = {std::to_string(row.index), status_name(o.status)};
    // The value the row ran with: its own, else the grid's set: (the row's comes last in --set,
    // row_arguments); empty only where the config's value stood.
    for (const std::string& key : grid.swept_keys) {
      std::string value;
      for (const auto* list : {&grid.fixed, &row.overrides}) {
        for (const SweepOverride& ov : *list) {
          if (ov.key == key) value = ov.value;
        }
      }
      cells.push_back(value);
    }
    nlohmann::json report;
    if (o.status == RowStatus::kOk) {
      std::ifstream in(fs::path(out_dir) / folder / "report.json");
      if (in) report = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
      if (report.is_discarded()) report = nullptr;
    }
    for (const std::string& path : grid.report_columns) cells.push_back(figure(report, path));
    std::ostringstream seconds;
    if (o.status == RowStatus::kOk || o.status == RowStatus::kFailed) seconds << o.seconds;
    cells.insert(cells.end(), {seconds.str(), o.error, folder});
    for (size_t i = 0; i < cells.size(); ++i) out << (i ? "," : "") << csv_field(cells[i]);
    out << "\n";
  }
  return out.str();
}

void write_sweep_results(const SweepGrid& grid, const std::string& out_dir,
                         const std::vector<RowOutcome>& outcomes) {
  const std::string text = sweep_results_csv(grid, out_dir, outcomes);
  write_file_atomically((fs::path(out_dir) / "results.csv").string(),
                        [&](std::ostream& os) { os << text; });
}

}  // namespace rbaa
