#include "rbaa/scene/scene_world.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "rbaa/error.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/io/materials_io.hpp"
#include "rbaa/scene/scene_mesh.hpp"
#include "rbaa/sim/barrier_stiffness.hpp"
#include "rbaa/sim/body_contact_form.hpp"

namespace rbaa {

namespace {

// The body-local ids (ascending) of a drive's vertices on a placed body mesh, turned by R from its
// own frame, its centre of mass at c (DriveSpec, scene.hpp).
std::vector<int> driven_vertex_ids(const Scene& scene, const DriveSpec& d, const TetMesh& mesh,
                                   const Eigen::Matrix3d& R, const Eigen::Vector3d& c) {
  const int n = mesh.num_vertices();
  auto fail = [&](const std::string& key, const std::string& what) {
    throw InputError(scene.source + ": key '" + d.key + "." + key + "': " + what);
  };
  if (!d.vertices.empty()) {
    if (d.vertices.back() >= n) {
      fail("vertices", "vertex " + std::to_string(d.vertices.back()) +
                           " is not one of the body's " + std::to_string(n) + " vertices (0 .. " +
                           std::to_string(n - 1) + ")");
    }
    return d.vertices;
  }
  const Eigen::Vector3d u = R * d.toward;
  Eigen::VectorXd along(n);
  for (int i = 0; i < n; ++i) along[i] = u.dot(mesh.V.row(i).transpose());
  const double end = along.maxCoeff();
  std::vector<int> candidates;
  for (int i = 0; i < n; ++i) {
    if (d.depth < 0 || along[i] >= end - d.depth) candidates.push_back(i);
  }
  if (d.count > 0) {
    if (d.count > static_cast<int>(candidates.size())) {
      std::ostringstream what;
      what << "value " << d.count << " is more than the " << candidates.size() << " vertices ";
      if (d.depth < 0)
        what << "of the body";
      else
        what << "within depth " << d.depth << " m of its end";
      fail("vertices.count", what.str());
    }
    // With a depth, the slab's vertices nearest the body's axis; without, the farthest along u.
    std::vector<double> key(n);
    for (int i : candidates) {
      const Eigen::Vector3d r = mesh.V.row(i).transpose() - c;
      key[i] = d.depth < 0 ? -along[i] : (r - r.dot(u) * u).norm();
    }
    std::stable_sort(candidates.begin(), candidates.end(),
                     [&](int a, int b) { return key[a] < key[b]; });
    candidates.resize(d.count);
    std::sort(candidates.begin(), candidates.end());
  }
  return candidates;
}

// Makes `body` (placed `mesh`, first vertex `vertex_begin`, turned by R) driven by `d`: its driven
// vertices, and its initial motion the drive's rigid motion at t = 0.
void apply_drive(const Scene& scene, const DriveSpec& d, const TetMesh& mesh,
                 const Eigen::Matrix3d& R, Body& body) {
  if (!d.enabled) return;
  for (int i : driven_vertex_ids(scene, d, mesh, R, body.centre)) {
    body.driven_vertices.push_back(body.vertex_begin + i);
  }
  body.drive = d.motion;
  body.velocity = d.motion.point_velocity(body.centre, 0.0);
  body.angular_velocity = d.motion.angular_speed(0.0) * d.motion.axis;
}

Eigen::Matrix3d rotation(const Eigen::Vector3d& axis, double angle_deg) {
  return Eigen::AngleAxisd(angle_deg * M_PI / 180.0, axis.normalized()).toRotationMatrix();
}

}  // namespace

int num_steps(const Scene& scene) {
  return static_cast<int>(std::lround(scene.duration / scene.time_step));
}

SimulationSettings simulation_settings(const Scene& scene, double kappa) {
  SimulationSettings s;
  s.time_step = scene.time_step;
  s.num_steps = num_steps(scene);
  s.integrator = scene.integrator;
  s.mass = scene.mass;
  s.gravity = scene.gravity;
  s.planes = scene.planes;
  s.obstacle_meshes = scene.obstacle_meshes;
  s.d_hat = scene.d_hat;
  s.friction_eps_v = scene.friction_eps_v;
  s.friction_iterations = scene.friction_iterations;
  s.body_friction = body_friction(scene);
  s.kappa = kappa;
  s.newton_tolerance = scene.newton_tolerance;
  s.newton_max_iterations = scene.newton_max_iterations;
  s.rigid_predictor = scene.newton_rigid_predictor;
  s.newton_chord_start = scene.newton_chord_start;
  s.contact_substeps = scene.contact_substeps;
  return s;
}

Eigen::MatrixXd body_friction(const Scene& scene) {
  if (scene.bodies.empty()) return {};
  const Eigen::Index n = static_cast<Eigen::Index>(scene.bodies.size()) + 1;
  Eigen::MatrixXd mu = Eigen::MatrixXd::Constant(n, n, scene.friction);
  for (const BodyPairFriction& p : scene.friction_pairs) {
    mu(p.a, p.b) = p.friction;
    mu(p.b, p.a) = p.friction;
  }
  mu.diagonal().setZero();
  return mu;
}

double scene_barrier_stiffness(const Scene& scene, const TetMesh& placed) {
  if (scene.kappa > 0) return scene.kappa;
  const Moments m = compute_moments(placed, scene.reference_rho);
  const double speed = barrier_design_speed(scene.velocity.norm(), scene.gravity, scene.planes,
                                            scene.obstacle_meshes, m.centre_of_mass());
  if (!(speed > 0)) {
    throw InputError(scene.source + ": cannot choose the barrier stiffness kappa by the energy "
                     "rule: the object neither moves nor falls onto an obstacle; set 'kappa'");
  }
  return barrier_stiffness_from_energy(m.m0, speed, scene.d_hat);
}

Scene swap_object(const Scene& scene, const std::string& name) {
  if (name == scene.object_name) return scene;
  const auto it = std::find_if(scene.bodies.begin(), scene.bodies.end(),
                               [&](const BodySpec& b) { return b.name == name; });
  if (it == scene.bodies.end()) {
    throw InputError(scene.source + ": no body named '" + name + "' to put in the object's place");
  }
  if (!scene.demonstration.object_copies.empty()) {
    throw InputError(scene.source + ": key 'demonstration.object_copies': the bodies it names "
                     "copy the object, which cannot trade places with body '" + name +
                     "' (attack.body); evaluate an attack on the object");
  }
  if (!it->materials_file.empty()) {
    throw InputError(scene.source + ": body '" + name + "' has a materials file (" +
                     it->materials_file + "); only a body of the reference material can take "
                     "the object's place");
  }
  const int i = static_cast<int>(it - scene.bodies.begin());
  Scene s = scene;
  if (!(s.kappa > 0)) s.kappa = scene_barrier_stiffness(scene, make_scene_mesh(scene));
  BodySpec old;
  old.name = scene.object_name;
  old.mesh = scene.mesh;
  old.position = scene.position;
  old.velocity = scene.velocity;
  old.angular_velocity = scene.angular_velocity;
  old.rotation_axis = scene.rotation_axis;
  old.rotation_angle_deg = scene.rotation_angle_deg;
  old.driven = scene.driven;
  const BodySpec& b = *it;
  s.object_name = b.name;
  s.mesh = b.mesh;
  s.position = b.position;
  s.velocity = b.velocity;
  s.angular_velocity = b.angular_velocity;
  s.rotation_axis = b.rotation_axis;
  s.rotation_angle_deg = b.rotation_angle_deg;
  s.driven = b.driven;
  s.bodies[i] = old;
  // World indices: 0 the object, k + 1 bodies[k]; the two swapped bodies trade theirs.
  const auto swapped = [i](int k) { return k == 0 ? i + 1 : k == i + 1 ? 0 : k; };
  for (BodyPairFriction& f : s.friction_pairs) {
    f.a = swapped(f.a);
    f.b = swapped(f.b);
  }
  return s;
}

Scene with_object_copies(const Scene& scene) {
  Scene s = scene;
  for (const std::string& name : scene.demonstration.object_copies) {
    const auto it = std::find_if(s.bodies.begin(), s.bodies.end(),
                                 [&](const BodySpec& b) { return b.name == name; });
    if (it == s.bodies.end()) {
      throw InputError(scene.source + ": key 'demonstration.object_copies': '" + name +
                       "' names no body");
    }
    it->object_copy = true;
  }
  return s;
}

MaterialField SceneWorld::materials(const MaterialField& object, const std::string& source) const {
  validate_material_field(object, bodies.front().num_elements(), source);
  const int n = object.size(), m = fixed_materials.size();
  MaterialField all;
  all.Y.resize(n + m);
  all.nu.resize(n + m);
  all.rho.resize(n + m);
  all.alpha.resize(n + m);
  all.Y << object.Y, fixed_materials.Y;
  all.nu << object.nu, fixed_materials.nu;
  all.rho << object.rho, fixed_materials.rho;
  all.alpha << object.alpha, fixed_materials.alpha;
  for (int i : copies) {
    const Body& b = bodies.at(i);
    all.Y.segment(b.element_begin, n) = object.Y;
    all.nu.segment(b.element_begin, n) = object.nu;
    all.rho.segment(b.element_begin, n) = object.rho;
    all.alpha.segment(b.element_begin, n) = object.alpha;
  }
  return all;
}

SceneWorld make_world(const Scene& scene, const TetMesh& object_mesh) {
  SceneWorld w;
  Body object;
  object.name = scene.object_name == "object" ? "object" : "'" + scene.object_name + "'";
  object.vertex_end = object_mesh.num_vertices();
  object.element_end = object_mesh.num_tets();
  object.centre = scene.position;
  object.velocity = scene.velocity;
  object.angular_velocity = scene.angular_velocity;
  apply_drive(scene, scene.driven, object_mesh,
              rotation(scene.rotation_axis, scene.rotation_angle_deg), object);
  w.bodies.push_back(object);
  std::vector<TetMesh> meshes{object_mesh};
  std::vector<MaterialField> fields;
  for (const BodySpec& spec : scene.bodies) {
    if (spec.object_copy) w.copies.push_back(static_cast<int>(w.bodies.size()));
    // A copy's elements get the object's materials in materials(); the reference's stand here.
    TetMesh mesh = spec.object_copy ? make_copy_mesh(scene, spec, object_mesh)
                                    : make_body_mesh(scene, spec);
    MaterialField field =
        spec.materials_file.empty() || spec.object_copy
            ? MaterialField::uniform(mesh.num_tets(), scene.reference_Y, scene.reference_nu,
                                     scene.reference_rho)
            : read_materials(spec.materials_file, mesh);
    if (!spec.materials_file.empty() && !spec.object_copy) {
      validate_material_field(field, mesh.num_tets(), spec.materials_file);
      // Its centre of mass under its own materials at its position, as for the object.
      const Eigen::Vector3d c = compute_moments(mesh, field.effective_density()).centre_of_mass();
      mesh.V.rowwise() += (spec.position - c).transpose();
    }
    Body b;
    b.name = "'" + spec.name + "'";
    b.vertex_begin = w.bodies.back().vertex_end;
    b.vertex_end = b.vertex_begin + mesh.num_vertices();
    b.element_begin = w.bodies.back().element_end;
    b.element_end = b.element_begin + mesh.num_tets();
    b.centre = spec.position;
    b.velocity = spec.velocity;
    b.angular_velocity = spec.angular_velocity;
    apply_drive(scene, spec.driven, mesh, rotation(spec.rotation_axis, spec.rotation_angle_deg), b);
    w.bodies.push_back(b);
    meshes.push_back(std::move(mesh));
    fields.push_back(std::move(field));
  }
  const Body& last = w.bodies.back();
  w.mesh.V.resize(last.vertex_end, 3);
  w.mesh.T.resize(last.element_end, 4);
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    const Body& b = w.bodies[i];
    w.mesh.V.middleRows(b.vertex_begin, b.num_vertices()) = meshes[i].V;
    w.mesh.T.middleRows(b.element_begin, b.num_elements()) =
        meshes[i].T.array() + b.vertex_begin;
  }
  const int fixed = last.element_end - w.bodies.front().element_end;
  w.fixed_materials = MaterialField::uniform(fixed, 1, 0.3, 1);
  for (std::size_t i = 0; i < fields.size(); ++i) {
    const Body& b = w.bodies[i + 1];
    const int at = b.element_begin - w.bodies.front().element_end;
    w.fixed_materials.Y.segment(at, b.num_elements()) = fields[i].Y;
    w.fixed_materials.nu.segment(at, b.num_elements()) = fields[i].nu;
    w.fixed_materials.rho.segment(at, b.num_elements()) = fields[i].rho;
    w.fixed_materials.alpha.segment(at, b.num_elements()) = fields[i].alpha;
  }
  if (w.bodies.size() > 1) {
    const BodyContactForm contact(w.mesh, vertex_body_ids(w.bodies, w.mesh.num_vertices()),
                                  scene.d_hat, 1.0);
    const Eigen::VectorXd q = Eigen::Map<const Eigen::VectorXd>(w.mesh.V.data(), 3 * w.mesh.num_vertices());
    const BodyClearance c = contact.clearance(q, scene.d_hat);
    if (c.intersecting || c.distance <= scene.d_hat) {
      std::ostringstream msg;
      msg << scene.source << ": body " << w.bodies[c.body_a].name << " and body "
          << w.bodies[c.body_b].name << " start " << (c.intersecting ? "overlapping" : "touching")
          << " (" << c.pair;
      if (!c.intersecting) msg << " at distance " << c.distance << " m";
      msg << "; they must start farther apart than d_hat = " << scene.d_hat << " m)";
      throw InputError(msg.str());
    }
  }
  return w;
}

std::vector<Body> simulated_bodies(const SceneWorld& world) {
  const bool driven = std::any_of(world.bodies.begin(), world.bodies.end(),
                                  [](const Body& b) { return b.is_driven(); });
  return world.bodies.size() > 1 || driven ? world.bodies : std::vector<Body>{};
}

DesignSpaceOptions design_space_options(const Scene& scene) {
  DesignSpaceOptions o;
  o.fields.clear();
  for (const std::string& name : scene.fields) o.fields.push_back(parse_design_field(name));
  o.Y_min = scene.Y_range.lo;
  o.Y_max = scene.Y_range.hi;
  o.nu_min = scene.nu_range.lo;
  o.nu_max = scene.nu_range.hi;
  o.rho_min = scene.rho_range.lo;
  o.rho_max = scene.rho_range.hi;
  o.alpha_min = scene.alpha_min;
  o.reference_rho = scene.reference_rho;
  o.alpha0 = scene.alpha0;
  o.Y0 = scene.Y0;
  o.nu0 = scene.nu0;
  o.boundary_by_vertex = scene.boundary_by_vertex;
  o.seed = scene.seed;
  o.perturbation = scene.perturbation;
  return o;
}

}  // namespace rbaa
