// rbaa evaluate: the demonstration. Rigid reference, rigid adversarial, deformable reference and
// deformable adversarial runs of one scene, with a report, CSVs, a plot and a summary.

#include <gflags/gflags.h>

#include <cmath>
#include <iostream>
#include <string>

#include "rbaa/cli/scene_flags.hpp"
#include "rbaa/cli/verb.hpp"
#include "rbaa/error.hpp"
#include "rbaa/eval/evaluation.hpp"
#include "rbaa/io/materials_io.hpp"
#include "rbaa/io/tet_mesh_file.hpp"
#include "rbaa/scene/scene_mesh.hpp"
#include "rbaa/scene/scene_world.hpp"

DEFINE_string(
    adversarial, "",
    "the adversarial object: an rbaa .msh with element data Y, nu, rho, alpha, "
    "placed at the scene's initial pose (rbaa attack writes adversarial.msh); it is translated so "
    "that its own centre of mass is at object.position. 'reference': the stiff reference "
    "itself (checks a demonstration scene before any attack)");
DEFINE_double(duration, 0, "seconds to simulate (0: the config's evaluation.duration, else 4 x the attack's time.duration)");
DEFINE_string(time_step, "", "time step of the deformable runs and of the traces: seconds, or auto (refine the "
                             "attack's step by 4 until the stiff baseline agrees with its rigid twin); empty: the "
                             "config's evaluation.time_step, else the attack's time.step");
DEFINE_double(rigid_step, 1e-3, "Bullet's internal time step in s");
DEFINE_bool(soft_control, true, "also simulate the reference shape in uniform material at the scene's softest "
                                "allowed Y (same moments): the share of the gap that softness alone explains");
DECLARE_string(out);

namespace {

int run_evaluate() {
  if (FLAGS_adversarial.empty()) throw rbaa::InputError("--adversarial is required");
  if (FLAGS_out.empty()) throw rbaa::InputError("--out is required");
  if (!(FLAGS_rigid_step > 0)) throw rbaa::InputError("--rigid_step must be positive");
  if (FLAGS_duration < 0) throw rbaa::InputError("--duration must not be negative");
  double time_step = 0;
  if (!FLAGS_time_step.empty() && FLAGS_time_step != "auto") {
    size_t used = 0;
    try {
      time_step = std::stod(FLAGS_time_step, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != FLAGS_time_step.size() || !(time_step > 0) || !std::isfinite(time_step)) {
      throw rbaa::InputError("--time_step=" + FLAGS_time_step + ": expected a positive number of seconds or auto");
    }
  }
  // An attack on another body (attack.body) designed that body: it takes the object's place.
  const rbaa::Scene loaded = rbaa::cli::load_scene_from_flags();
  const rbaa::Scene scene = rbaa::swap_object(loaded, loaded.attack_body);
  std::cerr << "rbaa evaluate: meshing the reference object of " << scene.source
            << (scene.object_name == "object" ? "" : " (the attacked body '" + scene.object_name + "')")
            << "\n";
  const rbaa::TetMesh reference = rbaa::make_scene_mesh(scene);
  // --adversarial=reference: the reference against itself, to check a demonstration scene (does
  // the stiff reference score, rigid and deformable?) before any attack exists.
  const bool self_check = FLAGS_adversarial == "reference";
  const rbaa::TetMesh adversarial_mesh =
      self_check ? reference : rbaa::read_tet_mesh(FLAGS_adversarial).mesh;
  const rbaa::MaterialField materials =
      self_check ? rbaa::MaterialField::uniform(reference.num_tets(), scene.reference_Y,
                                                scene.reference_nu, scene.reference_rho, 1.0)
                 : rbaa::read_materials(FLAGS_adversarial, adversarial_mesh);
  rbaa::EvaluationOptions options;
  options.duration = FLAGS_duration;
  options.time_step = time_step;
  options.search_time_step = FLAGS_time_step == "auto";
  options.soft_control = FLAGS_soft_control;
  options.progress = &std::cerr;
  options.rigid.internal_step = FLAGS_rigid_step;
  std::cerr << "rbaa evaluate: four runs (rigid and deformable, reference and adversarial)\n";
  rbaa::Evaluation ev = rbaa::evaluate(scene, reference, adversarial_mesh, materials, options);
  // The stiff reference is outside the perceptual bounds the materials picture is drawn for.
  if (self_check) ev.adversarial_mesh = rbaa::TetMesh();
  rbaa::write_evaluation(ev, scene, FLAGS_out);
  std::cerr << "rbaa evaluate: " << ev.duration << " s at step " << ev.time_step << " s: rigid gap "
            << ev.rigid_vs_rigid.max_position_gap << " m, deformable gap " << ev.deformable_vs_deformable.position_gap
            << " m, baseline-vs-rigid gap " << ev.deformable_vs_rigid.position_gap << " m ("
            << ev.attack_advantage << " x) -> " << FLAGS_out << "/report.json\n";
  return 0;
}

std::vector<std::string> flags() {
  std::vector<std::string> f = rbaa::cli::scene_flag_names();
  for (const char* name : {"adversarial", "out", "duration", "time_step", "rigid_step", "soft_control"}) f.push_back(name);
  return f;
}

}  // namespace

RBAA_REGISTER_VERB(evaluate, rbaa::cli::Verb{
    "evaluate", "compare reference and adversarial objects as rigid (Bullet) and deformable bodies",
    "rbaa evaluate --config=FILE --adversarial=FILE|reference --out=DIR [--duration=T] [--time_step=H]\n\n"
    "Runs four simulations of the scene: rigid reference, rigid adversarial (Bullet, each twin\n"
    "built from its own mesh and materials), deformable reference (uniform, stiff baseline) and\n"
    "deformable adversarial. Bullet's restitution of each plane (each body's against it),\n"
    "obstacle mesh and pair of bodies is fitted to the baseline's first contact with it\n"
    "(report.json's calibration: within [0, 1], above 1 only for a rebound above 1; of several\n"
    "that fit, the one whose twin follows the baseline closest; a plane touched with no rebound\n"
    "to fit is listed, not fitted);\n"
    "its Coulomb friction is the scene's, per plane, obstacle mesh and pair of bodies\n"
    "(report.json's rigid.friction).\n"
    "The deformable runs use the config's evaluation.time_step, which may be finer than the\n"
    "attack's: the comparison is meaningful where the stiff baseline agrees with its rigid twin;\n"
    "--time_step=auto refines the attack's step by 4 until it strays less than\n"
    "evaluation.baseline_tolerance (default 0.5 %) of its path. A fifth run, the reference shape\n"
    "in uniform material at the softest allowed Y, shows what softness alone does.\n"
    "Gaps, velocity angles and orientation gaps compare the runs at the end time T (the angle\n"
    "is between the velocities at T, not the outgoing ones after a contact).\n"
    "A config with a demonstration block also gets an outcome table (its predicate, e.g. the\n"
    "ball passes through the hoop, and its figure per run, e.g. the angle of the velocity at T)\n"
    "in summary.md and report.json.\n"
    "--adversarial=reference evaluates the stiff reference as its own adversary (a scene check).\n"
    "An attack on another body (attack.body) is evaluated with that body in the object's place.\n"
    "Writes DIR/report.json, DIR/summary.md, one CSV per run and DIR/paths.png.",
    flags(), run_evaluate});
