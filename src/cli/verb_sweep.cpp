// rbaa sweep: runs a grid of `rbaa attack|evaluate|simulate|study` rows (a product of lists or
// explicit rows of --set overrides) on this machine, or writes a Slurm job array that does.

#include <gflags/gflags.h>
#include <unistd.h>

#include <algorithm>
#include <climits>
#include <cstdio>
#include <filesystem>
#include <string>

#include "rbaa/cli/verb.hpp"
#include "rbaa/error.hpp"
#include "rbaa/sweep/slurm_script.hpp"
#include "rbaa/sweep/sweep_grid.hpp"
#include "rbaa/sweep/sweep_results.hpp"
#include "rbaa/sweep/sweep_runner.hpp"
#include "rbaa/sweep/thread_split.hpp"

DECLARE_string(out);
DEFINE_string(grid, "", "sweep: the grid file (YAML; README, \"Parameter sweeps\")");
DEFINE_int32(jobs, 1,
             "sweep: rows run at once on this machine (with --emit=slurm: at most this "
             "many array tasks at once if > 1)");
DEFINE_int32(threads, 0,
             "sweep: OpenMP threads per row; 0: cores / jobs (at least 1), so that "
             "jobs x threads <= cores");
DEFINE_int32(row, -1,
             "sweep: run only this row (0-based; a Slurm array task's "
             "$SLURM_ARRAY_TASK_ID) and leave results.csv to --merge");
DEFINE_bool(merge, false, "sweep: run nothing; gather the rows' outcomes into DIR/results.csv");
DEFINE_string(emit, "",
              "sweep: 'slurm' writes DIR/slurm/{array.sbatch,merge.sbatch,submit.sh} "
              "and runs nothing");

namespace {

namespace fs = std::filesystem;

std::string own_executable() {
  char buf[PATH_MAX];
  const ssize_t n = ::readlink("/proc/self/exe", buf, sizeof(buf) - 1);
  if (n <= 0) throw std::runtime_error("cannot find the rbaa program (/proc/self/exe)");
  return std::string(buf, static_cast<size_t>(n));
}

std::string duration_text(double s) {
  char buf[64];
  if (s < 10) {
    std::snprintf(buf, sizeof(buf), "%.1f s", s);
  } else if (s < 60) {
    std::snprintf(buf, sizeof(buf), "%.0f s", s);
  } else if (s < 3600) {
    std::snprintf(buf, sizeof(buf), "%d min %02d s", static_cast<int>(s) / 60,
                  static_cast<int>(s) % 60);
  } else {
    std::snprintf(buf, sizeof(buf), "%d h %02d min", static_cast<int>(s) / 3600,
                  (static_cast<int>(s) % 3600) / 60);
  }
  return buf;
}

std::string overrides_text(const rbaa::SweepRow& row) {
  std::string s;
  for (const auto& o : row.overrides) s += (s.empty() ? "" : " ") + o.key + "=" + o.value;
  return s.empty() ? "base config" : s;
}

// Every extra flag of the grid must be one the grid's verb reads (a typo, or another verb's flag,
// would fail every row): main() refuses those for the row, and this before any row starts.
void check_grid_flags(const rbaa::SweepGrid& grid) {
  const auto verbs = rbaa::cli::registered_verbs();
  const auto verb = std::find_if(verbs.begin(), verbs.end(),
                                 [&](const rbaa::cli::Verb& v) { return v.name == grid.verb; });
  for (const rbaa::SweepFlag& f : grid.flags) {
    const std::string where = grid.source + ":" + std::to_string(f.line) + ": flags: ";
    const std::string help = " (rbaa " + grid.verb + " --help lists its flags)";
    gflags::CommandLineFlagInfo info;
    if (!gflags::GetCommandLineFlagInfo(f.name.c_str(), &info)) {
      throw rbaa::InputError(where + "unknown flag --" + f.name + help);
    }
    if (verb != verbs.end() && !rbaa::cli::verb_reads_flag(*verb, info.name, info.filename)) {
      throw rbaa::InputError(where + "--" + f.name + " is not a flag of rbaa " + grid.verb + help);
    }
  }
}

int run_sweep_verb() {
  if (FLAGS_grid.empty()) throw rbaa::InputError("--grid is required");
  if (FLAGS_out.empty()) throw rbaa::InputError("--out is required (the sweep's folder)");
  if (!FLAGS_emit.empty() && FLAGS_emit != "slurm") {
    throw rbaa::InputError("--emit: '" + FLAGS_emit + "' is not one of: slurm");
  }
  if (FLAGS_merge && (FLAGS_row >= 0 || !FLAGS_emit.empty())) {
    throw rbaa::InputError("--merge runs alone (not with --row or --emit)");
  }
  if (FLAGS_row < -1) throw rbaa::InputError("--row must be >= 0");
  const rbaa::SweepGrid grid = rbaa::load_sweep_grid(FLAGS_grid);
  check_grid_flags(grid);
  const std::string out_dir = fs::absolute(FLAGS_out).lexically_normal().string();

  if (FLAGS_emit == "slurm") {
    rbaa::SlurmJob job;
    job.grid = fs::absolute(FLAGS_grid).lexically_normal().string();
    job.out_dir = out_dir;
    job.executable = own_executable();
    job.workdir = fs::current_path().string();
    job.max_parallel = FLAGS_jobs > 1 ? FLAGS_jobs : 0;
    const std::string submit = rbaa::write_slurm_scripts(grid, job);
    std::fprintf(stderr,
                 "sweep: %zu rows as a Slurm array in %s/slurm (array.sbatch, merge.sbatch); "
                 "submit with: bash %s\n",
                 grid.rows.size(), out_dir.c_str(), submit.c_str());
    return 0;
  }

  if (FLAGS_merge) {
    if (!fs::is_directory(out_dir)) {
      throw rbaa::InputError("--out: '" + out_dir +
                             "' is not a folder: nothing to merge (run the sweep's rows into it first)");
    }
    const auto outcomes = rbaa::read_sweep_outcomes(grid, out_dir);
    rbaa::write_sweep_results(grid, out_dir, outcomes);
    int counts[4] = {0, 0, 0, 0};
    for (const auto& o : outcomes) ++counts[static_cast<int>(o.status)];
    std::fprintf(
        stderr,
        "sweep: %zu rows: %d ok, %d failed, %d unfinished, %d never started -> %s/results.csv\n",
        outcomes.size(), counts[2], counts[3], counts[1], counts[0], out_dir.c_str());
    return counts[2] == static_cast<int>(outcomes.size()) ? 0 : 1;
  }

  rbaa::SweepOptions options;
  options.executable = own_executable();
  options.out_dir = out_dir;
  options.only_row = FLAGS_row;
  const int jobs = FLAGS_row >= 0 ? 1 : FLAGS_jobs;
  options.split = rbaa::split_threads(jobs, FLAGS_threads, rbaa::available_cores());
  const std::string which = FLAGS_row >= 0 ? "row " + std::to_string(FLAGS_row) + " of " +
                                                 std::to_string(grid.rows.size())
                                           : std::to_string(grid.rows.size()) + " rows";
  std::fprintf(stderr, "sweep: %s: %s of rbaa %s -> %s (%s)\n", grid.source.c_str(), which.c_str(),
               grid.verb.c_str(), out_dir.c_str(), rbaa::describe(options.split).c_str());
  if (options.split.oversubscribed) {
    std::fprintf(stderr, "sweep: note: %d x %d threads > %d cores: rows will compete for cores\n",
                 options.split.jobs, options.split.threads, options.split.cores);
  }

  auto on_progress = [&](const rbaa::SweepProgress& p) {
    std::string what;
    if (p.started >= 0) {
      what = "row " + std::to_string(p.started) + " started (" +
             overrides_text(grid.rows[p.started]) + (p.resumed ? "; resuming its checkpoint" : "") +
             ")";
    } else if (p.ended) {
      what = "row " + std::to_string(p.ended->index) + " " + rbaa::status_name(p.ended->status) +
             " in " + duration_text(p.ended->seconds);
      if (!p.ended->error.empty()) what += ": " + p.ended->error;
    }
    std::string eta = p.eta_seconds >= 0 ? duration_text(p.eta_seconds) : "?";
    if (p.done + p.failed == p.total) eta = "0.0 s";
    std::fprintf(stderr, "sweep: %s | %d/%d done%s, %d running, %d failed | ETA %s\n", what.c_str(),
                 p.done, p.total,
                 p.skipped ? (" (" + std::to_string(p.skipped) + " earlier)").c_str() : "",
                 p.running, p.failed, eta.c_str());
  };
  const rbaa::SweepSummary s = rbaa::run_sweep(grid, options, on_progress);
  std::fprintf(stderr, "sweep: %d %s: %d ok, %d skipped (finished earlier), %d failed, in %s%s\n",
               s.total, s.total == 1 ? "row" : "rows", s.ok, s.skipped, s.failed,
               duration_text(s.seconds).c_str(),
               FLAGS_row >= 0 ? "" : ("; " + out_dir + "/results.csv").c_str());
  return s.failed == 0 ? 0 : 1;
}

}  // namespace

RBAA_REGISTER_VERB(
    sweep,
    rbaa::cli::Verb{
        "sweep",
        "run a grid of attack/evaluate/simulate/study rows, here or on Slurm",
        "rbaa sweep --grid=FILE --out=DIR [--jobs=N] [--threads=T]\n"
        "       rbaa sweep --grid=FILE --out=DIR --emit=slurm [--jobs=N]\n"
        "       rbaa sweep --grid=FILE --out=DIR --row=K | --merge\n\n"
        "Runs one `rbaa VERB` per row of the grid (YAML: config, verb, set, flags, product of\n"
        "lists and/or explicit rows of --set overrides, report, slurm; README, \"Parameter\n"
        "sweeps\"), N rows at once, each in DIR/row-NNN with the verb's usual outputs, log.txt "
        "and\n"
        "sweep_row.json (status, one-line error). Each row gets OMP_NUM_THREADS = --threads, by\n"
        "default cores / N, and OPENBLAS_NUM_THREADS=1 unless set. DIR/results.csv has one line "
        "per\n"
        "row: the swept values, status, report.json's headline figures, seconds, error. Running "
        "again\n"
        "skips finished rows and re-runs failed ones (an attack row with a checkpoint.json\n"
        "goes on from it: --resume); a failed row does not stop the others.\n"
        "A row of other settings in DIR (the grid edited since, or for a finished row the\n"
        "config, a file it builds on or reads, or a file its values or flags name) is\n"
        "refused: use another --out. Exit code 0 when every row is ok, 1 when one failed,\n"
        "2 on bad input.\n"
        "--emit=slurm writes DIR/slurm/array.sbatch (one array task per row: "
        "--row=$SLURM_ARRAY_TASK_ID),\n"
        "merge.sbatch (--merge, after the array) and submit.sh, which submits both.",
        {"grid", "out", "jobs", "threads", "row", "merge", "emit"},
        run_sweep_verb});
