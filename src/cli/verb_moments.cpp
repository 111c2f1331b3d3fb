// rbaa moments: the 10 mass moments of a tet mesh as JSON.

#include <gflags/gflags.h>
#include <nlohmann/json.hpp>

#include <iostream>

#include "rbaa/cli/verb.hpp"
#include "rbaa/error.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/io/materials_io.hpp"
#include "rbaa/io/tet_mesh_file.hpp"

DEFINE_string(mesh, "", "tet mesh file (.msh, .mesh, .node/.ele)");
DECLARE_string(materials);  // default: uniform --density
DEFINE_double(density, 2500.0, "uniform density in kg/m^3 when no --materials is given");

namespace {

int run_moments() {
  if (FLAGS_mesh.empty()) throw rbaa::InputError("--mesh is required");
  if (!(FLAGS_density > 0)) throw rbaa::InputError("--density must be positive");
  const rbaa::TetMesh mesh = rbaa::read_tet_mesh(FLAGS_mesh).mesh;
  Eigen::VectorXd density = Eigen::VectorXd::Constant(mesh.num_tets(), FLAGS_density);
  if (!FLAGS_materials.empty()) {
    density = rbaa::read_materials(FLAGS_materials, mesh).effective_density();
  }
  const rbaa::Moments m = rbaa::compute_moments(mesh, density);
  nlohmann::json out;
  out["m0"] = m.m0;
  out["m1"] = {m.m1[0], m.m1[1], m.m1[2]};
  out["m2"] = {m.m2[0], m.m2[1], m.m2[2], m.m2[3], m.m2[4], m.m2[5]};
  std::cout << out.dump() << std::endl;
  return 0;
}

}  // namespace

RBAA_REGISTER_VERB(moments, rbaa::cli::Verb{
    "moments", "print the 10 mass moments of a tet mesh as JSON",
    "rbaa moments --mesh=FILE [--materials=FILE | --density=RHO]\n\n"
    "Prints {\"m0\": x, \"m1\": [x, y, z], \"m2\": [xx, yy, zz, xy, xz, yz]} on stdout: exact\n"
    "integrals over the linear tets of rho*alpha (kg), rho*alpha*x (kg m) and\n"
    "rho*alpha*(x.x I - x x^T) (kg m^2) about the origin.",
    {"mesh", "materials", "density"},
    run_moments});
