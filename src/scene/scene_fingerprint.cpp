#include "rbaa/scene/scene_fingerprint.hpp"

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "rbaa/scene/scene_world.hpp"

namespace rbaa {

namespace {

// Exact and locale-free: every bit of the double, "nan" for the unset initial materials.
std::string number(double x) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%a", x);
  return buffer;
}

std::string vector3(const Eigen::Vector3d& v) {
  return number(v.x()) + " " + number(v.y()) + " " + number(v.z());
}

// A mesh or surface file enters by its bytes, so moving it changes nothing and editing it does.
std::string file_content(const std::string& path) {
  if (path.empty()) return "-";
  std::ifstream in(path, std::ios::binary);
  if (!in) return "unreadable " + path;  // loading the scene reports it
  std::stringstream bytes;
  bytes << in.rdbuf();
  return fingerprint_hex(bytes.str());
}

// A drive's line; only driven bodies print one, so older fingerprints stay valid.
void print_drive(std::ostream& t, const DriveSpec& d) {
  if (!d.enabled) return;
  t << d.key << " vertices";
  for (int v : d.vertices) t << " " << v;
  t << " toward " << vector3(d.toward) << " " << number(d.depth) << " " << d.count << " axis "
    << vector3(d.motion.axis) << " centre " << vector3(d.motion.centre) << " omega "
    << number(d.motion.angular_velocity);
  for (const Eigen::Vector2d& row : d.motion.angular_velocity_table)
    t << " " << number(row[0]) << " " << number(row[1]);
  t << " velocity " << vector3(d.motion.velocity) << "\n";
}

}  // namespace

std::string scene_fingerprint_text(const Scene& s) {
  std::ostringstream t;
  t << "rbaa-attack 1\n";
  t << "mesh.shape " << (s.mesh.shape.empty() ? "-" : s.mesh.shape) << "\n";
  t << "mesh.surface " << file_content(s.mesh.surface_file) << "\n";
  t << "mesh.file " << file_content(s.mesh.mesh_file) << "\n";
  t << "mesh.target_tets " << s.mesh.target_tets << "\n";
  t << "mesh.radius " << number(s.mesh.radius) << "\n";
  t << "mesh.side " << number(s.mesh.side) << "\n";
  t << "mesh.volume " << number(s.mesh.volume) << "\n";
  t << "object.position " << vector3(s.position) << "\n";
  t << "object.velocity " << vector3(s.velocity) << "\n";
  t << "object.angular_velocity " << vector3(s.angular_velocity) << "\n";
  t << "object.rotation " << vector3(s.rotation_axis) << " " << number(s.rotation_angle_deg) << "\n";
  print_drive(t, s.driven);
  for (const Plane& p : s.planes) {
    t << "plane " << vector3(p.normal) << " " << number(p.offset);
    // Frictionless planes print as before, so older fingerprints stay valid.
    if (p.friction != 0) t << " friction " << number(p.friction) << " " << number(s.friction_eps_v);
    t << "\n";
  }
  // Only scenes with obstacle meshes print these lines, so older fingerprints stay valid.
  for (const ObstacleMesh& m : s.obstacle_meshes) {
    t << "obstacle.mesh " << file_content(m.file) << " " << vector3(m.position) << " "
      << vector3(m.rotation_axis) << " " << number(m.rotation_angle_deg) << " " << number(m.scale);
    // Frictionless meshes print as before.
    if (m.friction != 0) t << " friction " << number(m.friction) << " " << number(s.friction_eps_v);
    t << "\n";
  }
  // Likewise only scenes with further bodies print theirs.
  for (const BodySpec& b : s.bodies) {
    t << "body " << b.name << " " << (b.mesh.shape.empty() ? "-" : b.mesh.shape) << " "
      << file_content(b.mesh.surface_file) << " " << file_content(b.mesh.mesh_file) << " "
      << b.mesh.target_tets << " " << number(b.mesh.radius) << " " << number(b.mesh.side) << " "
      << number(b.mesh.volume) << " " << vector3(b.position) << " " << vector3(b.velocity) << " "
      << vector3(b.angular_velocity) << " " << vector3(b.rotation_axis) << " "
      << number(b.rotation_angle_deg) << " " << file_content(b.materials_file) << "\n";
    print_drive(t, b.driven);
  }
  // Friction between bodies, only where there is some (older fingerprints stay valid).
  const Eigen::MatrixXd mu = body_friction(s);
  for (Eigen::Index a = 0; a < mu.rows(); ++a) {
    for (Eigen::Index b = a + 1; b < mu.cols(); ++b) {
      if (mu(a, b) != 0) {
        t << "friction bodies " << a << " " << b << " " << number(mu(a, b)) << " "
          << number(s.friction_eps_v) << "\n";
      }
    }
  }
  t << "gravity " << vector3(s.gravity) << "\n";
  t << "time.step " << number(s.time_step) << "\n";
  t << "time.duration " << number(s.duration) << "\n";
  t << "time.integrator " << (s.integrator == Integrator::kBdf1 ? "bdf1" : "bdf2") << "\n";
  t << "time.mass " << (s.mass == MassModel::kLumped ? "lumped" : "consistent") << "\n";
  if (s.contact_substeps > 0) t << "time.contact_substeps " << s.contact_substeps << "\n";
  t << "contact.d_hat " << number(s.d_hat) << "\n";
  t << "contact.kappa " << number(s.kappa) << "\n";
  if (s.friction_iterations != 1) t << "contact.friction_iterations " << s.friction_iterations << "\n";
  t << "newton.tolerance " << number(s.newton_tolerance) << "\n";
  // The predictor changes results within Newton's tolerance; the default keeps older checkpoints'
  // fingerprints.
  if (!s.newton_rigid_predictor) t << "newton.rigid_predictor false\n";
  if (!s.newton_chord_start) t << "newton.chord_start false\n";
  t << "reference_material " << number(s.reference_Y) << " " << number(s.reference_nu) << " "
    << number(s.reference_rho) << "\n";
  t << "material_bounds.Y " << number(s.Y_range.lo) << " " << number(s.Y_range.hi) << "\n";
  t << "material_bounds.nu " << number(s.nu_range.lo) << " " << number(s.nu_range.hi) << "\n";
  t << "material_bounds.rho " << number(s.rho_range.lo) << " " << number(s.rho_range.hi) << "\n";
  t << "material_bounds.alpha_min " << number(s.alpha_min) << "\n";
  t << "attack.fields";
  for (const std::string& f : s.fields) t << " " << f;
  t << "\n";
  t << "attack.learning_rate " << number(s.learning_rate) << "\n";
  t << "attack.beta " << number(s.beta) << "\n";
  t << "attack.adam " << number(s.adam_beta1) << " " << number(s.adam_beta2) << "\n";
  t << "attack.seed " << s.seed << "\n";
  t << "attack.perturbation " << number(s.perturbation) << "\n";
  t << "attack.alpha0 " << number(s.alpha0) << "\n";
  t << "attack.Y0 " << number(s.Y0) << "\n";
  t << "attack.nu0 " << number(s.nu0) << "\n";
  t << "attack.smoothing_gamma " << number(s.smoothing_gamma) << "\n";
  t << "attack.boundary " << (s.boundary_by_vertex ? "vertices" : "faces") << "\n";
  t << "attack.round_threshold " << number(s.round_threshold) << "\n";
  t << "attack.project_moments " << (s.project_moments ? "true" : "false") << "\n";
  // The occupancy penalty prints only when on, so older fingerprints stay valid.
  if (s.occupancy_weight > 0 || s.occupancy_connectivity_weight > 0 || s.occupancy_repair_in_loop) {
    t << "attack.occupancy_penalty " << number(s.occupancy_weight) << " "
      << number(s.occupancy_connectivity_weight) << " " << number(s.occupancy_ramp_start) << " "
      << number(s.occupancy_ramp_end) << (s.occupancy_repair_in_loop ? " repair_in_loop" : "")
      << "\n";
  }
  // Only the non-default start prints, so older fingerprints stay valid.
  if (s.start_best_uniform) t << "attack.start best_uniform\n";
  // The attacked body and the objective print only when not the defaults, so older fingerprints
  // stay valid.
  if (s.attack_body != "object") t << "attack.body " << s.attack_body << "\n";
  if (s.objective.kind != ObjectiveSpec::Kind::kUndirected || !s.objective.body.empty()) {
    t << "objective " << objective_kind_name(s.objective.kind) << " "
      << (s.objective.body.empty() ? "-" : s.objective.body);
    if (s.objective.kind == ObjectiveSpec::Kind::kTarget) {
      t << " " << s.objective.component << " " << number(s.objective.value);
    }
    t << "\n";
  }
  return t.str();
}

std::string fingerprint_hex(const std::string& bytes) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 1099511628211ull;
  }
  std::ostringstream out;
  out << std::hex << std::setw(16) << std::setfill('0') << h;
  return out.str();
}

std::string scene_fingerprint(const Scene& scene) {
  return fingerprint_hex(scene_fingerprint_text(scene));
}

}  // namespace rbaa
