#pragma once
// What every rbaa benchmark shares (a header, so it does not become a binary of its own): the
// paper's scenes loaded from configs/*.yaml, the BLAS/LAPACK libraries mapped into the process
// and the one CHOLMOD's calls resolve to (a slower BLAS must not pass a ratio), and a reporter that
// remembers every run's time so that main() can print ratios measured in the same run.

#include <benchmark/benchmark.h>

#include <dlfcn.h>
#include <limits.h>
#include <stdlib.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "rbaa/scene/scene.hpp"
#include "rbaa/sim/threads.hpp"
#include "rbaa/sim/trajectory.hpp"

namespace rbaa_bench {

/// The scenes a benchmark runs: --scenes=ball,star,bunny,cube (default: all four), each loaded
/// from <configs>/<scene>.yaml (--configs=DIR, default "configs", i.e. run from the repository
/// root). Both flags are removed from argv before Google Benchmark sees it.
struct Options {
  std::vector<std::string> scenes{"ball", "star", "bunny", "cube"};
  std::string configs = "configs";
  /// --cpu_time: summaries use CPU time instead of wall time. Meaningful with one thread
  /// (OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1), where it is immune to other processes' load.
  bool cpu_time = false;
  /// --set=key.path=value[;key.path=value...] (repeatable): config overrides for every scene, as
  /// `rbaa --set`, e.g. --set=newton.rigid_predictor=false to time the old Newton.
  std::vector<std::string> overrides;
};

inline std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

/// Also sets the threads as `rbaa` does (tune_threads_for_shared_cores: OpenMP dynamic teams,
/// OpenBLAS on 1 thread unless the environment says otherwise), so that a benchmark times what
/// the command line runs; without it CHOLMOD's teams spun in futex calls (bench_gradient on the
/// cube: system 20 s beside user 23 s).
inline Options parse_options(int& argc, char** argv, std::vector<std::string> default_scenes) {
  const std::string threads = rbaa::tune_threads_for_shared_cores();
  if (!threads.empty()) std::printf("threads as rbaa sets them: %s\n", threads.c_str());
  Options o;
  o.scenes = std::move(default_scenes);
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    if (!std::strncmp(argv[i], "--scenes=", 9)) {
      o.scenes = split_list(argv[i] + 9);
    } else if (!std::strncmp(argv[i], "--configs=", 10)) {
      o.configs = argv[i] + 10;
    } else if (!std::strncmp(argv[i], "--set=", 6)) {
      std::stringstream in(argv[i] + 6);
      for (std::string item; std::getline(in, item, ';');) {
        if (!item.empty()) o.overrides.push_back(item);
      }
    } else if (!std::strcmp(argv[i], "--cpu_time")) {
      o.cpu_time = true;
    } else {
      argv[kept++] = argv[i];
    }
  }
  argc = kept;
  return o;
}

inline rbaa::Scene load(const Options& o, const std::string& scene,
                        std::vector<std::string> overrides = {}) {
  overrides.insert(overrides.begin(), o.overrides.begin(), o.overrides.end());
  return rbaa::load_scene(o.configs + "/" + scene + ".yaml", overrides);
}

/// BLAS/LAPACK libraries mapped into this process, and the library each of CHOLMOD's BLAS and
/// LAPACK calls resolves to. Mapped is not called: until Ceres's link interface was trimmed
/// (CMakeLists.txt), ATLAS's libf77blas was mapped beside OpenBLAS and CHOLMOD's dgemm_ bound to
/// it. The lookup is the global scope's, which is where CHOLMOD's calls resolve (it is loaded at
/// start-up, without RTLD_DEEPBIND). A symbol that does not resolve to OpenBLAS's pthread or serial
/// build is flagged.
inline std::string loaded_blas() {
  std::ifstream maps("/proc/self/maps");
  std::set<std::string> libs;
  for (std::string line; std::getline(maps, line);) {
    const auto slash = line.find('/');
    if (slash == std::string::npos) continue;
    const std::string path = line.substr(slash);
    for (const char* key : {"blas", "atlas", "lapack", "mkl"}) {
      if (path.find(key) != std::string::npos) libs.insert(path);
    }
  }
  std::string out;
  for (const auto& l : libs) out += "  " + l + "\n";
  if (out.empty()) out = "  (none mapped)\n";
  out += "CHOLMOD's BLAS/LAPACK calls resolve to:\n";
  for (const char* symbol : {"dgemm_", "dsyrk_", "dtrsm_", "dpotrf_"}) {
    Dl_info info{};
    void* f = dlsym(RTLD_DEFAULT, symbol);
    std::string from = "(not found)";
    if (f && dladdr(f, &info) && info.dli_fname) {
      char resolved[PATH_MAX];
      from = realpath(info.dli_fname, resolved) ? resolved : info.dli_fname;
    }
    // OpenBLAS's OpenMP build is flagged too: rbaa leaves dynamic teams off under it and it
    // factorises 4-20x slower (benchmarks/README, "Which BLAS").
    const bool pthread_or_serial = from.find("openblas-pthread") != std::string::npos ||
                                   from.find("openblas-serial") != std::string::npos;
    out += "  " + std::string(symbol) + " " + from +
           (pthread_or_serial ? "" : "  <- NOT OpenBLAS's pthread or serial build") + "\n";
  }
  return out;
}

/// Console reporter that also keeps each run's real time (s; the minimum over repetitions: the
/// machine is shared and the fastest run is the least disturbed) and counters by run name. The
/// counters are the fastest repetition's too, so that a ratio of time to counters (bench_attack's
/// time per factorisation, say) divides numbers of one repetition: before, every repetition
/// overwrote them, and with --benchmark_repetitions=3 the fastest time met the last one's counters.
class RecordingReporter : public benchmark::ConsoleReporter {
 public:
  explicit RecordingReporter(bool cpu_time = false) : cpu_time_(cpu_time) {}

  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      double unit = 1e-9;
      if (r.time_unit == benchmark::kMicrosecond) unit = 1e-6;
      if (r.time_unit == benchmark::kMillisecond) unit = 1e-3;
      if (r.time_unit == benchmark::kSecond) unit = 1.0;
      const double t = (cpu_time_ ? r.GetAdjustedCPUTime() : r.GetAdjustedRealTime()) * unit;
      const std::string name = r.benchmark_name();
      auto it = seconds.find(name);
      if (it != seconds.end() && !(t < it->second)) continue;
      seconds[name] = t;
      std::map<std::string, double>& kept = counters[name];
      kept.clear();
      for (const auto& c : r.counters) kept[c.first] = c.second.value;
    }
    ConsoleReporter::ReportRuns(runs);
  }
  /// Time of the run whose name starts with `prefix` (0 when absent), aggregates left out.
  double time(const std::string& prefix) const {
    double best = 0;
    for (const auto& [name, s] : seconds) {
      if (name.rfind(prefix, 0) != 0) continue;
      if (name.find("_mean") != std::string::npos || name.find("_median") != std::string::npos ||
          name.find("_stddev") != std::string::npos || name.find("_cv") != std::string::npos) {
        continue;
      }
      if (best == 0 || s < best) best = s;
    }
    return best;
  }
  double counter(const std::string& prefix, const std::string& key) const {
    for (const auto& [name, c] : counters) {
      if (name.rfind(prefix, 0) == 0 && c.count(key)) return c.at(key);
    }
    return 0;
  }

  std::map<std::string, double> seconds;
  std::map<std::string, std::map<std::string, double>> counters;

 private:
  bool cpu_time_ = false;
};

// Where the forward run's time went, as counters (seconds per run).
inline void newton_counters(benchmark::State& state, const rbaa::Trajectory& t) {
  double grad = 0, assembly = 0, factor = 0, solve = 0, search = 0, total = 0;
  int iterations = 0, fallbacks = 0;
  for (const rbaa::StepStats& s : t.steps) {
    grad += s.gradient_seconds;
    assembly += s.assembly_seconds;
    factor += s.factorization_seconds;
    solve += s.solve_seconds;
    search += s.line_search_seconds;
    total += s.seconds;
    iterations += s.newton_iterations;
    fallbacks += s.projected_fallbacks;
  }
  state.counters["newton_its"] = iterations;
  state.counters["fallbacks"] = fallbacks;
  state.counters["grad_s"] = grad;
  state.counters["assembly_s"] = assembly;
  state.counters["factor_s"] = factor;
  state.counters["solve_s"] = solve;
  state.counters["search_s"] = search;
  state.counters["other_s"] = total - grad - assembly - factor - solve - search;
}

}  // namespace rbaa_bench
