// rbaa study: the speed/accuracy trade-off around a scene's config (SPEC section 10), and
// whether an adversarial object's gap survives refinement.

#include <gflags/gflags.h>

#include <cstdio>
#include <sstream>

#include "rbaa/cli/scene_flags.hpp"
#include "rbaa/cli/verb.hpp"
#include "rbaa/error.hpp"
#include "rbaa/study/trade_off_study.hpp"

DECLARE_string(out);
DECLARE_string(adversarial);
DEFINE_bool(full, false, "study: the full sweep (h down to 1e-4, meshes up to 4x, one more Newton "
                         "tolerance); the default sweep fits in 30 minutes on 2 cores");
DEFINE_double(memory_budget_gb, 8.0, "study: stored factorisations past this size (GB) are rebuilt "
                                     "in the backward pass instead");
DEFINE_int32(reference_divisor, 16, "study: the reference in time runs at h / this");
DEFINE_string(time_steps, "",
              "study: comma-separated time steps (s) instead of the default sweep, each rounded "
              "to T / n, n whole, and from 1e-4 to 1/30 s as given and as rounded");
DEFINE_string(mesh_factors, "", "study: comma-separated multiples of the config's tet count instead "
                                "of the default sweep (the largest is the reference in space; each "
                                "at least 50 tets)");
DEFINE_string(newton_tolerances, "", "study: comma-separated Newton tolerances instead of the default sweep");

namespace {

std::vector<double> parse_list(const std::string& text, const char* flag) {
  std::vector<double> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    if (item.empty()) continue;
    try {
      std::size_t used = 0;
      const double v = std::stod(item, &used);
      if (used != item.size() || !(v > 0)) throw std::invalid_argument(item);
      out.push_back(v);
    } catch (const std::logic_error&) {
      throw rbaa::InputError(std::string("--") + flag + ": '" + item + "' is not a positive number");
    }
  }
  return out;
}

int run_study_verb() {
  if (FLAGS_out.empty()) throw rbaa::InputError("--out is required");
  if (!(FLAGS_memory_budget_gb > 0)) throw rbaa::InputError("--memory_budget_gb must be positive");
  if (FLAGS_reference_divisor < 2) throw rbaa::InputError("--reference_divisor must be >= 2");
  const rbaa::Scene scene = rbaa::cli::load_scene_from_flags();
  rbaa::StudyOptions options;
  options.full = FLAGS_full;
  options.memory_budget_bytes = static_cast<std::size_t>(FLAGS_memory_budget_gb * 1e9);
  options.reference_time_divisor = FLAGS_reference_divisor;
  options.time_steps = parse_list(FLAGS_time_steps, "time_steps");
  options.mesh_factors = parse_list(FLAGS_mesh_factors, "mesh_factors");
  options.newton_tolerances = parse_list(FLAGS_newton_tolerances, "newton_tolerances");
  options.adversarial_file = FLAGS_adversarial;
  options.on_progress = [](const std::string& m) { std::fprintf(stderr, "rbaa study: %s\n", m.c_str()); };
  const rbaa::StudyResult result = rbaa::run_study(scene, options);
  rbaa::write_study_outputs(result, FLAGS_out);
  std::fprintf(stderr, "rbaa study: %zu points in %.1f s; %s/study.md, study.csv, pareto.png\n",
               result.points.size(), result.total_seconds, FLAGS_out.c_str());
  return 0;
}

std::vector<std::string> flags() {
  std::vector<std::string> f = rbaa::cli::scene_flag_names();
  f.insert(f.end(), {"out", "full", "adversarial", "memory_budget_gb", "reference_divisor",
                     "time_steps", "mesh_factors", "newton_tolerances"});
  return f;
}

}  // namespace

RBAA_REGISTER_VERB(study, rbaa::cli::Verb{
    "study", "measure speed against accuracy around a scene's config",
    "rbaa study --config=FILE --out=DIR [--full] [--adversarial=FILE]\n\n"
    "Sweeps one factor at a time around the config (time step, mesh resolution, integrator,\n"
    "mass matrix, Newton tolerance, factor storage) and measures the wall time of a forward run\n"
    "and of a gradient, and the accuracy against a fine reference (the config mesh at h/16 in\n"
    "time, 16 being --reference_divisor; the finest mesh at the config's h in space):\n"
    "centre-of-mass and orientation error at T and the cosine of the gradient with the\n"
    "reference gradient. With --adversarial, also the adversarial object's gap at h, h/4,\n"
    "h / --reference_divisor and on a finer mesh. Writes DIR/study.csv, DIR/study.md,\n"
    "DIR/pareto.gp + pareto.png and DIR/survival.csv.",
    flags(), run_study_verb});
