// rbaa gradcheck: the adjoint gradient of a scene's undirected trajectory term along random
// directions, against central finite differences (SPEC section 3) or tangent-linear
// sensitivities (exact to round-off on any scene), per field or all together.

#include <gflags/gflags.h>

#include <cstdio>
#include <sstream>

#include "rbaa/cli/scene_flags.hpp"
#include "rbaa/cli/verb.hpp"
#include "rbaa/diff/gradient_check.hpp"
#include "rbaa/error.hpp"
#include "rbaa/io/materials_io.hpp"
#include "rbaa/opt/attack_problem.hpp"

DECLARE_string(materials);
DEFINE_string(fields, "", "design fields to check, comma separated from Y,nu,rho,alpha (default: the "
                          "scene's attack fields)");
DEFINE_int32(directions, 4, "number of random directions");
DEFINE_double(fd_step, 1e-2, "central-difference step along a unit direction (theta units; in material "
                             "space a fraction of each field's range), Richardson-extrapolated with step/2");
DEFINE_string(fd_space, "theta", "where the directions live: theta (the design vector) or material");
DECLARE_string(factor_storage);
DEFINE_double(gradcheck_tolerance, 1e-5, "largest finite-difference relative error that passes");
DEFINE_string(method, "fd", "fd (central finite differences), tangent (tangent-linear sensitivities "
                            "through the same linearisation as the adjoint) or both");
DEFINE_double(tangent_tolerance, 1e-10, "largest tangent-vs-adjoint relative error that passes");
DEFINE_double(tangent_noise_factor, 4.0, "a tangent-vs-adjoint error within this many times the "
                                         "tangent's own measured round-off also passes (0: off)");
DEFINE_uint64(gradcheck_seed, 1, "seed of the random directions");
DEFINE_string(body, "",
              "the attacked body, whose elements alone are the design (every other "
              "body keeps its material): object, or a name from the scene's bodies "
              "list (default: the config's attack.body, object)");

namespace {

std::vector<rbaa::DesignField> parse_fields(const std::string& list) {
  std::vector<rbaa::DesignField> fields;
  std::stringstream ss(list);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (item.empty()) continue;
    const rbaa::DesignField f = rbaa::parse_design_field(item);
    for (rbaa::DesignField g : fields) {
      if (g == f) throw rbaa::InputError("--fields names " + item + " twice");
    }
    fields.push_back(f);
  }
  if (fields.empty()) throw rbaa::InputError("--fields is empty");
  return fields;
}

int run_gradcheck() {
  if (FLAGS_directions < 1) throw rbaa::InputError("--directions must be >= 1");
  if (!(FLAGS_fd_step > 0)) throw rbaa::InputError("--fd_step must be positive");
  if (FLAGS_fd_space != "theta" && FLAGS_fd_space != "material") {
    throw rbaa::InputError("--fd_space must be theta or material, not " + FLAGS_fd_space);
  }
  const rbaa::FactorStorage storage = rbaa::parse_factor_storage(FLAGS_factor_storage);
  const rbaa::GradientCheckMethod method = rbaa::parse_gradient_check_method(FLAGS_method);
  const rbaa::Scene scene = rbaa::cli::load_scene_from_flags();
  std::fprintf(stderr, "rbaa gradcheck: meshing the reference object of %s\n", scene.source.c_str());
  // The scene's attack problem: its objective (default: the attacked body's undirected term),
  // the design on the attacked body (--body, default attack.body), every other body fixed.
  rbaa::AttackProblemOptions problem_options;
  problem_options.attacked_body = FLAGS_body;
  if (!FLAGS_fields.empty()) problem_options.fields = parse_fields(FLAGS_fields);
  problem_options.with_gradient = false;  // built below, after --materials
  rbaa::AttackProblem problem = rbaa::build_attack_problem(scene, problem_options);
  const rbaa::TetMesh& mesh = problem.world.mesh;
  const rbaa::SimulationSettings& settings = problem.settings;
  const double kappa = problem.kappa;
  rbaa::DesignSpace& design = *problem.design;
  const rbaa::DesignSpaceOptions& options = design.options();
  Eigen::VectorXd theta = design.initial_theta(true);
  if (!FLAGS_materials.empty()) {
    // Every field of the given design, checked or not, keeps its values.
    const rbaa::MaterialField given = problem.world_materials(
        rbaa::read_materials(FLAGS_materials, problem.body_mesh), FLAGS_materials);
    design.hold_fixed_fields(given);
    theta = design.to_theta(given);
  }
  const std::unique_ptr<rbaa::TrajectoryGradientFunction> gradient = problem.make_gradient(storage);
  rbaa::TrajectoryGradientFunction& f = *gradient;

  std::string names;
  for (rbaa::DesignField fld : options.fields) {
    names += std::string(names.empty() ? "" : ",") + rbaa::design_field_name(fld);
  }
  std::printf("gradcheck %s: %d tets, %d steps of %g s (%s), kappa %.4g, fields %s, %s space, "
              "method %s, step %g, factors %s\n",
              scene.name.c_str(), mesh.num_tets(), settings.num_steps, settings.time_step,
              settings.integrator == rbaa::Integrator::kBdf2 ? "BDF-2" : "BDF-1", kappa,
              names.c_str(), FLAGS_fd_space.c_str(), rbaa::gradient_check_method_name(method),
              FLAGS_fd_step, rbaa::factor_storage_name(storage));
  if (problem.several_bodies() || scene.objective.kind != rbaa::ObjectiveSpec::Kind::kUndirected) {
    std::printf("design on body %s (%d of %d tets), objective %s on body %s\n",
                problem.body().name.c_str(), problem.body().num_elements(), mesh.num_tets(),
                rbaa::objective_kind_name(scene.objective.kind),
                problem.world.bodies[problem.scored].name.c_str());
  }
  std::fflush(stdout);

  rbaa::GradientCheckOptions check;
  check.method = method;
  check.directions = FLAGS_directions;
  check.step = FLAGS_fd_step;
  check.seed = FLAGS_gradcheck_seed;
  check.material_space = FLAGS_fd_space == "material";
  check.fd_tolerance = FLAGS_gradcheck_tolerance;
  check.tangent_tolerance = FLAGS_tangent_tolerance;
  check.tangent_noise_factor = FLAGS_tangent_noise_factor;
  if (!(FLAGS_tangent_noise_factor >= 0)) throw rbaa::InputError("--tangent_noise_factor must be >= 0");
  const bool fd = method != rbaa::GradientCheckMethod::kTangent;
  const bool tangent = method != rbaa::GradientCheckMethod::kFiniteDifference;
  const rbaa::GradientCheckResult r = rbaa::check_gradient(
      f, theta, check, [&](int i, const rbaa::DirectionCheck& c) {
        if (tangent) {
          std::printf("direction %2d: adjoint %+.10e  tangent %+.10e  relative error %.3e  "
                      "(pointwise %.3e, tangent round-off %.1e)\n",
                      i, c.adjoint, c.tangent, c.tangent_relative_error, c.tangent_pointwise_error,
                      c.tangent_noise);
        }
        if (fd) {
          std::printf("direction %2d: adjoint %+.10e  finite difference %+.10e  relative error %.3e",
                      i, c.adjoint, c.finite_difference, c.relative_error);
          if (c.relative_error > FLAGS_gradcheck_tolerance) {
            std::printf("  (at 4x the step %+.10e, relative error %.3e: %s)",
                        c.coarse_finite_difference, c.coarse_relative_error,
                        c.noise_dominated ? "noise-dominated" : "not noise");
          }
          std::printf("\n");
        }
        std::fflush(stdout);
      });
  std::printf("objective %.10e, |gradient| %.4e, contact in %d of %d steps\n", r.value,
              r.gradient_norm, r.active_contact_steps, settings.num_steps);
  bool pass = true;
  int status = 0;
  if (tangent) {
    const bool ok = r.tangent_pass;
    std::printf("%s: max relative error %.3e (tolerance %.1e or %gx the tangent's own round-off, "
                "at most %.1e; tangent; %.2f s)\n",
                ok ? "PASS" : "FAIL", r.max_tangent_relative_error, FLAGS_tangent_tolerance,
                FLAGS_tangent_noise_factor, r.max_tangent_noise, r.tangent_seconds);
    pass = pass && ok;
  }
  if (fd) {
    const bool ok = r.max_relative_error <= FLAGS_gradcheck_tolerance;
    if (ok || !r.fd_noise_dominated) {
      std::printf("%s: max relative error %.3e (tolerance %.1e%s)\n", ok ? "PASS" : "FAIL",
                  r.max_relative_error, FLAGS_gradcheck_tolerance,
                  tangent ? ", finite differences" : "");
      pass = pass && ok;
    } else {
      // Not a verdict on the gradient: the objective moves less than Newton's noise allows.
      std::printf("INCONCLUSIVE: max relative error %.3e (tolerance %.1e%s) is finite-difference "
                  "noise: the estimates at the step and at 4x the step differ as much; use --method=tangent\n",
                  r.max_relative_error, FLAGS_gradcheck_tolerance,
                  tangent ? ", finite differences" : "");
      if (status == 0) status = 2;
    }
  }
  if (r.active_contact_steps == 0) {
    std::printf("note: no contact in this run; the check does not cover the barrier\n");
  }
  if (!pass) return 1;
  return status;
}

std::vector<std::string> flags() {
  std::vector<std::string> f = rbaa::cli::scene_flag_names();
  f.insert(f.end(), {"fields", "directions", "fd_step", "fd_space", "factor_storage",
                     "gradcheck_tolerance", "gradcheck_seed", "materials", "method",
                     "tangent_tolerance", "tangent_noise_factor", "body"});
  return f;
}

}  // namespace

RBAA_REGISTER_VERB(
    gradcheck,
    rbaa::cli::Verb{
        "gradcheck", "check the adjoint gradient of a scene (finite differences, tangent-linear)",
        "rbaa gradcheck --config=FILE [--method=fd|tangent|both] [--fields=Y,nu,rho,alpha]\n"
        "               [--directions=N] [--materials=FILE] [--body=NAME] [--set=...]\n\n"
        "Builds the scene's attack problem as rbaa attack does: simulates the scene with the "
        "reference\n"
        "material (kappa frozen from it), builds the config's objective (default: the undirected\n"
        "trajectory term -||q(T) - q_ref(T)||^2_Mref / (m0_ref L^2) of the attacked body; "
        "objective:\n"
        "{body, kind: target|away, ...} scores any body, README) with the design on the attacked "
        "body\n"
        "(--body, default attack.body; the other bodies keep their materials), and compares the\n"
        "adjoint gradient at the attack's perturbed starting design (or every field of "
        "--materials,\n"
        "the attacked body's) along random unit directions with\n"
        "  fd:      Richardson-extrapolated central differences (PASS at --gradcheck_tolerance). "
        "On\n"
        "           stiff scenes Y and nu move the objective by ~1e-7 relative, the size of "
        "Newton's\n"
        "           noise: a failing direction is re-measured at 4x the step, and when the "
        "adjoint\n"
        "           lies within twice the two estimates' difference for every failing direction "
        "the\n"
        "           verdict is INCONCLUSIVE (exit 2), not FAIL;\n"
        "  tangent: forward-mode sensitivities through the same converged per-step linearisation\n"
        "           (exact Hessians factorised afresh, BDF and start-up history, contact), which "
        "must\n"
        "           agree with the adjoint to round-off on any scene (PASS at --tangent_tolerance "
        "on\n"
        "           the dot-product test's normwise error |tangent - adjoint| / max(|gradient| "
        "|d|,\n"
        "           sum_k |dC/dq_k| |dq_k|), or within --tangent_noise_factor times the tangent's "
        "own\n"
        "           round-off measured by splitting d into two random parts, if larger (the "
        "cube's\n"
        "           150 stiff steps reach 1e-9); the pointwise error, relative to\n"
        "           the derivative itself, is printed beside it);\n"
        "  both:    the two.\n"
        "Prints one line per direction and method and a PASS/FAIL line per method; exits 1 on "
        "FAIL.\n"
        "Fast: --set='mesh.target_tets=300'.",
        flags(), run_gradcheck});
