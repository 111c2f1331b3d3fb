// rbaa export: writes a scene for another simulator (PolyFEM's command line).

#include <gflags/gflags.h>

#include <cstdio>
#include <filesystem>

#include "rbaa/cli/scene_flags.hpp"
#include "rbaa/cli/verb.hpp"
#include "rbaa/error.hpp"
#include "rbaa/scene/polyfem_model.hpp"
#include "rbaa/scene/polyfem_scene.hpp"
#include "rbaa/scene/scene_world.hpp"

DECLARE_string(adversarial);
DECLARE_string(out);  // here: the output directory
DEFINE_string(format, "", "export format: polyfem (a scene for PolyFEM_bin -j scene.json, run in DIR)");

namespace {

int run_export() {
  if (FLAGS_format != "polyfem") {
    throw rbaa::InputError("--format: unknown format '" + FLAGS_format + "' (known: polyfem)");
  }
  if (FLAGS_out.empty()) throw rbaa::InputError("--out is required");
  const rbaa::Scene loaded = rbaa::cli::load_scene_from_flags();
  // An adversarial object of an attack on another body (attack.body) takes that body's place.
  // demonstration.object_copies: those bodies are copies of the exported object, with its
  // materials, as in `rbaa evaluate`.
  const rbaa::Scene scene = rbaa::with_object_copies(
      FLAGS_adversarial.empty() ? loaded : rbaa::swap_object(loaded, loaded.attack_body));
  rbaa::ExportObject object;
  if (FLAGS_adversarial.empty()) {
    object = rbaa::reference_export_object(scene);
  } else {
    if (!std::filesystem::is_regular_file(FLAGS_adversarial)) {
      throw rbaa::InputError("--adversarial: no such file '" + FLAGS_adversarial + "'");
    }
    object = rbaa::adversarial_export_object(scene, FLAGS_adversarial);
    std::fprintf(stderr,
                 "adversarial object: %d elements, %d void elements and %d vertices removed, %d "
                 "partly occupied (exported as alpha^3 Y, alpha rho)\n",
                 object.mesh.num_tets(), object.removed_elements, object.removed_vertices,
                 object.fractional_elements);
  }
  const rbaa::PolyfemScene model = rbaa::polyfem_model(scene, object);
  const rbaa::PolyfemExportResult r = rbaa::write_polyfem_scene(FLAGS_out, model);
  std::fprintf(stderr,
               "%zu bodies (%d tets), %zu planes as squares of half side %.4g m, %zu obstacle "
               "meshes; run in that folder (its files are named relative to it): cd %s && "
               "PolyFEM_bin -j scene.json\n",
               model.bodies.size(), model.mesh.num_tets(), model.planes.size(), r.plane_half_width,
               model.obstacle_meshes.size(), FLAGS_out.c_str());
  return 0;
}

std::vector<std::string> flags() {
  std::vector<std::string> f = rbaa::cli::scene_flag_names();
  f.insert(f.end(), {"format", "adversarial", "out"});
  return f;
}

}  // namespace

// clang-format off
RBAA_REGISTER_VERB(export, rbaa::cli::Verb{
    "export", "write a scene for another simulator (PolyFEM)",
    "rbaa export --format=polyfem --config=FILE [--adversarial=MESH.msh] [--set=...] --out=DIR\n\n"
    "Writes DIR/scene.json for PolyFEM's command line (in DIR: PolyFEM_bin -j scene.json) with:\n"
    "DIR/object.msh and DIR/body_<i>_<name>.msh, every body as a Gmsh 2.2 ASCII tet mesh placed\n"
    "at t = 0 (the object is the reference, or the --adversarial mesh with its void elements,\n"
    "alpha < attack.round_threshold, removed and its centre of mass moved to object.position,\n"
    "turned into the scene's pose if the attack designed it unturned; its outer surface must be\n"
    "the scene's reference's, as rbaa evaluate requires, else it is refused; an attack on\n"
    "another body, attack.body, puts its object in that body's place; a body of\n"
    "demonstration.object_copies is a copy of that object, with its materials);\n"
    "DIR/E.txt, nu.txt, rho.txt, one value per element, all bodies' elements in file order\n"
    "(a partly occupied element as alpha^3 Y and alpha rho); DIR/plane_<i>.obj, each analytic\n"
    "plane as a square of two triangles (PolyFEM's own planes take no part in its contact),\n"
    "twice the farthest any body can get in the run across (at least 1 m), and\n"
    "DIR/obstacle_<i>.obj, the placed obstacle meshes, both with is_obstacle; gravity as\n"
    "boundary_conditions.rhs = -g; BDF with the scene's order, h and T; contact.dhat, the\n"
    "friction coefficient (PolyFEM has one: scenes with differing coefficients are refused) and\n"
    "epsv, solver.contact.friction_iterations (the scene's contact.friction_iterations);\n"
    "Neo-Hookean material; every body's initial rigid velocity field v + w x (x - c);\n"
    "driven vertices as Dirichlet conditions (Rodrigues' rotation at a constant angular velocity;\n"
    "drives with a table are refused); solver.nonlinear.grad_norm_tol = 1e-5 (PolyFEM's default\n"
    "1e-10 is below the round-off of GPa materials' elastic forces at an impact).",
    flags(), run_export});
// clang-format on
