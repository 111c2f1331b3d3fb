#include "rbaa/scene/polyfem_model.hpp"

#include <cctype>
#include <cmath>
#include <sstream>
#include <utility>
#include <vector>

#include "rbaa/error.hpp"
#include "rbaa/io/tet_mesh_file.hpp"
#include "rbaa/scene/scene_mesh.hpp"
#include "rbaa/scene/scene_world.hpp"

namespace rbaa {

ExportObject reference_export_object(const Scene& scene) {
  ExportObject o;
  o.mesh = make_scene_mesh(scene);
  o.materials = MaterialField::uniform(o.mesh.num_tets(), scene.reference_Y, scene.reference_nu,
                                       scene.reference_rho);
  return o;
}

ExportObject adversarial_export_object(const Scene& scene, const std::string& path) {
  const TetMeshFile file = read_tet_mesh(path);
  const int nt = file.mesh.num_tets();
  auto field = [&](const char* name, bool required) -> Eigen::VectorXd {
    const auto it = file.element_data.find(name);
    if (it == file.element_data.end()) {
      if (required) {
        throw InputError(path + ": no element data '" + name +
                         "' (an adversarial mesh carries Y, nu, rho and alpha)");
      }
      return Eigen::VectorXd::Ones(nt);
    }
    return it->second;
  };
  MaterialField all;
  all.Y = field("Y", true);
  all.nu = field("nu", true);
  all.rho = field("rho", true);
  all.alpha = field("alpha", false);
  std::vector<int> kept;
  for (int e = 0; e < nt; ++e) {
    const double a = all.alpha[e];
    if (!(a >= 0 && a <= 1)) {
      std::ostringstream msg;
      msg << path << ": element " << e << ": alpha " << a << " is outside [0, 1]";
      throw InputError(msg.str());
    }
    if (a >= scene.round_threshold) kept.push_back(e);
  }
  if (kept.empty()) {
    std::ostringstream msg;
    msg << path << ": every element is void (alpha < " << scene.round_threshold << ")";
    throw InputError(msg.str());
  }
  // In the scene's pose with its void elements still in, whose outer surface must be the
  // scene's reference's (as rbaa evaluate requires): another scene's object is refused.
  const TetMesh posed = adversarial_in_scene(scene, make_scene_mesh(scene), file.mesh, path);
  ExportObject o;
  o.removed_elements = nt - static_cast<int>(kept.size());
  const int n = static_cast<int>(kept.size());
  o.mesh.V = posed.V;
  o.mesh.T.resize(n, 4);
  o.materials = MaterialField::uniform(n, 1, 0.3, 1);
  for (int i = 0; i < n; ++i) {
    const int e = kept[i];
    o.mesh.T.row(i) = file.mesh.T.row(e);
    o.materials.Y[i] = all.Y[e];
    o.materials.nu[i] = all.nu[e];
    o.materials.rho[i] = all.rho[e];
    o.materials.alpha[i] = all.alpha[e];
    o.fractional_elements += all.alpha[e] < 1;
  }
  o.removed_vertices = remove_unreferenced_vertices(o.mesh);
  validate_material_field(o.materials, n, path);
  o.mesh = place_centre_of_mass(scene, std::move(o.mesh), o.materials.effective_density(), path);
  return o;
}

namespace {

// Every friction coefficient the scene sets on a pair of surfaces, with what it belongs to.
std::vector<std::pair<std::string, double>> friction_coefficients(const Scene& scene) {
  std::vector<std::pair<std::string, double>> out;
  for (std::size_t i = 0; i < scene.planes.size(); ++i) {
    out.emplace_back("obstacles.planes[" + std::to_string(i) + "]", scene.planes[i].friction);
  }
  for (const ObstacleMesh& m : scene.obstacle_meshes) out.emplace_back(m.name, m.friction);
  const Eigen::MatrixXd mu = body_friction(scene);
  auto name = [&](Eigen::Index i) { return body_name(scene, static_cast<int>(i)); };
  for (Eigen::Index a = 0; a < mu.rows(); ++a) {
    for (Eigen::Index b = a + 1; b < mu.cols(); ++b) {
      out.emplace_back("bodies " + name(a) + " and " + name(b), mu(a, b));
    }
  }
  return out;
}

}  // namespace

PolyfemScene polyfem_model(const Scene& scene, const ExportObject& object) {
  const SceneWorld world = make_world(scene, object.mesh);
  const MaterialField m = world.materials(object.materials, "exported object");
  PolyfemScene s;
  s.mesh = world.mesh;
  s.bodies = world.bodies;
  s.body_files.push_back("object.msh");
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    std::string name = scene.bodies[i].name;
    for (char& c : name) {
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') c = '_';
    }
    s.body_files.push_back("body_" + std::to_string(i) + "_" + name + ".msh");
  }
  s.E = m.Y.cwiseProduct(m.alpha.cwiseProduct(m.alpha).cwiseProduct(m.alpha));
  s.nu = m.nu;
  s.rho = m.rho.cwiseProduct(m.alpha);
  s.planes = scene.planes;
  s.obstacle_meshes = scene.obstacle_meshes;
  s.gravity = scene.gravity;
  s.time_step = scene.time_step;
  s.duration = scene.duration;
  s.num_steps = num_steps(scene);
  s.integrator = scene.integrator;
  s.mass = scene.mass;
  s.d_hat = scene.d_hat;
  s.friction_eps_v = scene.friction_eps_v;
  s.friction_iterations = scene.friction_iterations;
  const auto coefficients = friction_coefficients(scene);
  s.friction = coefficients.empty() ? scene.friction : coefficients.front().second;
  for (const auto& [who, mu] : coefficients) {
    if (mu != s.friction) {
      std::ostringstream msg;
      msg << scene.source << ": PolyFEM has one friction coefficient for every contact, but "
          << coefficients.front().first << " has " << s.friction << " and " << who << " has " << mu
          << " (make them equal, e.g. --set=contact.friction=" << s.friction << ")";
      throw InputError(msg.str());
    }
  }
  return s;
}

}  // namespace rbaa
