#include "rbaa/scene/polyfem_scene.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "rbaa/error.hpp"
#include "rbaa/io/atomic_file.hpp"
#include "rbaa/io/msh.hpp"
#include "rbaa/io/number_text.hpp"

namespace rbaa {

namespace {

using nlohmann::json;

// A number inside an expression, parenthesised so that a negative one stays one operand.
std::string num(double x) { return "(" + format_double(x) + ")"; }

void check_finite(const Eigen::VectorXd& v, const char* what) {
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v[i])) {
      std::ostringstream msg;
      msg << "polyfem export: " << what << " of element " << i << " is not finite";
      throw InputError(msg.str());
    }
  }
}

void write_values(const std::string& path, const Eigen::VectorXd& values) {
  write_file_atomically(path, [&](std::ostream& os) {
    for (Eigen::Index i = 0; i < values.size(); ++i) os << exact(values[i]) << '\n';
  });
}

void write_obj(const std::string& path,
               const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>& V,
               const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>& F) {
  write_file_atomically(path, [&](std::ostream& os) {
    os << "# written by rbaa export --format=polyfem\n";
    for (Eigen::Index i = 0; i < V.rows(); ++i) {
      os << "v " << exact(V(i, 0)) << ' ' << exact(V(i, 1)) << ' ' << exact(V(i, 2)) << '\n';
    }
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
      os << "f " << F(f, 0) + 1 << ' ' << F(f, 1) + 1 << ' ' << F(f, 2) + 1 << '\n';
    }
  });
}

// The body's part of the stacked mesh, renumbered from 0.
TetMesh body_mesh(const TetMesh& mesh, const Body& b) {
  TetMesh out;
  out.V = mesh.V.middleRows(b.vertex_begin, b.num_vertices());
  out.T = mesh.T.middleRows(b.element_begin, b.num_elements()).array() - b.vertex_begin;
  return out;
}

Eigen::Vector3d bodies_centroid(const PolyfemScene& s) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const Body& b : s.bodies) c += b.centre;
  return c / static_cast<double>(s.bodies.size());
}

// A square of half side `half` in the plane, centred on the projection of `around`, as two
// triangles whose normal (counter-clockwise corners) is the plane's normal.
void plane_square(const Plane& p, const Eigen::Vector3d& around, double half,
                  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>& V,
                  Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>& F) {
  const Eigen::Vector3d n = p.normal.normalized();
  const Eigen::Vector3d o = around - (n.dot(around) - p.offset) * n;
  Eigen::Vector3d seed =
      std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d u = n.cross(seed).normalized();
  const Eigen::Vector3d w = n.cross(u);  // u x w = n
  V.resize(4, 3);
  V.row(0) = (o - half * u - half * w).transpose();
  V.row(1) = (o + half * u - half * w).transpose();
  V.row(2) = (o + half * u + half * w).transpose();
  V.row(3) = (o - half * u + half * w).transpose();
  F.resize(2, 3);
  F << 0, 1, 2, 0, 2, 3;
}

// Point selections picking exactly the driven vertices: one sphere per vertex, radius a quarter
// of its distance to the nearest other vertex of the body. (A selection file would be simpler,
// but PolyFEM's file selections of points are boundary-only unless given as {"file", ...}, a
// form its Selection::build reads through a missing "id" key; driven vertices may be interior,
// e.g. the bat's knob.)
json driven_point_selections(const TetMesh& mesh, const Body& b, int id) {
  json list = json::array();
  for (int v : b.driven_vertices) {
    const Eigen::RowVector3d p = mesh.V.row(v);
    double nearest = std::numeric_limits<double>::infinity();
    for (int w = b.vertex_begin; w < b.vertex_end; ++w) {
      if (w != v) nearest = std::min(nearest, (mesh.V.row(w) - p).norm());
    }
    list.push_back({{"id", id},
                    {"center", {p[0], p[1], p[2]}},
                    {"radius", 0.25 * nearest},
                    {"boundary_only", false}});
  }
  return list;
}

}  // namespace

double plane_half_width(const PolyfemScene& s) {
  const Eigen::Vector3d c = bodies_centroid(s);
  double reach = 0;
  for (const Body& b : s.bodies) {
    double r_body = 0, r_centroid = 0;
    for (int v = b.vertex_begin; v < b.vertex_end; ++v) {
      const Eigen::Vector3d x = s.mesh.V.row(v).transpose();
      r_body = std::max(r_body, (x - b.centre).norm());
      r_centroid = std::max(r_centroid, (x - c).norm());
    }
    double speed = b.velocity.norm() + b.angular_velocity.norm() * r_body;
    if (b.is_driven()) {
      speed = std::max(speed,
                       b.drive.velocity.norm() + std::abs(b.drive.angular_velocity) *
                                                     ((b.centre - b.drive.centre).norm() + r_body));
    }
    reach = std::max(
        reach, r_centroid + speed * s.duration + 0.5 * s.gravity.norm() * s.duration * s.duration);
  }
  return std::max(1.0, 2.0 * reach);
}

std::array<std::string, 3> rigid_velocity_expressions(const Eigen::Vector3d& c,
                                                      const Eigen::Vector3d& v,
                                                      const Eigen::Vector3d& w) {
  const std::array<std::string, 3> r{"(x-" + num(c[0]) + ")", "(y-" + num(c[1]) + ")",
                                     "(z-" + num(c[2]) + ")"};
  std::array<std::string, 3> out;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    // (w x r)_i = w_j r_k - w_k r_j
    out[i] = num(v[i]) + "+" + num(w[j]) + "*" + r[k] + "-" + num(w[k]) + "*" + r[j];
  }
  return out;
}

std::array<std::string, 3> drive_displacement_expressions(const PrescribedMotion& m,
                                                          const std::string& who) {
  if (!m.angular_velocity_table.empty()) {
    throw InputError(who +
                     ": a drive with an angular velocity table is not exported to PolyFEM yet "
                     "(only a constant angular_velocity)");
  }
  const Eigen::Vector3d& k = m.axis;
  const std::string angle = num(m.angular_velocity) + "*t";
  const std::string cs = "cos(" + angle + ")", sn = "sin(" + angle + ")";
  const std::array<std::string, 3> p{"x", "y", "z"};
  std::array<std::string, 3> r;
  for (int i = 0; i < 3; ++i) r[i] = "(" + p[i] + "-" + num(m.centre[i]) + ")";
  const std::string k_dot_r = "(" + num(k[0]) + "*" + r[0] + "+" + num(k[1]) + "*" + r[1] + "+" +
                              num(k[2]) + "*" + r[2] + ")";
  std::array<std::string, 3> out;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, l = (i + 2) % 3;
    const std::string k_cross_r = "(" + num(k[j]) + "*" + r[l] + "-" + num(k[l]) + "*" + r[j] + ")";
    // x(t) - p = c + t v + cos r + sin (k x r) + (1 - cos) k (k . r) - p
    out[i] = num(m.centre[i]) + "+t*" + num(m.velocity[i]) + "+" + cs + "*" + r[i] + "+" + sn +
             "*" + k_cross_r + "+(1-" + cs + ")*" + num(k[i]) + "*" + k_dot_r + "-" + p[i];
  }
  return out;
}

PolyfemExportResult write_polyfem_scene(const std::string& dir, const PolyfemScene& s) {
  const int nt = s.mesh.num_tets();
  if (s.bodies.empty() || s.body_files.size() != s.bodies.size() || s.E.size() != nt ||
      s.nu.size() != nt || s.rho.size() != nt || s.bodies.back().element_end != nt ||
      s.bodies.back().vertex_end != s.mesh.num_vertices()) {
    throw InputError("polyfem export: bodies, body files, materials and mesh sizes disagree");
  }
  check_finite(s.E, "E");
  check_finite(s.nu, "nu");
  check_finite(s.rho, "rho");
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir)) {
    throw InputError("polyfem export: cannot create output folder '" + dir + "'");
  }
  auto at = [&](const std::string& name) { return (std::filesystem::path(dir) / name).string(); };

  PolyfemExportResult result;
  json geometry = json::array();
  json velocities = json::array();
  json dirichlet = json::array();
  for (std::size_t i = 0; i < s.bodies.size(); ++i) {
    const Body& b = s.bodies[i];
    const int volume_id = static_cast<int>(i) + 1;
    write_msh(at(s.body_files[i]), body_mesh(s.mesh, b), {}, MshVersion::kV22);
    result.files.push_back(at(s.body_files[i]));
    json g = {{"mesh", s.body_files[i]}, {"volume_selection", volume_id}};
    if (b.is_driven()) {
      // Point ids 100 + i: apart from the volume ids and from PolyFEM's defaults (-1, INT_MAX).
      const int point_id = 100 + static_cast<int>(i);
      g["point_selection"] = driven_point_selections(s.mesh, b, point_id);
      const auto u = drive_displacement_expressions(b.drive, "body " + b.name);
      dirichlet.push_back({{"id", point_id}, {"value", {u[0], u[1], u[2]}}});
    }
    geometry.push_back(g);
    const auto v = rigid_velocity_expressions(b.centre, b.velocity, b.angular_velocity);
    velocities.push_back({{"id", volume_id}, {"value", {v[0], v[1], v[2]}}});
  }

  result.plane_half_width = s.plane_half_width > 0 ? s.plane_half_width : plane_half_width(s);
  const Eigen::Vector3d around = bodies_centroid(s);
  for (std::size_t i = 0; i < s.planes.size(); ++i) {
    Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> V;
    Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> F;
    plane_square(s.planes[i], around, result.plane_half_width, V, F);
    const std::string name = "plane_" + std::to_string(i) + ".obj";
    write_obj(at(name), V, F);
    result.files.push_back(at(name));
    geometry.push_back({{"mesh", name}, {"is_obstacle", true}});
  }
  for (std::size_t i = 0; i < s.obstacle_meshes.size(); ++i) {
    const std::string name = "obstacle_" + std::to_string(i) + ".obj";
    write_obj(at(name), s.obstacle_meshes[i].V, s.obstacle_meshes[i].F);
    result.files.push_back(at(name));
    geometry.push_back({{"mesh", name}, {"is_obstacle", true}});
  }

  for (const auto& [name, values] : {std::pair<const char*, const Eigen::VectorXd*>{"E.txt", &s.E},
                                     {"nu.txt", &s.nu},
                                     {"rho.txt", &s.rho}}) {
    write_values(at(name), *values);
    result.files.push_back(at(name));
  }

  json scene;
  scene["geometry"] = geometry;
  // One material object (the schema boxes it into the list): Assembler::set_materials then reads
  // each file once and indexes it by the global element id. A list entry would re-read the file
  // for every element.
  scene["materials"] = {
      {"type", "NeoHookean"}, {"E", "E.txt"}, {"nu", "nu.txt"}, {"rho", "rho.txt"}};
  // rbaa runs round(T / h) steps (simulation_settings); PolyFEM, given tend and dt, would run
  // ceil(T / h), one more whenever T / h lands just above a whole number (0.07 / 0.005 =
  // 14.000000000000002). It takes exactly two of tend, dt and time_steps: dt and the count.
  scene["time"] = {
      {"dt", s.time_step},
      {"time_steps", s.num_steps},
      {"integrator", {{"type", "BDF"}, {"steps", s.integrator == Integrator::kBdf2 ? 2 : 1}}}};
  scene["contact"] = {{"enabled", true},
                      {"dhat", s.d_hat},
                      {"friction_coefficient", s.friction},
                      {"epsv", s.friction_eps_v}};
  // PolyFEM's body force: rhs = -g (rhs [0, 0, 9.8] accelerates by -9.8 m/s^2 along z).
  json bc = {{"rhs", {0.0 - s.gravity[0], 0.0 - s.gravity[1], 0.0 - s.gravity[2]}}};
  if (!dirichlet.empty()) bc["dirichlet_boundary"] = dirichlet;
  scene["boundary_conditions"] = bc;
  scene["initial_conditions"] = {{"velocity", velocities}};
  // polysolve stops Newton on the gradient norm (grad_norm_tol, default 1e-10, rescaled by
  // PolyFEM's characteristic force and length). With E up to 1e13 Pa the elastic gradient's own
  // round-off at an impact is above that, so Newton never meets it and PolyFEM aborts at the
  // iteration limit; the looser tolerance stops at what double precision resolves.
  scene["solver"] = {{"nonlinear", {{"grad_norm_tol", s.grad_norm_tol}}},
                     {"contact", {{"friction_iterations", s.friction_iterations}}},
                     {"advanced", {{"lump_mass_matrix", s.mass == MassModel::kLumped}}}};
  scene["output"] = {{"paraview", {{"file_name", "result.vtu"}}}};
  result.json_file = at("scene.json");
  write_file_atomically(result.json_file, [&](std::ostream& os) { os << scene.dump(2) << '\n'; });
  result.files.push_back(result.json_file);
  return result;
}

}  // namespace rbaa
