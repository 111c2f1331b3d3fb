// rbaa sweep as a user runs it: a 4-row sweep of short star simulations on this machine (results,
// resume, a row that fails alone, the thread split), bad grid files, and the same kind of sweep
// through a real single-node Slurm (scripts/slurm_localhost.sh), skipped where it cannot start.

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <thread>
#include <vector>

#include "cli/cli_fixture.hpp"
#include "rbaa/sweep/thread_split.hpp"

namespace {

using rbaa_cli_test::Cli;
using rbaa_cli_test::Result;
namespace fs = std::filesystem;

const std::string kStar = std::string(RBAA_SOURCE_DIR) + "/configs/star.yaml";

// The star at ~580 tets (its floor for 300) for two steps of 1/30 s: a second or two per row.
std::string star_grid(const std::string& rows, const std::string& config = kStar) {
  return "config: " + config +
         "\n"
         "verb: simulate\n"
         "set: {mesh.target_tets: 300, time.duration: 0.0667}\n"
         "flags: {vtu_every: 0, progress: false}\n" +
         rows;
}

std::vector<std::vector<std::string>> csv_rows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    std::vector<std::string> cells;
    std::string cell;
    bool quoted = false;
    for (char c : line) {
      if (c == '"') {
        quoted = !quoted;
      } else if (c == ',' && !quoted) {
        cells.push_back(cell);
        cell.clear();
      } else {
        cell += c;
      }
    }
    cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

int column(const std::vector<std::string>& header, const std::string& name) {
  for (size_t i = 0; i < header.size(); ++i) {
    if (header[i] == name) return static_cast<int>(i);
  }
  ADD_FAILURE() << "no column " << name;
  return 0;
}

class CliSweep : public Cli {
 protected:
  nlohmann::json report(const std::string& out, int row) const {
    return Cli::report(out + "/row-00" + std::to_string(row));
  }
};

// Four rows, two at a time, one with an override the scene rejects: it fails alone, with the
// scene's one-line error in results.csv; the others finish. Running again skips the three
// finished rows and retries the failed one; --row and --merge do what the Slurm tasks do.
TEST_F(CliSweep, FourStarRowsWithOneBadOverrideResumeAndMerge) {
  const std::string grid =
      write_file("grid.yaml", star_grid("rows:\n"
                                        "  - {object.velocity: [0, -10, -10]}\n"
                                        "  - {object.velocity: [0, -5, -5]}\n"
                                        "  - {time.duration: -1}\n"
                                        "  - {object.velocity: [0, -10, -5]}\n"));
  const std::string args = "sweep --grid=" + grid + " --out=" + path("out") + " --jobs=2";
  const Result first = run(args);
  EXPECT_EQ(first.exit_code, 1) << first.err;  // one row failed
  // Progress lines say what is done, running and failed, and the time left.
  EXPECT_NE(first.err.find("2 jobs x "), std::string::npos) << first.err;
  EXPECT_NE(first.err.find("row 1 ok in "), std::string::npos) << first.err;
  EXPECT_NE(first.err.find("row 2 failed in "), std::string::npos) << first.err;
  EXPECT_NE(first.err.find(" done, 1 running, "), std::string::npos) << first.err;
  EXPECT_NE(first.err.find("| 3/4 done, 0 running, 1 failed | ETA 0.0 s"), std::string::npos)
      << first.err;
  EXPECT_NE(first.err.find("4 rows: 3 ok, 0 skipped (finished earlier), 1 failed"),
            std::string::npos)
      << first.err;

  const std::string results = slurp(path("out/results.csv"));
  const auto table = csv_rows(results);
  ASSERT_EQ(table.size(), 5u) << results;
  const auto& h = table[0];
  EXPECT_EQ(h[0], "row");
  EXPECT_EQ(h[1], "status");
  EXPECT_EQ(h[2], "object.velocity");
  EXPECT_EQ(h[3], "time.duration");
  for (int row : {0, 1, 3}) {
    const auto& r = table[row + 1];
    EXPECT_EQ(r[column(h, "status")], "ok") << results;
    EXPECT_EQ(r[column(h, "steps")], "2") << results;
    EXPECT_GE(std::stoi(r[column(h, "newton.total_iterations")]), 2) << results;
    EXPECT_GT(std::stod(r[column(h, "timing.simulate_s")]), 0.0) << results;
    EXPECT_TRUE(r[column(h, "error")].empty()) << results;
    EXPECT_EQ(r[column(h, "folder")], "row-00" + std::to_string(row));
  }
  EXPECT_EQ(table[1][2], "[0, -10, -10]");
  const auto& bad = table[3];
  EXPECT_EQ(bad[column(h, "status")], "failed");
  EXPECT_EQ(bad[column(h, "time.duration")], "-1");
  EXPECT_NE(bad[column(h, "error")].find("error: "), std::string::npos) << results;
  EXPECT_NE(bad[column(h, "error")].find("time.duration"), std::string::npos) << results;
  EXPECT_NE(bad[column(h, "error")].find("[exit code 2]"), std::string::npos) << results;
  EXPECT_TRUE(fs::exists(path("out/row-002/log.txt")));

  // Each row had cores / jobs OpenMP threads (ctest's OMP_NUM_THREADS=2 notwithstanding).
  const int threads = std::max(1, rbaa::available_cores() / 2);
  EXPECT_EQ(report("out", 0)["timing"]["threads"].get<int>(), threads);

  // Resume: finished rows are not run again (their report is untouched), the failed one is.
  const auto stamp = fs::last_write_time(path("out/row-000/report.json"));
  const Result again = run(args);
  EXPECT_EQ(again.exit_code, 1) << again.err;
  EXPECT_NE(again.err.find("4 rows: 0 ok, 3 skipped (finished earlier), 1 failed"),
            std::string::npos)
      << again.err;
  EXPECT_EQ(again.err.find("row 0 started"), std::string::npos) << again.err;
  EXPECT_NE(again.err.find("row 2 started"), std::string::npos) << again.err;
  EXPECT_EQ(fs::last_write_time(path("out/row-000/report.json")), stamp);
  EXPECT_EQ(slurp(path("out/results.csv")).substr(0, results.find("\n1,")),
            results.substr(0, results.find("\n1,")));

  // One row alone (a Slurm task) leaves results.csv to --merge; --threads is the user's choice.
  const std::string merged_before = slurp(path("out/results.csv"));
  fs::remove_all(path("out/row-003"));
  const Result one = run("sweep --grid=" + grid + " --out=" + path("out") + " --row=3 --threads=2");
  EXPECT_EQ(one.exit_code, 0) << one.err;
  EXPECT_EQ(report("out", 3)["timing"]["threads"].get<int>(), 2);
  EXPECT_EQ(slurp(path("out/results.csv")), merged_before);
  const Result merge = run("sweep --grid=" + grid + " --out=" + path("out") + " --merge");
  EXPECT_EQ(merge.exit_code, 1) << merge.err;
  EXPECT_NE(merge.err.find("4 rows: 3 ok, 1 failed, 0 unfinished, 0 never started"),
            std::string::npos)
      << merge.err;
  EXPECT_EQ(csv_rows(slurp(path("out/results.csv"))).size(), 5u);
  const Result out_of_range = run("sweep --grid=" + grid + " --out=" + path("out") + " --row=4");
  EXPECT_EQ(out_of_range.exit_code, 2);
  EXPECT_NE(out_of_range.err.find("has 4 rows (0 to 3)"), std::string::npos) << out_of_range.err;

  // The grid changed under the same --out: refused, not mixed.
  const std::string changed =
      write_file("changed.yaml", star_grid("product: {time.duration: [0.1]}\n"));
  expect_failure("sweep --grid=" + changed + " --out=" + path("out"),
                 "holds a run of other settings");
}

// The review's case: a finished row of a config edited since (the star's velocity) was skipped as
// finished, its results standing for the new velocity. The marker keeps the config's fingerprint:
// an edit is refused as other settings, a comment is not an edit.
TEST_F(CliSweep, AFinishedRowOfAnEditedConfigIsNotTakenAsFinished) {
  const std::string star = path("star.yaml");
  std::filesystem::copy_file(kStar, star);
  const std::string original = slurp(star);
  const std::string grid =
      write_file("grid.yaml", star_grid("rows: [{time.step: 0.0333}]\n", star));
  const std::string args = "sweep --grid=" + grid + " --out=" + path("out");
  const Result first = run(args);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  const std::string results = slurp(path("out/results.csv"));

  std::string slower = original;
  const std::string velocity = "velocity: [0, -10, -10]";
  ASSERT_NE(slower.find(velocity), std::string::npos);
  slower.replace(slower.find(velocity), velocity.size(), "velocity: [0, -5, -5]");
  write_file("star.yaml", slower);
  expect_failure(args, "row-000 holds a run of other settings than " + grid + "'s row 0: " + star +
                           " or a file it builds on changed since (config fingerprint ");
  EXPECT_EQ(slurp(path("out/results.csv")), results);

  write_file("star.yaml", "# the same star, annotated\n" + original);
  const Result again = run(args);
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.err.find("1 row: 0 ok, 1 skipped (finished earlier)"), std::string::npos)
      << again.err;
}

// An attack row interrupted after some iterations (its marker left "running", its checkpoint
// written) continues from the checkpoint when the sweep runs again, instead of starting over and
// overwriting it, and ends where an uninterrupted row ends. The tiny ball: ~0.6 s an attack.
TEST_F(CliSweep, AnInterruptedAttackRowContinuesFromItsCheckpoint) {
  const std::string ball = write_file("ball.yaml", rbaa_cli_test::kTinyBall);
  const std::string grid = write_file(
      "grid.yaml", "config: " + ball +
                       "\nverb: attack\nset: {attack.iterations: 4}\nrows: [{attack.seed: 2}]\n");
  const std::string args = "sweep --grid=" + grid + " --out=" + path("out");
  const Result straight = run(args);
  ASSERT_EQ(straight.exit_code, 0) << straight.err;
  const nlohmann::json uninterrupted = report("out", 0);

  // The row as a killed sweep leaves it after 2 of its 4 iterations: the same scene's checkpoint
  // (the attack's fingerprint leaves out the iteration count), no report, marker "running".
  const Result half =
      run("attack --config=" + ball +
          " --set='attack.iterations=4;attack.seed=2' --iterations=2 --out=" + path("half"));
  ASSERT_EQ(half.exit_code, 0) << half.err;
  fs::copy_file(path("half/checkpoint.json"), path("out/row-000/checkpoint.json"),
                fs::copy_options::overwrite_existing);
  fs::remove(path("out/row-000/report.json"));
  nlohmann::json marker = nlohmann::json::parse(slurp(path("out/row-000/sweep_row.json")));
  const auto arguments = marker["arguments"];
  marker["status"] = "running";
  write_file("out/row-000/sweep_row.json", marker.dump(2));

  const Result resumed = run(args);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_NE(resumed.err.find("row 0 started (attack.seed=2; resuming its checkpoint)"),
            std::string::npos)
      << resumed.err;
  const std::string log = slurp(path("out/row-000/log.txt"));
  EXPECT_EQ(log.find("iter    1/4"), std::string::npos) << log;
  EXPECT_EQ(log.find("iter    2/4"), std::string::npos) << log;
  EXPECT_NE(log.find("iter    3/4"), std::string::npos) << log;
  EXPECT_EQ(report("out", 0)["iterations"], 4);
  EXPECT_EQ(report("out", 0)["gap"], uninterrupted["gap"]);
  // The marker keeps the grid's arguments, without --resume: the next run skips the row.
  EXPECT_EQ(nlohmann::json::parse(slurp(path("out/row-000/sweep_row.json")))["arguments"],
            arguments);
  const Result again = run(args);
  EXPECT_NE(again.err.find("1 row: 0 ok, 1 skipped (finished earlier)"), std::string::npos)
      << again.err;
}

// The review's case: a row failed because its config's mesh.file did not exist yet; once the
// user made it, the sweep refused the row as one of other settings ("holds a run of other
// settings ... use another --out") instead of re-running it as its help promises. A failed row
// now runs again on the config as it is.
TEST_F(CliSweep, ARowThatFailedRunsAgainOnTheMendedConfig) {
  std::string ball = rbaa_cli_test::kTinyBall;
  const std::string shape = "shape: sphere, radius: 0.1, target_tets: 300";
  ball.replace(ball.find(shape), shape.size(), "file: ball.msh");
  const std::string config = write_file("ball.yaml", ball);
  const std::string grid =
      write_file("grid.yaml", "config: " + config +
                                  "\nverb: simulate\nflags: {vtu_every: 0, progress: false}\n"
                                  "rows: [{time.step: 0.01}]\n");
  const std::string args = "sweep --grid=" + grid + " --out=" + path("out");
  const Result missing = run(args);
  EXPECT_EQ(missing.exit_code, 1) << missing.err;
  EXPECT_NE(missing.err.find("ball.msh: cannot read"), std::string::npos) << missing.err;

  ASSERT_EQ(
      run("mesh --shape=sphere --radius=0.1 --target_tets=300 --out=" + path("ball.msh")).exit_code,
      0);
  const Result mended = run(args);
  EXPECT_EQ(mended.exit_code, 0) << mended.err;
  EXPECT_NE(mended.err.find("1 row: 1 ok, 0 skipped"), std::string::npos) << mended.err;
  EXPECT_EQ(report("out", 0)["steps"], 5);
}

// The review's case: a finished row that read another mesh through its own override
// (rows: [{mesh.file: b2.msh}]) was skipped as finished after b2.msh was meshed again, its
// results standing for the old mesh. The row's fingerprint now holds the file's bytes.
TEST_F(CliSweep, AFinishedRowWhoseOwnMeshFileChangedIsNotTakenAsFinished) {
  std::string ball = rbaa_cli_test::kTinyBall;
  const std::string shape = "shape: sphere, radius: 0.1, target_tets: 300";
  ball.replace(ball.find(shape), shape.size(), "file: ball.msh");
  const std::string config = write_file("ball.yaml", ball);
  const std::string mesh = "mesh --shape=sphere --radius=0.1 --out=";
  ASSERT_EQ(run(mesh + path("ball.msh") + " --target_tets=300").exit_code, 0);
  ASSERT_EQ(run(mesh + path("b2.msh") + " --target_tets=200").exit_code, 0);
  const std::string grid =
      write_file("grid.yaml", "config: " + config +
                                  "\nverb: simulate\nflags: {vtu_every: 0, progress: false}\n"
                                  "rows: [{mesh.file: b2.msh}]\n");
  const std::string args = "sweep --grid=" + grid + " --out=" + path("out");
  ASSERT_EQ(run(args).exit_code, 0);
  EXPECT_NE(run(args).err.find("1 row: 0 ok, 1 skipped (finished earlier)"), std::string::npos);

  ASSERT_EQ(run(mesh + path("b2.msh") + " --target_tets=400").exit_code, 0);
  expect_failure(args, "row-000 holds a run of other settings than " + grid +
                           "'s row 0: " + config +
                           ", a file it builds on or one the row's values name changed "
                           "since (config fingerprint ");
}

// An interrupted attack row of a config edited since is resumed, and rbaa attack refuses the
// checkpoint of another scene itself: the row fails naming both fingerprints, with the sweep's
// own advice (the attack's "drop --resume" is not the user's to follow), rather than going on
// from the old scene's design. Without its checkpoint the row starts over and finishes.
TEST_F(CliSweep, AnAttackRowsCheckpointOfAnEditedSceneIsRefusedNotResumed) {
  const std::string ball = write_file("ball.yaml", rbaa_cli_test::kTinyBall);
  const std::string grid = write_file(
      "grid.yaml", "config: " + ball +
                       "\nverb: attack\nset: {attack.iterations: 2}\nrows: [{attack.seed: 2}]\n");
  const std::string args = "sweep --grid=" + grid + " --out=" + path("out");
  ASSERT_EQ(run(args).exit_code, 0);
  ASSERT_TRUE(fs::exists(path("out/row-000/checkpoint.json")));
  nlohmann::json marker = nlohmann::json::parse(slurp(path("out/row-000/sweep_row.json")));
  marker["status"] = "running";
  write_file("out/row-000/sweep_row.json", marker.dump(2));
  fs::remove(path("out/row-000/report.json"));
  std::string slower = rbaa_cli_test::kTinyBall;
  const std::string velocity = "velocity: [0, 2.0, 0]";
  slower.replace(slower.find(velocity), velocity.size(), "velocity: [0, 1.5, 0]");
  write_file("ball.yaml", slower);

  const Result resumed = run(args);
  EXPECT_EQ(resumed.exit_code, 1) << resumed.err;
  EXPECT_NE(resumed.err.find("resuming its checkpoint"), std::string::npos) << resumed.err;
  const auto table = csv_rows(slurp(path("out/results.csv")));
  ASSERT_EQ(table.size(), 2u);
  const std::string error = table[1][column(table[0], "error")];
  EXPECT_NE(error.find("checkpoint.json: checkpoint belongs to another scene or other settings "
                       "(fingerprint "),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("(the sweep resumed the row's checkpoint.json: remove it to start the row "
                       "over)"),
            std::string::npos)
      << error;
  EXPECT_FALSE(fs::exists(path("out/row-000/report.json")));

  fs::remove(path("out/row-000/checkpoint.json"));
  const Result over = run(args);
  EXPECT_EQ(over.exit_code, 0) << over.err;
  EXPECT_EQ(report("out", 0)["iterations"], 2);
}

TEST_F(CliSweep, BadGridFilesGiveOneLineErrors) {
  const std::string head = "config: " + kStar + "\nverb: simulate\n";
  auto fails = [&](const std::string& name, const std::string& text, const std::string& message) {
    const std::string grid = write_file(name, text);
    expect_failure("sweep --grid=" + grid + " --out=" + path("out"), grid + message);
  };
  fails("unknown_key.yaml", head + "product: {time.step: [0.01]}\nseeds: [1, 2]\n",
        ":4: unknown key 'seeds' (a grid has: config, verb, set, flags, product, rows, report, "
        "slurm)");
  fails("empty_product.yaml", head + "product: {}\n",
        ":3: product: empty (give key.path: [values])");
  fails("empty_list.yaml", head + "product:\n  time.step: []\n",
        ":4: product: key 'time.step': empty list");
  fails("unknown_verb.yaml", "config: " + kStar + "\nverb: smulate\nproduct: {time.step: [0.01]}\n",
        ":2: verb 'smulate' is not one of: attack, evaluate, simulate, study");
  fails("unknown_flag.yaml", head + "flags:\n  vtu_evry: 0\nproduct: {time.step: [0.01]}\n",
        ":4: flags: unknown flag --vtu_evry (rbaa simulate --help lists its flags)");
  // A flag of another verb: gflags knows it, but every row would fail on it.
  fails("other_verbs_flag.yaml", head + "flags: {iterations: 5}\nproduct: {time.step: [0.01]}\n",
        ":3: flags: --iterations is not a flag of rbaa simulate (rbaa simulate --help lists its "
        "flags)");
  fails("twice.yaml", head + "product: {time.step: [0.01]}\nproduct: {time.step: [0.02]}\n",
        ":4: key 'product' is given twice in this mapping (only one value can hold)");
  // Under flags: too: every row ran with --vtu_every=0 --vtu_every=1, the last winning.
  fails("flag_twice.yaml",
        head + "flags:\n  vtu_every: 0\n  vtu_every: 1\nproduct: {time.step: [0.01]}\n",
        ":5: key 'flags.vtu_every' is given twice in this mapping (only one value can hold)");
  // A key that is a list: an input error (exit 2) naming the line, not yaml-cpp's conversion.
  fails("list_key.yaml", head + "? [a, b]\n: 1\nproduct: {time.step: [0.01]}\n",
        ":3: a key must be a name, not a list or mapping");
  EXPECT_EQ(run("sweep --grid=" + path("list_key.yaml") + " --out=" + path("out")).exit_code, 2);
  expect_failure("sweep --grid=" + path("missing.yaml") + " --out=" + path("out"),
                 "missing.yaml: cannot read the grid file");
  expect_failure("sweep --out=" + path("out"), "--grid is required");
  // --merge into a folder no row ran in: said so, not "cannot write results.csv".
  const std::string good = write_file("good.yaml", head + "product: {time.step: [0.01]}\n");
  expect_failure("sweep --grid=" + good + " --out=" + path("out") + " --merge",
                 "--out: '" + path("out") + "' is not a folder: nothing to merge");
  EXPECT_FALSE(fs::exists(path("out")));

  const Result help = run("sweep --help");
  EXPECT_EQ(help.exit_code, 0);
  for (const char* flag : {"--grid", "--jobs", "--threads", "--row", "--merge", "--emit"}) {
    EXPECT_NE(help.out.find(flag), std::string::npos) << flag;
  }
  EXPECT_NE(run("--help").out.find("sweep"), std::string::npos);
}

// The Slurm engine itself: a one-node cluster on this machine (scripts/slurm_localhost.sh, as
// root; CI installs slurm-wlm and munge), an array of 4 rows submitted with the emitted
// submit.sh, and the merge job's results.csv.
TEST_F(CliSweep, SlurmArrayOfFourRowsThroughTheRealEngine) {
  const std::string script = std::string(RBAA_SOURCE_DIR) + "/scripts/slurm_localhost.sh";
  const bool was_up = std::system(("bash " + script + " status >/dev/null 2>&1").c_str()) == 0;
  const std::string log = path("slurm_start.txt");
  const Result start = shell("bash " + script + " start 2>" + log);
  const std::string& started = start.out;
  if (start.exit_code != 0) {
    std::string why = slurp(log);
    while (!why.empty() && why.back() == '\n') why.pop_back();
    GTEST_SKIP() << "no Slurm engine on this machine (" << why
                 << "); install it with: bash scripts/slurm_localhost.sh install (as root)";
  }
  const std::string key = "export SLURM_CONF=";
  ASSERT_EQ(started.rfind(key, 0), 0u) << started;
  const std::string slurm_conf = started.substr(key.size(), started.find('\n') - key.size());
  const std::string env = "SLURM_CONF=" + slurm_conf + " ";

  const std::string grid =
      write_file("grid.yaml", star_grid("product:\n"
                                        "  object.velocity: [[0, -10, -10], [0, -5, -5]]\n"
                                        "  time.duration: [0.034, 0.0667]\n"));
  const Result emit = run("sweep --grid=" + grid + " --out=" + path("out") + " --emit=slurm");
  ASSERT_EQ(emit.exit_code, 0) << emit.err;
  EXPECT_NE(emit.err.find("submit with: bash " + path("out/slurm/submit.sh")), std::string::npos)
      << emit.err;
  EXPECT_FALSE(fs::exists(path("out/row-000")));  // emitting runs nothing

  const Result submit = shell(env + "bash " + path("out/slurm/submit.sh") + " 2>&1");
  ASSERT_EQ(submit.exit_code, 0) << submit.out;
  EXPECT_NE(submit.out.find("(4 tasks), merge job "), std::string::npos) << submit.out;
  // "array job A (4 tasks), merge job M -> ..."
  const std::string array_id = submit.out.substr(10, submit.out.find(' ', 10) - 10);
  const size_t m = submit.out.find("merge job ") + 10;
  const std::string merge_id = submit.out.substr(m, submit.out.find(' ', m) - m);

  // The merge job writes merge.out when it ends; rows take a second or two each.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(8);
  std::string merged;
  while (std::chrono::steady_clock::now() < deadline) {
    const std::string queue =
        shell(env + "squeue -h -o %i -j " + array_id + "," + merge_id + " 2>/dev/null").out;
    if (queue.empty() && fs::exists(path("out/slurm/merge.out"))) break;
    std::this_thread::sleep_for(std::chrono::seconds(1));
  }
  const std::string results = slurp(path("out/results.csv"));
  if (results.empty()) {
    (void)std::system((env + "scancel " + array_id + " " + merge_id + " 2>/dev/null").c_str());
  }
  const auto table = csv_rows(results);
  ASSERT_EQ(table.size(), 5u) << results << slurp(path("out/slurm/merge.out"));
  const auto& h = table[0];
  for (int row = 0; row < 4; ++row) {
    EXPECT_EQ(table[row + 1][column(h, "status")], "ok")
        << results << slurp(path("out/slurm/row-" + std::to_string(row) + ".out"));
    EXPECT_TRUE(fs::exists(path("out/slurm/row-" + std::to_string(row) + ".out")));
  }
  EXPECT_EQ(table[1][column(h, "steps")], "1");
  EXPECT_EQ(table[2][column(h, "steps")], "2");
  EXPECT_EQ(table[3][column(h, "object.velocity")], "[0, -5, -5]");
  // Each task ran on its --cpus-per-task=1 (SLURM_CPUS_PER_TASK), not on the node's cores.
  EXPECT_EQ(report("out", 0)["timing"]["threads"].get<int>(), 1);
  EXPECT_NE(slurp(path("out/slurm/merge.out")).find("4 rows: 4 ok"), std::string::npos);

  if (!was_up) (void)std::system(("bash " + script + " stop").c_str());
}

}  // namespace
