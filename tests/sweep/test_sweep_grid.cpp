// The sweep's grid file, thread split, results table and Slurm scripts, without running rows
// (tests/cli/test_cli_sweep.cpp runs them).

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "rbaa/error.hpp"
#include "rbaa/scene/scene.hpp"
#include "rbaa/scene/scene_fingerprint.hpp"
#include "rbaa/sweep/config_fingerprint.hpp"
#include "rbaa/sweep/slurm_script.hpp"
#include "rbaa/sweep/sweep_grid.hpp"
#include "rbaa/sweep/sweep_results.hpp"
#include "rbaa/sweep/sweep_runner.hpp"
#include "rbaa/sweep/thread_split.hpp"

namespace {

namespace fs = std::filesystem;

const std::string kConfigs = std::string(RBAA_SOURCE_DIR) + "/configs";

rbaa::SweepGrid parse(const std::string& text) {
  return rbaa::parse_sweep_grid(text, "grid.yaml", kConfigs);
}

// The InputError's message, or "" if parsing succeeded.
std::string parse_error(const std::string& text) {
  try {
    parse(text);
  } catch (const rbaa::InputError& e) {
    return e.what();
  }
  return "";
}

std::string row_text(const rbaa::SweepRow& row) {
  std::string s;
  for (const auto& o : row.overrides) s += (s.empty() ? "" : " ") + o.key + "=" + o.value;
  return s;
}

TEST(SweepGrid, ProductCombinesEveryValueFirstKeySlowest) {
  const auto g = parse(
      "config: star.yaml\n"
      "verb: attack\n"
      "product:\n"
      "  attack.learning_rate: [0.02, 0.05]\n"
      "  attack.seed: [1, 2, 3]\n");
  EXPECT_EQ(g.config, fs::absolute(kConfigs + "/star.yaml").lexically_normal().string());
  ASSERT_EQ(g.rows.size(), 6u);
  EXPECT_EQ(row_text(g.rows[0]), "attack.learning_rate=0.02 attack.seed=1");
  EXPECT_EQ(row_text(g.rows[2]), "attack.learning_rate=0.02 attack.seed=3");
  EXPECT_EQ(row_text(g.rows[5]), "attack.learning_rate=0.05 attack.seed=3");
  for (int i = 0; i < 6; ++i) EXPECT_EQ(g.rows[i].index, i);
  EXPECT_EQ(g.swept_keys, (std::vector<std::string>{"attack.learning_rate", "attack.seed"}));
  EXPECT_EQ(rbaa::row_folder_name(5), "row-005");
}

TEST(SweepGrid, ExplicitRowsAloneOrEachTimesTheProduct) {
  const auto only = parse(
      "config: star.yaml\nverb: simulate\n"
      "rows:\n"
      "  - {time.duration: 0.1}\n"
      "  - {time.duration: 0.2, object.velocity: [0, -5, -5]}\n");
  ASSERT_EQ(only.rows.size(), 2u);
  EXPECT_EQ(row_text(only.rows[0]), "time.duration=0.1");
  EXPECT_EQ(row_text(only.rows[1]), "time.duration=0.2 object.velocity=[0, -5, -5]");
  EXPECT_EQ(only.swept_keys, (std::vector<std::string>{"time.duration", "object.velocity"}));

  const auto both = parse(
      "config: star.yaml\nverb: attack\n"
      "rows: [{attack.beta: 1.0e3}, {attack.beta: 1.0e4}]\n"
      "product: {attack.seed: [1, 2]}\n");
  ASSERT_EQ(both.rows.size(), 4u);
  EXPECT_EQ(row_text(both.rows[1]), "attack.beta=1.0e3 attack.seed=2");
  EXPECT_EQ(row_text(both.rows[2]), "attack.beta=1.0e4 attack.seed=1");
}

TEST(SweepGrid, RowArgumentsCarrySharedOverridesThenTheRowsThenFlags) {
  const auto g = parse(
      "config: star.yaml\nverb: simulate\n"
      "set: {mesh.target_tets: 300}\n"
      "flags: {vtu_every: 0, progress: false}\n"
      "product: {time.duration: [0.1]}\n");
  EXPECT_EQ(rbaa::row_arguments(g, g.rows[0]),
            (std::vector<std::string>{"simulate", "--config=" + g.config,
                                      "--set=mesh.target_tets=300;time.duration=0.1",
                                      "--vtu_every=0", "--progress=false"}));
  // The verb's headline figures, plus the grid's own.
  const auto r =
      parse("config: star.yaml\nverb: attack\nproduct: {attack.seed: [1]}\nreport: [kappa]\n");
  EXPECT_EQ(r.report_columns.front(), "iterations");
  EXPECT_EQ(r.report_columns.back(), "kappa");
  EXPECT_NE(std::find(r.report_columns.begin(), r.report_columns.end(), "gap.final"),
            r.report_columns.end());
  EXPECT_NE(std::find(r.report_columns.begin(), r.report_columns.end(),
                      "moments.max_normalized_residual"),
            r.report_columns.end());
}

// The README's example grid: the star's attack over 3 learning rates x 3 seeds.
TEST(SweepGrid, TheReadmesExampleGridIsValid) {
  const auto g = rbaa::load_sweep_grid(kConfigs + "/sweeps/star_learning_rate_seed.yaml");
  EXPECT_EQ(g.verb, "attack");
  EXPECT_EQ(g.config, fs::absolute(kConfigs + "/star.yaml").lexically_normal().string());
  ASSERT_EQ(g.rows.size(), 9u);
  EXPECT_EQ(row_text(g.rows[4]), "attack.learning_rate=0.05 attack.seed=2");
  EXPECT_EQ(g.report_columns.back(), "objective.final");
  EXPECT_EQ(g.slurm_options.size(), 2u);
}

// Bad grids: one message naming the file, the line and what is wrong.
TEST(SweepGrid, BadGridsNameFileLineAndValue) {
  const std::string head = "config: star.yaml\nverb: simulate\n";
  EXPECT_EQ(
      parse_error(head + "colour: red\nproduct: {a.b: [1]}\n"),
      "grid.yaml:3: unknown key 'colour' (a grid has: config, verb, set, flags, product, rows, "
      "report, slurm)");
  EXPECT_EQ(parse_error(head + "product: {}\n"),
            "grid.yaml:3: product: empty (give key.path: [values])");
  EXPECT_EQ(parse_error(head + "product:\n  time.step: [0.01]\n  attack.seed: []\n"),
            "grid.yaml:5: product: key 'attack.seed': empty list");
  EXPECT_EQ(parse_error("config: star.yaml\nverb: atack\nproduct: {a.b: [1]}\n"),
            "grid.yaml:2: verb 'atack' is not one of: attack, evaluate, simulate, study");
  EXPECT_EQ(parse_error(head),
            "grid.yaml:1: no rows: give product (lists to combine) or rows (a list)");
  EXPECT_EQ(parse_error("config: nowhere.yaml\nverb: simulate\nproduct: {a.b: [1]}\n")
                .rfind("grid.yaml:1: config 'nowhere.yaml': no such file", 0),
            0u);
  EXPECT_EQ(parse_error(head + "product: {time.step: 0.01}\n"),
            "grid.yaml:3: product: key 'time.step': expected a list of values");
  EXPECT_EQ(parse_error(head + "rows: [{a.b: 1}]\nproduct: {a.b: [2]}\n"),
            "grid.yaml:3: rows[0]: key 'a.b' is also in product");
  EXPECT_EQ(parse_error(head + "flags: {out: x}\nproduct: {a.b: [1]}\n"),
            "grid.yaml:3: flags: --out is set by the sweep itself");
  EXPECT_EQ(parse_error(head + "product: {'a b': [1]}\n"),
            "grid.yaml:3: product: 'a b' is not a config key path (e.g. attack.seed)");
  EXPECT_EQ(parse_error(head + "product: {a.b: ['x;y']}\n"),
            "grid.yaml:3: key 'a.b': value 'x;y' contains ';', which separates --set items");
  EXPECT_EQ(parse_error(head + "product: {a.b: [1]\n").substr(0, 24), "grid.yaml:4: invalid YAM");
  // A key given twice in any mapping: yaml-cpp keeps both, a lookup finds the first and a loop
  // sees both, so a second block would be dropped (here: 1 row instead of 2, and set's a.b = 1
  // instead of 2) and a flag given twice went to every row twice, the last winning.
  const std::string twice = " is given twice in this mapping (only one value can hold)";
  EXPECT_EQ(parse_error(head + "product: {a.b: [1]}\nproduct: {a.b: [2, 3]}\n"),
            "grid.yaml:4: key 'product'" + twice);
  EXPECT_EQ(parse_error(head + "set: {a.b: 1}\nproduct: {c.d: [1]}\nset: {a.b: 2}\n"),
            "grid.yaml:5: key 'set'" + twice);
  EXPECT_EQ(parse_error(head + "flags:\n  vtu_every: 0\n  vtu_every: 1\nproduct: {a.b: [1]}\n"),
            "grid.yaml:5: key 'flags.vtu_every'" + twice);
  EXPECT_EQ(parse_error(head + "slurm: {time: '1:00', time: '2:00'}\nproduct: {a.b: [1]}\n"),
            "grid.yaml:3: key 'slurm.time'" + twice);
  EXPECT_EQ(parse_error(head + "product: {a.b: [1], a.b: [2]}\n"),
            "grid.yaml:3: key 'product.a.b'" + twice);
  EXPECT_EQ(parse_error(head + "rows:\n  - {a.b: 1}\n  - {a.b: 1, a.b: 2}\n"),
            "grid.yaml:5: key 'rows[1].a.b'" + twice);
  EXPECT_EQ(parse_error(head + "? [a, b]\n: 1\nproduct: {a.b: [1]}\n"),
            "grid.yaml:3: a key must be a name, not a list or mapping");
  EXPECT_EQ(parse_error(head + "flags: {? [a, b] : 1}\nproduct: {a.b: [1]}\n"),
            "grid.yaml:3: under 'flags': a key must be a name, not a list or mapping");
}

// jobs x threads <= cores unless the user asks for more threads (or more jobs than cores).
TEST(SweepThreads, JobsTimesThreadsFitTheCores) {
  auto s = rbaa::split_threads(2, 0, 8);
  EXPECT_EQ(s.threads, 4);
  EXPECT_FALSE(s.oversubscribed);
  s = rbaa::split_threads(3, 0, 8);
  EXPECT_EQ(s.threads, 2);
  s = rbaa::split_threads(1, 0, 2);
  EXPECT_EQ(s.threads, 2);
  s = rbaa::split_threads(4, 0, 2);
  EXPECT_EQ(s.threads, 1);
  EXPECT_TRUE(s.oversubscribed);
  s = rbaa::split_threads(2, 3, 2);  // asked for
  EXPECT_EQ(s.threads, 3);
  EXPECT_TRUE(s.oversubscribed);
  EXPECT_EQ(rbaa::describe(rbaa::split_threads(2, 0, 2)), "2 jobs x 1 thread on 2 cores");
  EXPECT_THROW(rbaa::split_threads(0, 0, 2), rbaa::InputError);
  EXPECT_GE(rbaa::available_cores(), 1);
}

class SweepFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) / ("rbaa_sweep_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

// results.csv: one line per row, finished or not; figures from report.json; errors quoted.
TEST_F(SweepFiles, ResultsTableHasEveryRowWithStatusFiguresAndErrors) {
  const auto g =
      parse("config: star.yaml\nverb: simulate\nproduct: {time.duration: [0.1, 0.2, 0.3]}\n");
  const std::string out = dir_.string();
  const std::string config = rbaa::config_fingerprint(g);
  rbaa::RowOutcome ok{0,     rbaa::RowStatus::kOk, rbaa::row_arguments(g, g.rows[0]), "", 0, 1.5,
                      config};
  rbaa::write_row_outcome(out + "/row-000", ok);
  std::ofstream(out + "/row-000/report.json")
      << R"({"steps": 3, "newton": {"total_iterations": 12, "max_iterations_in_a_step": 5},
            "min_contact_distance": null, "timing": {"simulate_s": 0.25}})";
  rbaa::RowOutcome bad{1,
                       rbaa::RowStatus::kFailed,
                       rbaa::row_arguments(g, g.rows[1]),
                       "rbaa simulate: error: a, \"b\" [exit code 2]",
                       2,
                       0.5,
                       config};
  rbaa::write_row_outcome(out + "/row-001", bad);
  const auto outcomes = rbaa::read_sweep_outcomes(g, out);
  ASSERT_EQ(outcomes.size(), 3u);
  EXPECT_EQ(outcomes[2].status, rbaa::RowStatus::kPending);
  rbaa::write_sweep_results(g, out, outcomes);
  std::ifstream in(out + "/results.csv");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(
      text.str(),
      "row,status,time.duration,steps,newton.total_iterations,newton.max_iterations_in_a_step,"
      "min_contact_distance,timing.simulate_s,seconds,error,folder\n"
      "0,ok,0.1,3,12,5,,0.25,1.5,,row-000\n"
      "1,failed,0.2,,,,,,0.5,\"rbaa simulate: error: a, \"\"b\"\" [exit code 2]\",row-001\n"
      "2,pending,0.3,,,,,,,,row-002\n");

  // A folder holding a row of other settings is refused rather than mixed in.
  const auto changed =
      parse("config: star.yaml\nverb: simulate\nproduct: {time.duration: [0.15, 0.2]}\n");
  try {
    rbaa::read_sweep_outcomes(changed, out);
    FAIL() << "expected an error";
  } catch (const rbaa::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("row-000 holds a run of other settings"),
              std::string::npos)
        << e.what();
  }
}

// A row's arguments name the config by its path; its contents, its base's and its meshes' enter
// by the fingerprint its marker keeps, so a finished row of an edited config is not taken for the
// grid's row. The evaluation's duration, which the attack's scene_fingerprint leaves out, counts;
// comments do not.
TEST_F(SweepFiles, AnEditedConfigOrBaseIsAnotherRowButACommentIsNot) {
  const fs::path star = dir_ / "star.yaml", child = dir_ / "child.yaml";
  fs::copy_file(kConfigs + "/star.yaml", star);
  std::ofstream(child) << "base: star.yaml\ntime: {duration: 0.1}\n";
  const auto g = rbaa::parse_sweep_grid(
      "config: child.yaml\nverb: evaluate\nset: {mesh.target_tets: 300}\n"
      "product: {attack.seed: [1, 2]}\n",
      "grid.yaml", dir_.string());
  const std::string before = rbaa::config_fingerprint(g);
  EXPECT_EQ(before.size(), 16u);
  EXPECT_NE(rbaa::config_fingerprint_text(g).find("scene "), std::string::npos);
  const std::string scene_before = rbaa::scene_fingerprint(rbaa::load_scene(child.string()));
  const std::string out = (dir_ / "out").string();
  rbaa::RowOutcome ok{0,     rbaa::RowStatus::kOk, rbaa::row_arguments(g, g.rows[0]), "", 0, 1.0,
                      before};
  rbaa::write_row_outcome(out + "/row-000", ok);
  EXPECT_EQ(rbaa::read_sweep_outcomes(g, out)[1].config_fingerprint, before);

  auto star_text = [&] {
    std::ifstream in(star);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  };
  const std::string original = star_text();
  std::ofstream(star) << "# annotated\n" << original;
  EXPECT_EQ(rbaa::config_fingerprint(g), before);
  EXPECT_EQ(rbaa::read_sweep_outcomes(g, out)[0].status, rbaa::RowStatus::kOk);

  std::string edited = original;
  const std::string from = "  duration: 1.2\n";
  ASSERT_NE(edited.find(from), std::string::npos);
  edited.replace(edited.find(from), from.size(), "  duration: 2.4\n");
  std::ofstream(star) << edited;
  EXPECT_EQ(rbaa::scene_fingerprint(rbaa::load_scene(child.string())), scene_before);
  EXPECT_NE(rbaa::config_fingerprint(g), before);
  try {
    rbaa::read_sweep_outcomes(g, out);
    FAIL() << "expected an error";
  } catch (const rbaa::InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(out + "/row-000 holds a run of other settings than " +
                                              "grid.yaml's row 0: " + g.config +
                                              " or a file it builds on changed since (config "
                                              "fingerprint " +
                                              before + ", now ",
                                          0),
              0u)
        << e.what();
  }
  // A marker written before the sweep kept fingerprints cannot be checked: taken as it is.
  ok.config_fingerprint.clear();
  rbaa::write_row_outcome(out + "/row-000", ok);
  EXPECT_EQ(rbaa::read_sweep_outcomes(g, out)[0].status, rbaa::RowStatus::kOk);
}

// Only a finished row stands for the config it ran on. A row that failed (its config's mesh.file
// missing, say) or was interrupted runs again on the config as it is now: refusing it after the
// user mended the config contradicted "re-runs the failed ones".
TEST_F(SweepFiles, AFailedOrInterruptedRowOfAnEditedConfigRunsAgain) {
  const auto g = parse("config: star.yaml\nverb: simulate\nproduct: {time.duration: [0.1, 0.2]}\n");
  const std::string out = dir_.string(), now = rbaa::config_fingerprint(g);
  const std::string then = "0123456789abcdef";
  ASSERT_NE(now, then);
  const std::string error = "rbaa simulate: error: ball.msh: cannot read";
  rbaa::RowOutcome failed{
      0, rbaa::RowStatus::kFailed, rbaa::row_arguments(g, g.rows[0]), error, 2, 0.1, then};
  rbaa::write_row_outcome(out + "/row-000", failed);
  rbaa::RowOutcome running{
      1, rbaa::RowStatus::kRunning, rbaa::row_arguments(g, g.rows[1]), "", 0, 0, then};
  rbaa::write_row_outcome(out + "/row-001", running);
  const auto outcomes = rbaa::read_sweep_outcomes(g, out);
  EXPECT_EQ(outcomes[0].status, rbaa::RowStatus::kFailed);
  EXPECT_EQ(outcomes[1].status, rbaa::RowStatus::kRunning);
  for (const auto& o : outcomes) EXPECT_EQ(o.config_fingerprint, now);
  // The same row finished is refused.
  running.status = rbaa::RowStatus::kOk;
  rbaa::write_row_outcome(out + "/row-001", running);
  EXPECT_THROW(rbaa::read_sweep_outcomes(g, out), rbaa::InputError);
}

// A file a row's own value or the grid's flags name counted by its path only (the fingerprint
// loaded the scene with set: alone), though README said an edit of any file the config reads
// counts. Its bytes now enter that row's fingerprint: an edit of b2.msh is another row 0, not
// another row 1; an edit of the flag's file is another of both. A row naming no file keeps the
// grid's fingerprint, as markers written before hold it.
TEST_F(SweepFiles, AFileARowsValueOrAFlagNamesCountsByItsBytes) {
  fs::copy_file(kConfigs + "/star.yaml", dir_ / "star.yaml");
  std::ofstream(dir_ / "b2.msh") << "first mesh\n";
  const fs::path adversarial = dir_ / "a.msh";
  std::ofstream(adversarial) << "first object\n";
  const std::string head = "config: star.yaml\nverb: evaluate\n";
  const std::string rows =
      "rows: [{mesh.file: b2.msh}, {attack.seed: 1}, {obstacles.x: [a, b2.msh]}]\n";
  const auto g =
      rbaa::parse_sweep_grid(head + "flags: {adversarial: " + adversarial.string() + "}\n" + rows,
                             "grid.yaml", dir_.string());
  const auto plain = rbaa::parse_sweep_grid(head + rows, "grid.yaml", dir_.string());
  const std::string grid_print = rbaa::config_fingerprint(g);
  auto row_print = [&](const rbaa::SweepGrid& grid, int row) {
    return rbaa::row_config_fingerprint(grid_print, grid, grid.rows[row]);
  };
  EXPECT_EQ(
      rbaa::row_files_text(plain, plain.rows[0]).rfind("set mesh.file names b2.msh: bytes ", 0),
      0u);
  EXPECT_EQ(rbaa::row_files_text(plain, plain.rows[1]), "");
  EXPECT_EQ(row_print(plain, 1), grid_print);
  EXPECT_NE(row_print(plain, 0), grid_print);
  EXPECT_NE(row_print(plain, 2), grid_print);
  EXPECT_NE(rbaa::row_files_text(plain, plain.rows[2]).find("set obstacles.x names b2.msh"),
            std::string::npos);
  EXPECT_NE(
      rbaa::row_files_text(g, g.rows[1]).find("flag --adversarial names " + adversarial.string()),
      std::string::npos);

  const std::string out = (dir_ / "out").string();
  std::vector<std::string> before;
  for (int row = 0; row < 3; ++row) {
    before.push_back(row_print(g, row));
    rbaa::RowOutcome ok{row, rbaa::RowStatus::kOk, rbaa::row_arguments(g, g.rows[row]), "", 0,
                        1.0, before.back()};
    rbaa::write_row_outcome(out + "/row-00" + std::to_string(row), ok);
  }
  EXPECT_EQ(rbaa::read_sweep_outcomes(g, out)[0].status, rbaa::RowStatus::kOk);

  std::ofstream(dir_ / "b2.msh") << "second mesh\n";
  EXPECT_NE(row_print(g, 0), before[0]);
  EXPECT_EQ(row_print(g, 1), before[1]);
  try {
    rbaa::read_sweep_outcomes(g, out);
    FAIL() << "expected an error";
  } catch (const rbaa::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("row-000 holds a run of other settings than grid.yaml's "
                                         "row 0: " +
                                         g.config +
                                         ", a file it builds on or one the row's values name "
                                         "changed since"),
              std::string::npos)
        << e.what();
  }
  std::ofstream(dir_ / "b2.msh") << "first mesh\n";
  std::ofstream(adversarial) << "second object\n";
  for (int row = 0; row < 3; ++row) EXPECT_NE(row_print(g, row), before[row]) << row;
}

// A swept key's cell is the value the row ran with: its own, else the grid's set: value.
TEST_F(SweepFiles, ResultsTableFillsASweptKeyFromSetWhereTheRowHasNone) {
  const auto g = parse(
      "config: star.yaml\nverb: study\n"
      "set: {a.b: 5}\n"
      "rows: [{a.b: 1}, {c.d: 2}]\n");
  EXPECT_EQ(rbaa::row_arguments(g, g.rows[1])[2], "--set=a.b=5;c.d=2");
  const std::string csv =
      rbaa::sweep_results_csv(g, dir_.string(), rbaa::read_sweep_outcomes(g, dir_.string()));
  EXPECT_EQ(csv,
            "row,status,a.b,c.d,seconds,error,folder\n"
            "0,pending,1,,,,row-000\n"
            "1,pending,5,2,,,row-001\n");
}

// An attack row whose folder holds the attack's checkpoint continues from it (--resume on the
// process's command line only); other verbs, and attack rows without one, start afresh.
TEST_F(SweepFiles, AnAttackRowWithACheckpointResumesIt) {
  const auto attack = parse("config: star.yaml\nverb: attack\nproduct: {attack.seed: [1]}\n");
  const auto args = rbaa::row_arguments(attack, attack.rows[0]);
  const std::string row = (dir_ / "row-000").string();
  EXPECT_EQ(rbaa::row_process_arguments(attack, args, row), args);
  fs::create_directories(row);
  std::ofstream(row + "/checkpoint.json") << "{}\n";
  auto resumed = args;
  resumed.push_back("--resume");
  EXPECT_EQ(rbaa::row_process_arguments(attack, args, row), resumed);
  // The grid's own --resume is not given twice.
  const auto own = parse(
      "config: star.yaml\nverb: attack\nflags: {resume: true}\nproduct: {attack.seed: [1]}\n");
  const auto own_args = rbaa::row_arguments(own, own.rows[0]);
  EXPECT_EQ(rbaa::row_process_arguments(own, own_args, row), own_args);
  const auto simulate = parse("config: star.yaml\nverb: simulate\nproduct: {time.step: [0.01]}\n");
  const auto simulate_args = rbaa::row_arguments(simulate, simulate.rows[0]);
  EXPECT_EQ(rbaa::row_process_arguments(simulate, simulate_args, row), simulate_args);
}

TEST_F(SweepFiles, SlurmArrayHasOneTaskPerRowAndAMergeAfterIt) {
  const auto g = parse(
      "config: star.yaml\nverb: simulate\nproduct: {time.duration: [0.1, 0.2], attack.seed: [1, "
      "2]}\n"
      "slurm: {time: '00:10:00', partition: short}\n");
  rbaa::SlurmJob job{"/data/grid.yaml", "/data/out", "/opt/rbaa/bin/rbaa", "/data", 2};
  const auto s = rbaa::slurm_scripts(g, job);
  auto has = [](const std::string& text, const std::string& line) {
    EXPECT_NE(text.find(line), std::string::npos) << "missing: " << line << "\nin:\n" << text;
  };
  has(s.array, "#!/bin/bash\n");
  has(s.array, "\n#SBATCH --array=0-3%2\n");
  has(s.array, "\n#SBATCH --output=/data/out/slurm/row-%a.out\n");
  has(s.array, "\n#SBATCH --chdir=/data\n");
  has(s.array, "\n#SBATCH --time=00:10:00\n#SBATCH --partition=short\n#SBATCH --cpus-per-task=1\n");
  has(s.array,
      "\nexec '/opt/rbaa/bin/rbaa' sweep --grid='/data/grid.yaml' --out='/data/out' "
      "--row=\"$SLURM_ARRAY_TASK_ID\"\n");
  has(s.merge,
      "\nexec '/opt/rbaa/bin/rbaa' sweep --grid='/data/grid.yaml' --out='/data/out' --merge\n");
  EXPECT_EQ(s.merge.find("--array"), std::string::npos);
  has(s.submit, "array=$(sbatch --parsable '/data/out/slurm/array.sbatch')\n");
  has(s.submit,
      "merge=$(sbatch --parsable --dependency=afterany:\"$array\" "
      "'/data/out/slurm/merge.sbatch')\n");

  job.out_dir = dir_.string();
  const std::string submit = rbaa::write_slurm_scripts(g, job);
  EXPECT_EQ(submit, (dir_ / "slurm/submit.sh").string());
  for (const char* f : {"array.sbatch", "merge.sbatch", "submit.sh"}) {
    EXPECT_TRUE(fs::exists(dir_ / "slurm" / f)) << f;
  }
}

}  // namespace
