#include "rbaa/opt/attack_problem.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "rbaa/diff/cholmod_factor.hpp"
#include "rbaa/error.hpp"
#include "rbaa/scene/scene_mesh.hpp"
#include "rbaa/scene/scene_world.hpp"
#include "rbaa/sim/mass_matrix.hpp"
#include "rbaa/sim/observables.hpp"

namespace rbaa {

namespace {

Eigen::VectorXd positions(const TetMesh& mesh) {
  return Eigen::Map<const Eigen::VectorXd>(mesh.V.data(), 3 * mesh.num_vertices());
}

bool covers(const Body& b, const TetMesh& mesh) {
  return b.element_begin == 0 && b.element_end == mesh.num_tets() && b.vertex_begin == 0 &&
         b.vertex_end == mesh.num_vertices();
}

// Body b's own mesh, cut out of the stacked one (its own vertex indices).
TetMesh cut_body(const TetMesh& stacked, const Body& b) {
  if (covers(b, stacked)) return stacked;
  TetMesh m;
  m.V = stacked.V.middleRows(b.vertex_begin, b.num_vertices());
  m.T = stacked.T.middleRows(b.element_begin, b.num_elements()).array() - b.vertex_begin;
  return m;
}

// A per-element density that is zero outside body b (unchanged when b is the whole mesh).
Eigen::VectorXd only_body(Eigen::VectorXd density, const Body& b) {
  for (int e = 0; e < density.size(); ++e) {
    if (e < b.element_begin || e >= b.element_end) density[e] = 0.0;
  }
  return density;
}

void copy_elements(MaterialField& to, int to_begin, const MaterialField& from, int from_begin,
                   int n) {
  to.Y.segment(to_begin, n) = from.Y.segment(from_begin, n);
  to.nu.segment(to_begin, n) = from.nu.segment(from_begin, n);
  to.rho.segment(to_begin, n) = from.rho.segment(from_begin, n);
  to.alpha.segment(to_begin, n) = from.alpha.segment(from_begin, n);
}

// The world's design space, masked to A, its elements outside A holding the reference
// materials, and the same layout on A's own mesh.
void make_designs(AttackProblem& p, const DesignSpaceOptions& options) {
  const Body& a = p.body();
  std::vector<char> mask(p.world.mesh.num_tets(), 0);
  for (int e = a.element_begin; e < a.element_end; ++e) mask[e] = 1;
  // The drive holds A by its driven vertices: their elements stay solid (not designed), so that
  // the continuous design is the object rounding keeps (every driven vertex stays in it).
  DesignSpaceOptions world_options = options;
  world_options.solid_vertices = a.driven_vertices;
  p.design = std::make_unique<DesignSpace>(p.world.mesh, world_options, std::move(mask));
  p.design->hold_fixed_elements(p.reference_materials);
  DesignSpaceOptions body_options = options;
  body_options.solid_vertices.clear();
  for (int v : a.driven_vertices) body_options.solid_vertices.push_back(v - a.vertex_begin);
  p.body_design = std::make_unique<DesignSpace>(p.body_mesh, body_options);
}

}  // namespace

int body_index(const Scene& scene, const std::string& name, const std::string& what) {
  if (name == scene.object_name) return 0;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    if (scene.bodies[i].name == name) return static_cast<int>(i) + 1;
  }
  throw InputError(what + "=" + name + ": the scene has no such body");
}

Eigen::Vector3d body_centre_of_mass(const Eigen::VectorXd& q, const TetMesh& mesh,
                                    const Eigen::VectorXd& density, const Body& body) {
  return centre_of_mass(q, vertex_masses(mesh, only_body(density, body)));
}

std::shared_ptr<const TrajectoryObjective> make_objective(
    const ObjectiveSpec& spec, const TetMesh& mesh, const std::vector<Body>& bodies, int scored,
    double reference_rho, const Eigen::VectorXd& reference_final,
    const Eigen::Vector3d& scored_reference_com, double scored_length) {
  const Body& b = bodies.at(scored);
  if (spec.kind == ObjectiveSpec::Kind::kUndirected) {
    return UndirectedTrajectoryObjective::from_reference(mesh, reference_rho, reference_final, b);
  }
  if (!(scored_length > 0) || !std::isfinite(scored_length)) {
    throw InputError("objective: body " + b.name + " has no positive radius of gyration");
  }
  // Dimensionless like the undirected term: centre-of-mass distances over L_B.
  const double w = 1.0 / (scored_length * scored_length);
  std::vector<DirectedObjective::Term> terms;
  if (spec.kind == ObjectiveSpec::Kind::kTarget) {
    const Eigen::Vector3d axis = Eigen::Vector3d::Unit(spec.component);
    terms.push_back({std::make_shared<CentreOfMassObservable>(mesh, b, axis), spec.value, w});
  } else {
    // -|c_B(T) - c_B,ref(T)|^2 / L^2 as sum_i (-1 / L^2) (c_B,i - c_B,ref,i)^2.
    for (int i = 0; i < 3; ++i) {
      terms.push_back({std::make_shared<CentreOfMassObservable>(mesh, b, Eigen::Vector3d::Unit(i)),
                       scored_reference_com[i], -w});
    }
  }
  return std::make_shared<DirectedObjective>(std::move(terms));
}

MaterialField AttackProblem::world_materials(const MaterialField& body_field,
                                             const std::string& source) const {
  validate_material_field(body_field, body().num_elements(), source);
  MaterialField all = reference_materials;
  copy_elements(all, body().element_begin, body_field, 0, body().num_elements());
  return all;
}

MaterialField AttackProblem::body_materials(const MaterialField& world_field) const {
  MaterialField m = MaterialField::uniform(body().num_elements(), 1, 0.3, 1);
  copy_elements(m, 0, world_field, body().element_begin, body().num_elements());
  return m;
}

BodyFinalState AttackProblem::final_state(const Eigen::VectorXd& q_final,
                                          const MaterialField& materials) const {
  BodyFinalState s;
  const Eigen::VectorXd density = materials.effective_density();
  s.gap = gap->gap(q_final);
  s.com_gap = (body_centre_of_mass(q_final, world.mesh, density, body()) - reference_com).norm();
  s.scored_com = body_centre_of_mass(q_final, world.mesh, density, world.bodies[scored]);
  return s;
}

ReferenceRun AttackProblem::run_reference(const SimulationSettings& run_settings,
                                          const ReferenceRunner& runner) const {
  ReferenceRun r;
  r.simulator = std::make_unique<Simulator>(world.mesh, reference_materials, run_settings,
                                            scene.source + " (reference material)");
  r.trajectory = runner ? runner(*r.simulator, q0, v0) : r.simulator->run(q0, v0);
  const Eigen::VectorXd& q_final = r.trajectory.q.back();
  const Eigen::VectorXd density = reference_materials.effective_density();
  r.com = body_centre_of_mass(q_final, world.mesh, density, body());
  r.scored_com = body_centre_of_mass(q_final, world.mesh, density, world.bodies[scored]);
  return r;
}

BodyRun AttackProblem::simulate(const MaterialField& body_field) const {
  const MaterialField materials = world_materials(body_field);
  Simulator sim(world.mesh, materials, settings);
  const Trajectory run = sim.run(q0, v0);
  BodyRun r;
  r.objective = objective->evaluate(run, materials, nullptr);
  r.state = final_state(run.q.back(), materials);
  return r;
}

void AttackProblem::start_from(double Y0, double nu0) {
  scene.Y0 = Y0;
  scene.nu0 = nu0;
  DesignSpaceOptions o = design->options();
  o.Y0 = Y0;
  o.nu0 = nu0;
  make_designs(*this, o);
  if (gradient) gradient = make_gradient(storage);
}

std::unique_ptr<TrajectoryGradientFunction> AttackProblem::make_gradient(
    FactorStorage factor_storage) const {
  return std::make_unique<TrajectoryGradientFunction>(world.mesh, settings, q0, v0, *design,
                                                      objective, factor_storage);
}

ReplacedWorld AttackProblem::with_body(const TetMesh& mesh, const MaterialField& materials,
                                       const std::vector<int>& vertex_origin,
                                       const Eigen::VectorXd* reference_final) const {
  validate_material_field(materials, mesh.num_tets(), "the replaced body's materials");
  if (static_cast<int>(vertex_origin.size()) != mesh.num_vertices()) {
    throw InputError("with_body: vertex_origin does not fit the mesh");
  }
  ReplacedWorld r;
  std::vector<TetMesh> meshes;
  int vertices = 0, elements = 0;
  for (std::size_t i = 0; i < world.bodies.size(); ++i) {
    const Body& old = world.bodies[i];
    meshes.push_back(static_cast<int>(i) == attacked ? mesh : cut_body(world.mesh, old));
    Body b = old;
    b.vertex_begin = vertices;
    b.element_begin = elements;
    vertices += meshes.back().num_vertices();
    elements += meshes.back().num_tets();
    b.vertex_end = vertices;
    b.element_end = elements;
    // Driven vertices are stacked-mesh ids: shift them with the body, and through vertex_origin
    // for the replaced one (its new vertex v is its old local vertex vertex_origin[v]).
    std::vector<int> local(old.num_vertices(), -1);
    if (static_cast<int>(i) == attacked) {
      for (int v = 0; v < static_cast<int>(vertex_origin.size()); ++v) {
        if (vertex_origin[v] >= 0 && vertex_origin[v] < old.num_vertices()) local[vertex_origin[v]] = v;
      }
    } else {
      for (int v = 0; v < old.num_vertices(); ++v) local[v] = v;
    }
    for (int& d : b.driven_vertices) {
      const int v = local.at(d - old.vertex_begin);
      if (v < 0) throw InputError("with_body: a driven vertex of " + old.name + " is not in the replacing mesh");
      d = b.vertex_begin + v;
    }
    r.bodies.push_back(b);
  }
  r.mesh.V.resize(vertices, 3);
  r.mesh.T.resize(elements, 4);
  r.materials = MaterialField::uniform(elements, 1, 0.3, 1);
  const Eigen::VectorXd& q_ref = reference_final ? *reference_final : reference.q.back();
  if (q_ref.size() != 3 * world.mesh.num_vertices()) {
    throw InputError("with_body: the reference's final positions do not fit the world");
  }
  r.reference_final.resize(3 * vertices);
  for (std::size_t i = 0; i < r.bodies.size(); ++i) {
    const Body& b = r.bodies[i];
    const Body& old = world.bodies[i];
    r.mesh.V.middleRows(b.vertex_begin, b.num_vertices()) = meshes[i].V;
    r.mesh.T.middleRows(b.element_begin, b.num_elements()) = meshes[i].T.array() + b.vertex_begin;
    if (static_cast<int>(i) == attacked) {
      copy_elements(r.materials, b.element_begin, materials, 0, b.num_elements());
      for (int v = 0; v < b.num_vertices(); ++v) {
        r.reference_final.segment<3>(3 * (b.vertex_begin + v)) =
            q_ref.segment<3>(3 * (old.vertex_begin + vertex_origin[v]));
      }
    } else {
      copy_elements(r.materials, b.element_begin, reference_materials, old.element_begin,
                    b.num_elements());
      r.reference_final.segment(3 * b.vertex_begin, 3 * b.num_vertices()) =
          q_ref.segment(3 * old.vertex_begin, 3 * old.num_vertices());
    }
  }
  r.settings = settings;
  const bool driven = std::any_of(r.bodies.begin(), r.bodies.end(), [](const Body& b) { return b.is_driven(); });
  r.settings.bodies = r.bodies.size() > 1 || driven ? r.bodies : std::vector<Body>{};
  r.q0 = positions(r.mesh);
  r.v0 = initial_velocities(r.q0, r.bodies);
  r.gap = UndirectedTrajectoryObjective::from_reference(r.mesh, scene.reference_rho,
                                                        r.reference_final, r.bodies[attacked]);
  r.objective = scored == attacked && scene.objective.kind == ObjectiveSpec::Kind::kUndirected
                    ? r.gap
                    : make_objective(scene.objective, r.mesh, r.bodies, scored, scene.reference_rho,
                                     r.reference_final, scored_reference_com, scored_length);
  return r;
}

AttackProblem build_attack_problem(const Scene& scene, const AttackProblemOptions& options) {
  auto stage = [&](const std::string& s) {
    if (options.on_stage) options.on_stage(s);
  };
  AttackProblem p;
  p.scene = scene;
  p.attacked =
      body_index(scene, options.attacked_body.empty() ? scene.attack_body : options.attacked_body,
                 options.attacked_body.empty() ? "attack.body" : "--body");
  p.scored = scene.objective.body.empty()
                 ? p.attacked
                 : body_index(scene, scene.objective.body, "objective.body");

  stage("meshing the reference object");
  const TetMesh object_mesh = options.object_mesh ? *options.object_mesh : make_scene_mesh(scene);
  p.kappa = options.kappa > 0 ? options.kappa : scene_barrier_stiffness(scene, object_mesh);
  p.world = make_world(scene, object_mesh);
  const Body& a = p.body();
  const Body& b = p.world.bodies[p.scored];
  p.body_mesh = cut_body(p.world.mesh, a);
  p.settings = simulation_settings(scene, p.kappa);
  p.settings.bodies = simulated_bodies(p.world);  // several bodies, or a driven one
  p.q0 = positions(p.world.mesh);
  p.v0 = initial_velocities(p.q0, p.world.bodies);

  // The reference: A uniform at the reference material (what the attack designs from), every
  // other body as the scene gives it.
  const MaterialField uniform = MaterialField::uniform(
      a.num_elements(), scene.reference_Y, scene.reference_nu, scene.reference_rho, 1.0);
  p.reference_materials = p.world.materials(
      MaterialField::uniform(p.world.bodies.front().num_elements(), scene.reference_Y,
                             scene.reference_nu, scene.reference_rho, 1.0));
  copy_elements(p.reference_materials, a.element_begin, uniform, 0, a.num_elements());
  p.reference_moments = compute_moments(p.body_mesh, uniform.effective_density());

  stage("simulating the reference object");
  ReferenceRun reference = p.run_reference(p.settings, options.run_reference);
  p.reference_simulator = std::move(reference.simulator);
  p.reference = std::move(reference.trajectory);
  p.reference_com = reference.com;
  p.scored_reference_com = reference.scored_com;
  const Eigen::VectorXd& q_ref = p.reference.q.back();
  p.scored_length = radius_of_gyration(compute_moments(
      p.world.mesh,
      only_body(Eigen::VectorXd::Constant(p.world.mesh.num_tets(), scene.reference_rho), b)));

  p.gap =
      UndirectedTrajectoryObjective::from_reference(p.world.mesh, scene.reference_rho, q_ref, a);
  p.objective =
      p.scored == p.attacked && scene.objective.kind == ObjectiveSpec::Kind::kUndirected
          ? p.gap
          : make_objective(scene.objective, p.world.mesh, p.world.bodies, p.scored,
                           scene.reference_rho, q_ref, p.scored_reference_com, p.scored_length);

  DesignSpaceOptions design_options = design_space_options(scene);
  if (!options.fields.empty()) design_options.fields = options.fields;
  make_designs(p, design_options);

  p.storage = options.storage;
  if (p.storage == FactorStorage::kStore) {
    const std::size_t estimate =
        CholmodFactor::bytes_of(p.reference_simulator->newton().linear_solver().cholmod_factor()) *
        std::size_t(p.reference.num_steps());
    if (estimate > options.stored_factor_budget) {
      p.storage = FactorStorage::kRebuild;
      std::ostringstream note;
      note << "stored factors would take " << std::setprecision(3) << estimate / 1e9
           << " GB: rebuilt";
      p.storage_note = note.str();
    }
  }
  if (options.with_gradient) p.gradient = p.make_gradient(p.storage);
  return p;
}

}  // namespace rbaa
