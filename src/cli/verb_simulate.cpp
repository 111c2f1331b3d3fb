// rbaa simulate: the deformable forward simulation of a scene, with outputs for inspection.

#include <gflags/gflags.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <utility>

#include "rbaa/cli/scene_flags.hpp"
#include "rbaa/cli/verb.hpp"
#include "rbaa/error.hpp"
#include "rbaa/io/materials_io.hpp"
#include "rbaa/scene/scene_mesh.hpp"
#include "rbaa/scene/simulate.hpp"

DECLARE_string(materials);
DECLARE_string(out);  // here: the output directory
DEFINE_int32(vtu_every, 1, "write every k-th step as .vtu for ParaView (0: none)");
DEFINE_bool(progress, true, "print one line per step on stderr");
DEFINE_bool(newton_log, false,
            "print one line per Newton iteration on stderr (Hessian kind, step velocity, CCD and "
            "line-search fractions, energy change): for a step that does not converge");

namespace {

int run_simulate() {
  if (FLAGS_out.empty()) throw rbaa::InputError("--out is required");
  if (FLAGS_vtu_every < 0) throw rbaa::InputError("--vtu_every must be >= 0");
  const rbaa::Scene scene = rbaa::cli::load_scene_from_flags();
  rbaa::TetMesh mesh = rbaa::make_scene_mesh(scene);
  rbaa::MaterialField materials = rbaa::MaterialField::uniform(
      mesh.num_tets(), scene.reference_Y, scene.reference_nu, scene.reference_rho);
  if (!FLAGS_materials.empty()) {
    materials = rbaa::read_materials(FLAGS_materials, mesh);
    mesh = rbaa::place_centre_of_mass(scene, std::move(mesh), materials.effective_density(),
                                      FLAGS_materials);
  }

  rbaa::SimulationOptions options;
  if (FLAGS_progress) {
    options.on_step = [&](int step, const Eigen::VectorXd&, const rbaa::StepStats& s) {
      std::fprintf(stderr, "step %4d  t %.4f s  newton %3d  d_min %.3e m  %.3f s\n", step,
                   step * scene.time_step, s.newton_iterations, s.min_distance, s.seconds);
    };
  }
  if (FLAGS_newton_log) {
    options.on_newton_iteration = [](const std::string& context, const rbaa::NewtonIteration& it) {
      std::fprintf(stderr,
                   "  %s  it %3d  %s  v %.3e m/s  ccd %.3g  alpha %.3g  dE %.3e  g.dq %.3e  dof %ld\n",
                   context.c_str(), it.iteration, it.exact_hessian ? "exact    " : "projected",
                   it.step_velocity, it.max_step_fraction, it.step_fraction, it.energy_change,
                   it.directional_derivative, static_cast<long>(it.largest_dof));
    };
  }
  const rbaa::SimulationRun run = rbaa::run_simulation(scene, mesh, materials, options);
  rbaa::OutputOptions out;
  out.vtu_every = FLAGS_vtu_every;
  rbaa::write_simulation_outputs(run, scene, FLAGS_out, out);
  std::fprintf(stderr, "%d steps in %.2f s (kappa %.4g%s); outputs in %s\n",
               run.trajectory.num_steps(), run.simulate_seconds, run.settings.kappa,
               run.kappa_from_rule ? ", energy rule" : "", FLAGS_out.c_str());
  int floor_steps = 0;
  double floor_velocity = 0;
  for (const rbaa::StepStats& s : run.trajectory.steps) {
    if (!s.roundoff_limited) continue;
    ++floor_steps;
    floor_velocity = std::max(floor_velocity, s.floor_velocity);
  }
  if (floor_steps > 0) {
    std::fprintf(stderr,
                 "note: Newton stopped in %d steps at its round-off floor (no progress for 10 "
                 "iterations; slowest step up to %.3g m/s) above newton.tolerance = %g x the "
                 "bounding-box diagonal per s: that tolerance is below what double precision "
                 "resolves there\n",
                 floor_steps, floor_velocity, run.settings.newton_tolerance);
  }
  for (const rbaa::Bounce& b : run.bounces) {
    const double t = b.first_step * scene.time_step;
    if (b.kind == rbaa::BounceKind::kBounce) {
      std::fprintf(stderr, "bounce on plane %d at t %.3f s: restitution %.3f\n", b.planes[0], t,
                   b.restitution);
    } else {
      std::fprintf(stderr, "%s contact at t %.3f s: no restitution: %s\n",
                   rbaa::bounce_kind_name(b.kind), t, b.note.c_str());
    }
  }
  return 0;
}

std::vector<std::string> flags() {
  std::vector<std::string> f = rbaa::cli::scene_flag_names();
  f.insert(f.end(), {"materials", "out", "vtu_every", "progress", "newton_log"});
  return f;
}

}  // namespace

RBAA_REGISTER_VERB(simulate, rbaa::cli::Verb{
    "simulate", "run the deformable (FEM) simulation of a scene",
    "rbaa simulate --config=FILE [--materials=FILE] --out=DIR\n\n"
    "Simulates the scene's reference object (or the object with the given per-element\n"
    "materials, moved so that its centre of mass is at object.position) with BDF time\n"
    "stepping, stable Neo-Hookean elasticity and IPC contact against the scene's planes and\n"
    "triangle-mesh obstacles (obstacles.meshes), with the scene's further bodies (bodies) and\n"
    "lagged Coulomb friction on every contact: contact.friction, or a plane's or mesh's own\n"
    "friction, or contact.pairs' for two bodies; contact.friction_iterations = k > 1 re-lags\n"
    "friction from each step's solution up to k - 1 times (forward runs only).\n"
    "Writes DIR/trajectory.csv (per step: time, centre of mass, linear and angular momentum,\n"
    "orientation quaternion, minimum contact distance, Newton iterations),\n"
    "DIR/trajectory.pvd with DIR/frames/*.vtu for ParaView, and DIR/report.json (steps, Newton\n"
    "iterations and friction re-lags, symbolic analyses, line-search energies and CCD searches\n"
    "stopped by their iteration cap (newton.ccd_caps: each answered a shorter step than need be),\n"
    "kappa, timings\n"
    "with Newton's split by phase, and every contact episode: its kind,\n"
    "planes and normal velocities; a restitution only for a one-plane contact whose normal\n"
    "velocity reversed; contact with mesh obstacles shows in the minimum distance, not yet as\n"
    "episodes).\n"
    "With time.contact_substeps = k steps shrink to h/k around contact; trajectory.csv keeps one\n"
    "row per step of h and report.json's contact_resolving says what the sub-steps did.",
    flags(), run_simulate});
