#include "rbaa/sweep/sweep_runner.hpp"

#include <sys/wait.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <deque>
#include <filesystem>
#include <map>
#include <set>
#include <stdexcept>

#include "rbaa/error.hpp"
#include "rbaa/sweep/sweep_results.hpp"

namespace rbaa {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double seconds_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

}  // namespace

std::vector<std::string> row_process_arguments(const SweepGrid& grid,
                                               const std::vector<std::string>& arguments,
                                               const std::string& row_dir) {
  std::vector<std::string> argv = arguments;
  const bool own_resume = std::any_of(grid.flags.begin(), grid.flags.end(),
                                      [](const SweepFlag& f) { return f.name == "resume"; });
  // The name rbaa attack writes after every iteration (attack.cpp, attack_loop_options); it
  // refuses a checkpoint of other settings itself, naming both fingerprints.
  if (grid.verb == "attack" && !own_resume && fs::exists(fs::path(row_dir) / "checkpoint.json")) {
    argv.push_back("--resume");
  }
  return argv;
}

SweepSummary run_sweep(const SweepGrid& grid, const SweepOptions& options,
                       const std::function<void(const SweepProgress&)>& on_progress) {
  const auto start = Clock::now();
  if (options.only_row >= static_cast<int>(grid.rows.size())) {
    throw InputError("--row=" + std::to_string(options.only_row) + ": " + grid.source + " has " +
                     std::to_string(grid.rows.size()) + " rows (0 to " +
                     std::to_string(grid.rows.size() - 1) + ")");
  }
  std::error_code ec;
  fs::create_directories(options.out_dir, ec);
  if (ec)
    throw InputError(options.out_dir + ": cannot create the sweep's folder (" + ec.message() + ")");

  std::vector<RowOutcome> outcomes = read_sweep_outcomes(grid, options.out_dir);
  const bool whole = options.only_row < 0;
  SweepSummary summary;
  SweepProgress progress;
  std::deque<int> queue;
  for (const SweepRow& row : grid.rows) {
    if (!whole && row.index != options.only_row) continue;
    ++summary.total;
    if (outcomes[row.index].status == RowStatus::kOk) {
      ++summary.skipped;
    } else {
      queue.push_back(row.index);
    }
  }
  progress.total = summary.total;
  progress.skipped = progress.done = summary.skipped;

  std::map<int, std::pair<int, Clock::time_point>> running;  // pid -> (row, start)
  std::set<int> resumed;                                     // rows given --resume here
  double finished_seconds = 0;
  int finished_here = 0;
  auto report = [&](const RowOutcome* ended, int started) {
    progress.running = static_cast<int>(running.size());
    progress.ended = ended;
    progress.started = started;
    if (finished_here > 0) {
      const double mean = finished_seconds / finished_here;
      const int left = static_cast<int>(queue.size() + running.size());
      progress.eta_seconds = mean * std::ceil(static_cast<double>(left) / options.split.jobs);
    }
    if (on_progress) on_progress(progress);
  };
  if (whole) write_sweep_results(grid, options.out_dir, outcomes);

  while (!queue.empty() || !running.empty()) {
    while (!queue.empty() && static_cast<int>(running.size()) < options.split.jobs) {
      const int index = queue.front();
      queue.pop_front();
      const std::string dir = (fs::path(options.out_dir) / row_folder_name(index)).string();
      RowOutcome& o = outcomes[index];
      o.status = RowStatus::kRunning;
      o.arguments = row_arguments(grid, grid.rows[index]);
      o.error.clear();
      o.exit_code = 0;
      o.seconds = 0;
      write_row_outcome(dir, o);
      const auto argv = row_process_arguments(grid, o.arguments, dir);
      const int pid = start_row_process(options.executable, argv, dir, options.split.threads);
      running[pid] = {index, Clock::now()};
      progress.resumed = argv.size() > o.arguments.size();
      if (progress.resumed) resumed.insert(index);
      report(nullptr, index);
      progress.resumed = false;
    }
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(std::string("waitpid: ") + std::strerror(errno));
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;  // not one of ours
    const int index = it->second.first;
    const double seconds = seconds_between(it->second.second, Clock::now());
    running.erase(it);
    const std::string dir = (fs::path(options.out_dir) / row_folder_name(index)).string();
    RowOutcome& o = outcomes[index];
    o.seconds = seconds;
    o.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
      o.status = RowStatus::kOk;
      ++summary.ok;
      ++progress.done;
    } else {
      o.status = RowStatus::kFailed;
      o.error = row_error(dir, status);
      // The --resume was the sweep's, not the user's: the attack's advice to drop it (a
      // checkpoint of another scene, the config edited since) cannot be followed here.
      if (resumed.count(index)) {
        o.error +=
            " (the sweep resumed the row's checkpoint.json: remove it to start the row over)";
      }
      ++summary.failed;
      ++progress.failed;
    }
    write_row_outcome(dir, o);
    finished_seconds += seconds;
    ++finished_here;
    if (whole) write_sweep_results(grid, options.out_dir, outcomes);
    report(&o, -1);
  }
  summary.seconds = seconds_between(start, Clock::now());
  return summary;
}

}  // namespace rbaa
