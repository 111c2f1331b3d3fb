#pragma once
// A scene for PolyFEM's command-line simulator (https://github.com/polyfem/polyfem,
// `PolyFEM_bin -j scene.json`): the bodies as Gmsh 2.2 tet meshes, per-element E, nu, rho as
// text files, obstacles as triangle meshes, and a JSON that sets gravity, BDF time stepping, IPC
// contact, initial velocities and driven (Dirichlet) vertices.
//
// The JSON keys follow PolyFEM's input schema as read at polyfem commit 661588e8 (2026-06-23):
// json-specs/input-spec.json (geometry, time, contact, boundary_conditions, initial_conditions,
// solver, output), json-specs/material-parameters.json (NeoHookean: E, nu, rho),
// json-specs/selection.json (point selections), json-specs/boundary-condition.json, and
// polysolve's nonlinear-solver-spec.json at the commit polyfem pins (715253d9: grad_norm_tol).
// How values are read: a string value naming an existing file is read as a matrix and indexed by
// the global element id (utils/ExpressionValue.cpp, assembler/MatParams.cpp), elements numbered
// through the non-obstacle geometries in list order (mesh/GeometryReader.cpp); otherwise it is a
// tinyexpr expression in x, y, z (rest position) and t.

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "rbaa/mesh/tet_mesh.hpp"
#include "rbaa/sim/world.hpp"

namespace rbaa {

/// What is exported: a physical model, not a config.
struct PolyfemScene {
  TetMesh mesh;                         ///< every body stacked (#V by 3, #T by 4), placed at t = 0
  std::vector<Body> bodies;             ///< ranges, centres, initial motions, driven vertices; >= 1
  std::vector<std::string> body_files;  ///< file name of each body's mesh (e.g. "object.msh")
  Eigen::VectorXd E, nu, rho;           ///< #T each (Pa, -, kg/m^3), stacked like mesh.T
  std::vector<Plane> planes;
  std::vector<ObstacleMesh> obstacle_meshes;
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  ///< m/s^2
  double time_step = 0.01;                            ///< s
  double duration = 0.25;                             ///< s
  int num_steps = 25;                                 ///< steps of time_step rbaa runs (num_steps)
  Integrator integrator = Integrator::kBdf2;
  MassModel mass = MassModel::kConsistent;
  double d_hat = 1e-3;           ///< m
  double friction = 0;           ///< PolyFEM's one (global) Coulomb coefficient
  double friction_eps_v = 1e-3;  ///< m/s
  int friction_iterations = 1;   ///< solver.contact.friction_iterations (rbaa's, see Scene)
  /// Half the side of the square each analytic plane becomes (m); <= 0: plane_half_width().
  double plane_half_width = 0;
  /// polysolve's nonlinear.grad_norm_tol (see polyfem_scene.cpp for why not its 1e-10).
  double grad_norm_tol = 1e-5;
};

/// What write_polyfem_scene wrote.
struct PolyfemExportResult {
  std::string json_file;           ///< DIR/scene.json
  std::vector<std::string> files;  ///< every file written, the JSON last
  double plane_half_width = 0;     ///< m, as used
};

/// The default half side of the plane squares: twice the farthest a body's vertex can get from
/// the bodies' common centroid in the run, bounded by its start distance plus (|v| + |w| r) T +
/// |g| T^2 / 2, and at least 1 m. Planes are centred on the projection of that centroid.
double plane_half_width(const PolyfemScene& scene);

/// The three components (tinyexpr text in x, y, z) of the rigid velocity field
/// v + w x (p - c) at rest position p = (x, y, z).
std::array<std::string, 3> rigid_velocity_expressions(const Eigen::Vector3d& centre,
                                                      const Eigen::Vector3d& velocity,
                                                      const Eigen::Vector3d& angular_velocity);

/// The three components (tinyexpr text in x, y, z, t) of the displacement u = x(t) - p of a
/// point at rest position p under `motion` (PrescribedMotion::position): Rodrigues' rotation by
/// omega t about the axis through centre + t velocity. Throws InputError naming `who` for a
/// piecewise-linear angular velocity table (not exported yet).
std::array<std::string, 3> drive_displacement_expressions(const PrescribedMotion& motion,
                                                          const std::string& who);

/// Writes DIR/<body_files[i]> (Gmsh 2.2 ASCII), DIR/E.txt, nu.txt, rho.txt (one value per line,
/// #T lines, stacked element order), DIR/plane_<i>.obj, DIR/obstacle_<i>.obj (placed triangles)
/// and DIR/scene.json, each atomically; creates DIR. Throws InputError when DIR cannot be made,
/// the sizes disagree, or a value is not finite.
PolyfemExportResult write_polyfem_scene(const std::string& dir, const PolyfemScene& scene);

}  // namespace rbaa
