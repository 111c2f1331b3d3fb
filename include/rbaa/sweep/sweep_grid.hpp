#pragma once
// A parameter sweep's grid: which verb to run on which base config, and the rows, each a list of
// `--set key=value` overrides (README, "Parameter sweeps"). Read from YAML:
//
//   config: ../configs/star.yaml      # resolved against the grid file's folder
//   verb: attack                      # attack | evaluate | simulate | study
//   set: {attack.iterations: 20}      # overrides every row shares
//   flags: {vtu_every: 0}             # extra flags every row gets, as --name=value
//   product:                          # every combination; the first key varies slowest
//     attack.learning_rate: [0.02, 0.05]
//     attack.seed: [1, 2, 3]
//   rows:                             # explicit rows; with a product, each row x every combination
//     - {attack.beta: 1.0e4}
//   report: [kappa]                   # extra report.json figures for results.csv (dotted paths)
//   slurm: {time: "02:00:00"}         # sbatch options for --emit=slurm, as --name=value
//
// Every key is checked: unknown keys, an unknown verb, an empty list or product, a key given twice
// in any mapping (a row, flags:, slurm: included) are errors "FILE:LINE: ...". The override values
// themselves are checked by the row when it runs (a bad one fails that row alone, with the scene's
// error).

#include <string>
#include <utility>
#include <vector>

namespace rbaa {

/// One `--set` assignment; `value` is YAML text (a scalar, or a flow list such as [0, -10, -10]).
struct SweepOverride {
  std::string key;
  std::string value;
};

struct SweepRow {
  int index = 0;                         ///< 0-based; the row's folder is row-NNN
  std::vector<SweepOverride> overrides;  ///< this row's swept values
};

/// An extra flag `--name=value` given to every row.
struct SweepFlag {
  std::string name;
  std::string value;
  int line = 0;  ///< line in the grid file, for errors about the flag
};

struct SweepGrid {
  std::string source;                ///< the grid file (for messages)
  std::string verb;                  ///< one of sweep_verbs()
  std::string config;                ///< the base scene config, absolute
  std::vector<SweepOverride> fixed;  ///< `set:`: overrides every row shares
  std::vector<SweepFlag> flags;
  std::vector<std::string> swept_keys;  ///< keys that vary, in first-seen order (results columns)
  std::vector<SweepRow> rows;
  std::vector<std::string> report_columns;  ///< report.json figures (dotted paths) for results
  std::vector<std::pair<std::string, std::string>> slurm_options;  ///< sbatch --name=value
};

/// Reads and checks a grid file; throws InputError "FILE:LINE: what" on bad input.
SweepGrid load_sweep_grid(const std::string& path);

/// Parses grid YAML text; `source` names it in errors, `base_dir` resolves `config`.
SweepGrid parse_sweep_grid(const std::string& yaml_text, const std::string& source,
                           const std::string& base_dir);

/// The verbs a sweep drives: attack, evaluate, simulate, study.
const std::vector<std::string>& sweep_verbs();

/// The headline figures results.csv takes from a verb's report.json (dotted paths): gaps, moment
/// residual, iterations and times for attack; Newton iterations and times for simulate; the gaps
/// and the attack's advantage for evaluate; none for study (it writes study.csv).
std::vector<std::string> default_report_columns(const std::string& verb);

/// The row's command line after the program name, without --out: the verb, --config, one --set
/// with the shared and the row's overrides (the row's last), then the extra flags. Two runs with
/// the same arguments are the same row (resume compares them).
std::vector<std::string> row_arguments(const SweepGrid& grid, const SweepRow& row);

/// "row-007": the folder of row 7 under the sweep's output folder.
std::string row_folder_name(int index);

}  // namespace rbaa
