// rbaa gradcheck: the adjoint gradient of a scene's undirected trajectory term against central
// finite differences along random directions (SPEC section 3), per field or all together.

#include <gflags/gflags.h>

#include <cstdio>
#include <sstream>

#include "rbaa/cli/scene_flags.hpp"
#include "rbaa/cli/verb.hpp"
#include "rbaa/diff/gradient_check.hpp"
#include "rbaa/diff/trajectory_objective.hpp"
#include "rbaa/error.hpp"
#include "rbaa/io/materials_io.hpp"
#include "rbaa/scene/scene_mesh.hpp"
#include "rbaa/sim/barrier_stiffness.hpp"
#include "rbaa/sim/simulator.hpp"

DECLARE_string(materials);
DEFINE_string(fields, "", "design fields to check, comma separated from Y,nu,rho,alpha (default: the "
                          "scene's attack fields)");
DEFINE_int32(directions, 4, "number of random directions");
DEFINE_double(fd_step, 1e-2, "central-difference step along a unit direction (theta units; in material "
                             "space a fraction of each field's range), Richardson-extrapolated with step/2");
DEFINE_string(fd_space, "theta", "where the directions live: theta (the design vector) or material");
DECLARE_string(factor_storage);
DEFINE_double(gradcheck_tolerance, 1e-5, "largest relative error that passes");
DEFINE_uint64(gradcheck_seed, 1, "seed of the random directions");

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
  const rbaa::Scene scene = rbaa::cli::load_scene_from_flags();
  std::fprintf(stderr, "rbaa gradcheck: meshing the reference object of %s\n", scene.source.c_str());
  const rbaa::TetMesh mesh = rbaa::make_scene_mesh(scene);
  const double kappa = rbaa::scene_barrier_stiffness(scene, mesh);
  const rbaa::SimulationSettings settings = rbaa::simulation_settings(scene, kappa);
  const Eigen::VectorXd q0 =
      Eigen::Map<const Eigen::VectorXd>(mesh.V.data(), 3 * mesh.num_vertices());
  const Eigen::VectorXd v0 =
      rbaa::rigid_velocities(q0, scene.position, scene.velocity, scene.angular_velocity);

  // The undirected objective against the uniform reference's final positions.
  rbaa::Simulator reference(mesh,
                            rbaa::MaterialField::uniform(mesh.num_tets(), scene.reference_Y,
                                                         scene.reference_nu, scene.reference_rho),
                            settings, scene.source + " (reference material)");
  const rbaa::Trajectory ref = reference.run(q0, v0);
  auto objective =
      rbaa::UndirectedTrajectoryObjective::from_reference(mesh, scene.reference_rho, ref.q.back());

  rbaa::DesignSpaceOptions options = rbaa::DesignSpaceOptions::from_scene(scene);
  if (!FLAGS_fields.empty()) options.fields = parse_fields(FLAGS_fields);
  const rbaa::DesignSpace design(mesh, options);
  Eigen::VectorXd theta = design.initial_theta(true);
  if (!FLAGS_materials.empty()) {
    theta = design.to_theta(rbaa::read_materials(FLAGS_materials, mesh.num_tets()));
  }
  rbaa::TrajectoryGradientFunction f(mesh, settings, q0, v0, design, objective, storage);

  std::string names;
  for (rbaa::DesignField fld : options.fields) {
    names += std::string(names.empty() ? "" : ",") + rbaa::design_field_name(fld);
  }
  std::printf("gradcheck %s: %d tets, %d steps of %g s (%s), kappa %.4g, fields %s, %s space, "
              "step %g, factors %s\n",
              scene.name.c_str(), mesh.num_tets(), settings.num_steps, settings.time_step,
              settings.integrator == rbaa::Integrator::kBdf2 ? "BDF-2" : "BDF-1", kappa,
              names.c_str(), FLAGS_fd_space.c_str(), FLAGS_fd_step,
              rbaa::factor_storage_name(storage));
  std::fflush(stdout);

  rbaa::GradientCheckOptions check;
  check.directions = FLAGS_directions;
  check.step = FLAGS_fd_step;
  check.seed = FLAGS_gradcheck_seed;
  check.material_space = FLAGS_fd_space == "material";
  const rbaa::GradientCheckResult r = rbaa::check_gradient(
      f, theta, check, [&](int i, const rbaa::DirectionCheck& c) {
        std::printf("direction %2d: adjoint %+.10e  finite difference %+.10e  relative error %.3e\n",
                    i, c.adjoint, c.finite_difference, c.relative_error);
        std::fflush(stdout);
      });
  std::printf("objective %.10e, |gradient| %.4e, contact in %d of %d steps\n", r.value,
              r.gradient_norm, r.active_contact_steps, settings.num_steps);
  const bool pass = r.max_relative_error <= FLAGS_gradcheck_tolerance;
  std::printf("%s: max relative error %.3e (tolerance %.1e)\n", pass ? "PASS" : "FAIL",
              r.max_relative_error, FLAGS_gradcheck_tolerance);
  if (r.active_contact_steps == 0) {
    std::printf("note: no contact in this run; the check does not cover the barrier\n");
  }
  return pass ? 0 : 1;
}

std::vector<std::string> flags() {
  std::vector<std::string> f = rbaa::cli::scene_flag_names();
  f.insert(f.end(), {"fields", "directions", "fd_step", "fd_space", "factor_storage",
                     "gradcheck_tolerance", "gradcheck_seed", "materials"});
  return f;
}

}  // namespace

RBAA_REGISTER_VERB(gradcheck, rbaa::cli::Verb{
    "gradcheck", "check the adjoint gradient of a scene against finite differences",
    "rbaa gradcheck --config=FILE [--fields=Y,nu,rho,alpha] [--directions=N] [--set=...]\n\n"
    "Simulates the scene with the reference material (kappa frozen from it), builds the undirected\n"
    "trajectory objective -||q(T) - q_ref(T)||^2_Mref / (m0_ref L^2) and compares its adjoint\n"
    "gradient at the attack's perturbed starting design (or --materials) with Richardson-\n"
    "extrapolated central differences along random unit directions. Prints one line per direction\n"
    "and PASS or FAIL; exits non-zero on FAIL. Fast: --set='mesh.target_tets=300'.",
    flags(), run_gradcheck});
