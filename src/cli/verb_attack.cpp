// rbaa attack: build an adversarial object for a scene.

#include <gflags/gflags.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "rbaa/cli/scene_flags.hpp"
#include "rbaa/cli/verb.hpp"
#include "rbaa/error.hpp"
#include "rbaa/opt/attack.hpp"
#include "rbaa/opt/iteration_eta.hpp"
#include "rbaa/scene/scene_fingerprint.hpp"

DEFINE_int32(iterations, -1, "Adam iterations (-1: the config's attack.iterations); a resumed run may extend it");
DEFINE_bool(resume, false, "continue from OUT/checkpoint.json (written after every iteration)");
DECLARE_string(factor_storage);
DECLARE_string(out);
DECLARE_string(config);

namespace {

std::string duration_text(double s) {
  std::ostringstream out;
  if (s >= 3600) out << static_cast<int>(s / 3600) << "h" << std::setw(2) << std::setfill('0') << static_cast<int>(std::fmod(s, 3600) / 60) << "m";
  else if (s >= 60) out << static_cast<int>(s / 60) << "m" << std::setw(2) << std::setfill('0') << static_cast<int>(std::fmod(s, 60)) << "s";
  else out << std::fixed << std::setprecision(1) << s << "s";
  return out.str();
}

int run_attack_verb() {
  if (FLAGS_out.empty()) throw rbaa::InputError("--out is required");
  rbaa::Scene scene = rbaa::cli::load_scene_from_flags();
  if (FLAGS_iterations < -1) {
    throw rbaa::InputError("--iterations=" + std::to_string(FLAGS_iterations) +
                           ": expected a whole number >= 0 (-1: the config's attack.iterations)");
  }
  if (FLAGS_iterations >= 0) scene.iterations = FLAGS_iterations;
  rbaa::AttackOptions options;
  options.out_dir = FLAGS_out;
  options.resume = FLAGS_resume;
  options.storage = rbaa::parse_factor_storage(FLAGS_factor_storage);
  // The parsed settings that change the result, not the config's bytes (scene_fingerprint.hpp).
  options.fingerprint = rbaa::scene_fingerprint(scene);
  // The output folder must be writable before hours of work go into it.
  {
    std::error_code ec;
    std::filesystem::create_directories(FLAGS_out, ec);
    const std::string probe = FLAGS_out + "/.rbaa_write_probe";
    if (ec || !std::ofstream(probe)) throw rbaa::InputError(FLAGS_out + ": output folder is not writable");
    std::filesystem::remove(probe);
  }
  // The iterations' own times: the work before the loop (the best uniform start's runs) is not
  // iteration time.
  rbaa::IterationEta eta;
  options.on_stage = [](const std::string& s) { std::cerr << "rbaa attack: " << s << std::endl; };
  options.on_iteration = [&](const rbaa::ProgressRow& row, int total) {
    eta.add(row, total);
    std::fprintf(stderr,
                 "iter %4d/%d  objective %+.6e  gap %.4e m  com gap %.4e m  moment residual %.2e  "
                 "grey %.3f  components %d  %6.2f s/iter  ETA %s\n",
                 row.iteration + 1, total, row.objective, row.gap, row.com_gap,
                 row.max_moment_residual, row.grey_fraction, row.components, row.seconds,
                 duration_text(eta.seconds_left()).c_str());
  };
  const rbaa::AttackResult result = rbaa::run_attack(scene, options);
  rbaa::write_attack_outputs(result, scene, FLAGS_out);
  std::fprintf(stderr,
               "rbaa attack: gap %.4e m -> %.4e m (continuous) -> %.4e m (final object); max moment residual %.2e; "
               "void fraction %.3f; %s -> %s/report.json\n",
               result.gap_initial, result.gap_continuous, result.gap_final, result.max_normalized_residual,
               result.post.void_fraction, duration_text(result.total_seconds).c_str(), FLAGS_out.c_str());
  const rbaa::RefinementCheck& c = result.refinement;
  if (c.measured) {
    std::fprintf(stderr,
                 "rbaa attack: at h / %d = %.3g s the final object's gap is %.4e m (%.0f %% of %.4e m at "
                 "the attack's step; the reference itself moved %.3e m)\n",
                 c.factor, c.time_step, c.gap, 100.0 * c.gap / std::max(c.gap_at_attack_step, 1e-300),
                 c.gap_at_attack_step, c.reference_com_shift);
  }
  return 0;
}

std::vector<std::string> flags() {
  std::vector<std::string> f = rbaa::cli::scene_flag_names();
  for (const char* name : {"out", "iterations", "resume", "factor_storage"}) f.push_back(name);
  return f;
}

}  // namespace

RBAA_REGISTER_VERB(
    attack,
    rbaa::cli::Verb{
        "attack",
        "build an adversarial object for a scene (forward + adjoint, Adam, post-processing)",
        "rbaa attack --config=FILE --out=DIR [--iterations=N] [--resume] "
        "[--factor_storage=store|rebuild]\n\n"
        "Minimises C = -|q_adv(T) - q_ref(T)|^2_Mref / (m0 L^2) + beta |r|^2 over per-element Y, "
        "nu,\n"
        "rho and alpha (the config's attack.fields) with Adam; the config's objective key replaces "
        "the\n"
        "first term (kind target: a body's final centre of mass towards a value; away: away from "
        "the\n"
        "reference run's; on any body, README). In a scene with bodies the attacked body "
        "(attack.body,\n"
        "default the object) is designed among them: they keep their materials, its moments alone "
        "are\n"
        "matched. It then rounds the occupancy, joins the occupied elements into one body, "
        "re-fits\n"
        "densities to the reference moments (1e-10) and re-simulates the final object; with\n"
        "attack.polish_iterations = N > 0 it then runs N Adam iterations on Y, nu, rho of that "
        "solid\n"
        "object (occupancy fixed) and keeps the result if its gap is larger (with an objective "
        "key: if\n"
        "its objective is lower; never if its re-fit or simulation fails: report.json "
        "polish.failed).\n"
        "Last, the reference and the final object are re-simulated at the attack's step divided "
        "by\n"
        "attack.refinement_factor (default 2; 0 turns it off): report.json refinement.gap beside\n"
        "refinement.gap_at_attack_step says whether the gap belongs to the object or to the step.\n"
        "With attack.start: best_uniform (default: given, the config's attack.Y0 and nu0) it "
        "first\n"
        "simulates the attacked body uniform at Y, nu at the ends and middle of their ranges (3 x "
        "3,\n"
        "rho the reference's), starts from the one with the best objective (undirected: the "
        "largest\n"
        "gap) and keeps the loop's best design if its last is worse: report.json start.* and\n"
        "loop.kept_iteration.\n"
        "With attack.occupancy_penalty.repair_in_loop (on in configs/ball.yaml and "
        "ball_accurate.yaml)\n"
        "the elements the connectivity repair would fill are filled after every Adam step (moments\n"
        "retracted), so rounding keeps the gap; its weight and connectivity_weight add a greyness "
        "and a\n"
        "repair-set penalty instead (README, \"Keeping the gap through rounding\"); progress.csv "
        "reports\n"
        "the penalty, components and grey fraction.\n"
        "Progress goes to stderr and DIR/progress.csv (polish: DIR/polish_progress.csv);\n"
        "DIR/checkpoint.json (polish_checkpoint.json) is written atomically after every iteration\n"
        "(--resume continues from it if the parsed settings that change the result are the same:\n"
        "comments, key order, evaluation.*, attack.iterations, attack.polish_iterations and\n"
        "newton.max_iterations may differ; a mesh file counts by its content; the polish's also\n"
        "names the object it started from, and one of another object is started over). Writes\n"
        "DIR/adversarial.msh and .vtu (final object, element data Y, nu, rho, alpha), "
        "DIR/continuous.msh\n"
        "and DIR/report.json. A simulation that fails mid-run (Newton, or a non-finite objective "
        "or\n"
        "gradient) stops the loop at the last design\n"
        "that simulated; the failing one is kept in DIR/failed_design.msh (rbaa simulate "
        "--materials).\n"
        "DIR/continuous.msh is written before post-processing, so a failed density re-fit loses "
        "nothing.",
        flags(), run_attack_verb});
