// rbaa mesh: tetrahedralise a reference shape or a closed surface with CGAL Mesh_3.

#include <gflags/gflags.h>

#include <chrono>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <utility>

#include "rbaa/cli/verb.hpp"
#include "rbaa/error.hpp"
#include "rbaa/io/tet_mesh_file.hpp"
#include "rbaa/mesh/tetrahedralize.hpp"

DEFINE_string(shape, "", "reference shape: sphere, cube, star, bat or bunny (SPEC section 7)");
DEFINE_string(surface, "", "closed surface file to tetrahedralise (.off, .obj, .stl, .ply)");
DEFINE_int32(target_tets, 0, "wanted number of tets (0: the paper's count for --shape, 5000 for --surface)");
DECLARE_string(out);
DEFINE_double(radius, 0, "with --shape=sphere: its radius in m (not given: 0.121)");
DEFINE_double(side, 0, "with --shape=cube: its side in m (not given: 0.05)");
DEFINE_double(
    volume, 0,
    "with --surface: scale the tet mesh to this volume (m^3) and centre it (not given: keep)");

namespace {

/// The size flags (--radius, --side, --volume) each belong to one input, and the library reads a
/// value <= 0 as "the default": a size given for another shape, or a non-positive one, would be
/// dropped without a word and another object meshed than the one asked for. A flag counts as
/// given when gflags marks it so (on the command line or in a --flagfile), even at the default's
/// value 0. Non-finite numbers are already refused in main() with every verb's flags.
void check_size_flags() {
  // The size flag the chosen input reads, if any.
  const std::string used = rbaa::mesh_size_key(FLAGS_surface.empty() ? FLAGS_shape : "");
  const std::string input = FLAGS_surface.empty() ? "--shape=" + FLAGS_shape : "--surface";
  const std::pair<const char*, double> sizes[] = {
      {"radius", FLAGS_radius}, {"side", FLAGS_side}, {"volume", FLAGS_volume}};
  for (const auto& [name, value] : sizes) {
    if (gflags::GetCommandLineFlagInfoOrDie(name).is_default) continue;
    // gflags' current_value prints 17 digits (0.10000000000000001); the user typed fewer.
    std::ostringstream given;
    given << "--" << name << "=" << std::setprecision(12) << value;
    if (name != used) {
      throw rbaa::InputError(given.str() + ": " + input + " has no " + name +
                             " (--radius is --shape=sphere's, --side --shape=cube's, --volume "
                             "--surface's)");
    }
    if (!(value > 0)) throw rbaa::InputError(given.str() + ": must be positive");
  }
}

int run_mesh() {
  if (FLAGS_shape.empty() == FLAGS_surface.empty()) {
    throw rbaa::InputError("give exactly one of --shape and --surface");
  }
  if (FLAGS_out.empty()) throw rbaa::InputError("--out is required");
  if (FLAGS_target_tets < 0) throw rbaa::InputError("--target_tets must be positive");
  // An unknown shape is the error to report, not the size flags it cannot have.
  if (!FLAGS_shape.empty()) rbaa::default_tet_count(FLAGS_shape);
  check_size_flags();
  const auto start = std::chrono::steady_clock::now();
  rbaa::TetMesh mesh;
  rbaa::MeshingOutcome outcome;
  if (!FLAGS_shape.empty()) {
    rbaa::ShapeParameters params;
    params.radius = FLAGS_radius;
    params.side = FLAGS_side;
    mesh = rbaa::mesh_shape(FLAGS_shape, FLAGS_target_tets, params, &outcome);
  } else {
    mesh = rbaa::mesh_surface_file(FLAGS_surface, FLAGS_target_tets > 0 ? FLAGS_target_tets : 5000,
                                   FLAGS_volume, &outcome);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  rbaa::write_tet_mesh(FLAGS_out, mesh);
  if (!outcome.within_tolerance()) {
    std::cerr << "rbaa mesh: warning: the target of " << outcome.target_tets
              << " tets was not met within " << 100 * outcome.tolerance << " %: got "
              << mesh.num_tets() << " (" << outcome.shortfall() << ")\n";
  }
  const Eigen::VectorXd vol = rbaa::tet_volumes(mesh);
  std::cerr << "rbaa mesh: " << mesh.num_tets() << " tets (target " << outcome.target_tets << "), "
            << mesh.num_vertices() << " vertices, volume " << vol.sum() << " m^3, smallest tet "
            << vol.minCoeff() << " m^3, " << seconds << " s -> " << FLAGS_out << "\n";
  return 0;
}

}  // namespace

RBAA_REGISTER_VERB(mesh, rbaa::cli::Verb{
    "mesh", "tetrahedralise a reference shape or a closed surface (CGAL Mesh_3)",
    "rbaa mesh --shape=sphere|cube|star|bat|bunny | --surface=FILE [--target_tets=N] --out=FILE\n"
    "          [--radius=M (sphere) | --side=M (cube) | --volume=M3 (surface)]\n\n"
    "Meshes deterministically (sequential CGAL, fixed seed): the same command writes the same file.\n"
    "The cell size is searched until the tet count is within 5% of --target_tets; a surface's\n"
    "detail can set a floor (sharp edges keep small elements), and then the count closest to\n"
    "the target is kept and a warning on stderr says so. Every tet is positively oriented and\n"
    "non-degenerate.",
    {"shape", "surface", "target_tets", "out", "radius", "side", "volume"},
    run_mesh});
