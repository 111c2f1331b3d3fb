#include "rbaa/scene/simulate.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include "rbaa/error.hpp"
#include "rbaa/io/atomic_file.hpp"
#include "rbaa/io/csv.hpp"
#include "rbaa/io/vtu.hpp"
#include "rbaa/sim/barrier_stiffness.hpp"
#include "rbaa/sim/threads.hpp"
#include "rbaa/sim/vertex_plane.hpp"

namespace rbaa {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

const char* integrator_name(Integrator i) { return i == Integrator::kBdf2 ? "bdf2" : "bdf1"; }
const char* mass_name(MassModel m) { return m == MassModel::kConsistent ? "consistent" : "lumped"; }

nlohmann::json vec3(const Eigen::Vector3d& v) { return {v[0], v[1], v[2]}; }

// The contact distances of positions q: per plane (the object's surface only when there are
// further bodies: bounces are the object's) and the smallest to anything.
StepObservables contact_distances(Simulator& sim, const Eigen::VectorXd& q,
                                  const std::vector<Body>& bodies) {
  const ContactSet& set = sim.contact_form().contact_set();
  const Body& object = bodies.front();
  StepObservables o;
  // Bounces are the object's: with further bodies, only its surface vertices count.
  if (bodies.size() > 1) {
    o.plane_distance.assign(set.planes().size(), std::numeric_limits<double>::infinity());
    for (int v : set.surface_vertices()) {
      if (v < object.vertex_begin || v >= object.vertex_end) continue;
      for (std::size_t p = 0; p < set.planes().size(); ++p) {
        o.plane_distance[p] = std::min(o.plane_distance[p], vertex_plane_distance(q.segment<3>(3 * v), set.planes()[p]));
      }
    }
  } else {
    o.plane_distance = set.min_distance_per_plane(q);
  }
  o.min_distance = set.min_distance(q);
  // Mesh obstacles: the closest pair within d_hat (beyond it, the planes' figure stands).
  if (const MeshObstacleForm* mesh = sim.mesh_obstacle_form()) {
    o.min_distance = std::min(o.min_distance, mesh->min_distance(q));
  }
  if (const BodyContactForm* pairs = sim.body_contact_form()) {
    o.min_distance = std::min(o.min_distance, pairs->min_distance(q));
  }
  return o;
}

}  // namespace

std::vector<StepObservables> compute_observables(Simulator& simulator,
                                                 const Trajectory& trajectory) {
  Simulator& sim = simulator;
  const Eigen::VectorXd& masses = sim.vertex_masses();
  // On the grid of h only: the rigid twin and the bounce detection compare runs step by step.
  // With contact-resolving steps the distances of a position of the grid are the smallest over
  // the sub-steps since the previous one, so that an impact shorter than h still shows.
  const std::vector<int> frames = trajectory.grid_frames();
  std::vector<StepObservables> out(frames.size());
  std::vector<Body> bodies = sim.settings().bodies;
  if (bodies.empty()) {
    Body whole;
    whole.vertex_end = sim.rest_mesh().num_vertices();
    whole.element_end = sim.rest_mesh().num_tets();
    bodies.push_back(whole);
  }
  const Body& object = bodies.front();
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const int k = frames[i];
    const Eigen::VectorXd& q = trajectory.q[k];
    const Eigen::VectorXd v = trajectory.velocity(k);
    const Eigen::VectorXd Mv = sim.inertia_form().multiply(v);
    StepObservables& o = out[i];
    o.time = trajectory.time(k);
    // The object's motion (the first body's), the whole system's momenta.
    const auto m = masses.segment(object.vertex_begin, object.num_vertices());
    const auto part = [&](const Eigen::VectorXd& x) {
      return Eigen::VectorXd(x.segment(3 * object.vertex_begin, 3 * object.num_vertices()));
    };
    o.centre_of_mass = centre_of_mass(part(q), m);
    o.com_velocity = centre_of_mass(part(v), m);
    o.linear_momentum = linear_momentum(Mv);
    o.angular_momentum = angular_momentum(q, Mv);
    o.orientation = best_fit_rotation(part(trajectory.q[0]), part(q), m);
    for (std::size_t b = 1; b < bodies.size(); ++b) {
      const Body& body = bodies[b];
      o.body_centres.push_back(centre_of_mass(
          q.segment(3 * body.vertex_begin, 3 * body.num_vertices()),
          masses.segment(body.vertex_begin, body.num_vertices())));
    }
    const StepObservables d = contact_distances(sim, q, bodies);
    o.plane_distance = d.plane_distance;
    o.min_distance = d.min_distance;
    for (int j = i == 0 ? k : frames[i - 1] + 1; j < k; ++j) {
      const StepObservables sub = contact_distances(sim, trajectory.q[j], bodies);
      o.min_distance = std::min(o.min_distance, sub.min_distance);
      for (std::size_t p = 0; p < o.plane_distance.size(); ++p)
        o.plane_distance[p] = std::min(o.plane_distance[p], sub.plane_distance[p]);
    }
  }
  return out;
}

namespace {

// report.json's `contact_resolving`: steps taken, sub-steps per contact, what refinement cost.
nlohmann::json contact_resolving_json(const Trajectory& t) {
  const ContactResolvingStats& c = t.resolving;
  const int substeps = c.refined_steps;  // steps shorter than h
  return {{"substeps", c.substeps},
          {"steps_taken", t.num_steps()},
          {"steps_of_h", static_cast<int>(t.grid.size()) - 1},
          {"sub_steps", substeps},
          {"contacts", c.contacts},
          {"sub_steps_per_contact", c.contacts ? double(substeps) / c.contacts : 0.0},
          {"predicted_halvings", c.predicted_halvings},
          {"rejected_steps", c.rejected_steps},
          {"rejected_newton_iterations", c.rejected_newton_iterations},
          {"rejected_s", c.rejected_seconds}};
}

}  // namespace

SimulationRun run_simulation(const Scene& scene, const TetMesh& placed_mesh,
                             const MaterialField& materials, const SimulationOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  SimulationRun run;
  double kappa = options.kappa;
  if (!(kappa > 0)) {
    run.kappa_from_rule = !(scene.kappa > 0);
    kappa = scene_barrier_stiffness(scene, placed_mesh);
  }
  run.settings = simulation_settings(scene, kappa);
  // Further bodies are stacked after the object, with their own fixed materials.
  const SceneWorld world = make_world(scene, placed_mesh);
  run.mesh = world.mesh;
  run.materials = world.materials(materials, scene.source + " (materials)");
  run.bodies = world.bodies;
  run.settings.bodies = simulated_bodies(world);
  Simulator sim(run.mesh, run.materials, run.settings, scene.source + " (materials)");
  if (options.on_newton_iteration) sim.newton().set_iteration_callback(options.on_newton_iteration);
  run.vertex_masses = sim.vertex_masses();
  const Eigen::VectorXd q0 = sim.rest_positions();
  const Eigen::VectorXd v0 = initial_velocities(q0, world.bodies);
  run.setup_seconds = seconds_since(t0);

  const auto t1 = std::chrono::steady_clock::now();
  run.trajectory = sim.run(q0, v0, options.on_step);
  run.simulate_seconds = seconds_since(t1);

  run.observables = compute_observables(sim, run.trajectory);
  std::vector<std::vector<double>> distances;
  std::vector<Eigen::Vector3d> velocities;
  for (const StepObservables& o : run.observables) {
    distances.push_back(o.plane_distance);
    velocities.push_back(o.com_velocity);
  }
  run.bounces = find_bounces(distances, velocities, run.settings.planes, run.settings.d_hat,
                             run.settings.gravity, run.settings.time_step);
  return run;
}

void write_simulation_outputs(const SimulationRun& run, const Scene& scene, const std::string& dir,
                              const OutputOptions& options) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir + ": cannot create the output directory (" + ec.message() + ")");
  const Trajectory& t = run.trajectory;
  const int n = static_cast<int>(t.q.size());

  // Per-step CSV.
  // com and q: the object's; p and L: the whole system's; then each further body's centre.
  std::vector<std::string> header = {
      "step", "time", "com_x", "com_y", "com_z", "p_x", "p_y", "p_z", "L_x", "L_y", "L_z",
      "q_w", "q_x", "q_y", "q_z", "min_distance", "newton_iterations"};
  const int further = n > 0 ? static_cast<int>(run.observables[0].body_centres.size()) : 0;
  for (int b = 0; b < further; ++b) {
    for (const char* axis : {"_com_x", "_com_y", "_com_z"}) header.push_back(scene.bodies[b].name + axis);
  }
  // One row per step of h (the observables' grid); a sub-stepped step's Newton iterations summed.
  const std::vector<int> grid = t.grid_frames();
  const int rows_n = static_cast<int>(run.observables.size());
  Eigen::MatrixXd rows(rows_n, header.size());
  for (int k = 0; k < rows_n; ++k) {
    const StepObservables& o = run.observables[k];
    int iterations = 0;
    for (int j = k == 0 ? 0 : grid[k - 1]; k > 0 && j < grid[k]; ++j) iterations += t.steps[j].newton_iterations;
    rows.row(k).head(17) << k, o.time, o.centre_of_mass.transpose(), o.linear_momentum.transpose(),
        o.angular_momentum.transpose(), o.orientation.w(), o.orientation.x(), o.orientation.y(),
        o.orientation.z(), std::isfinite(o.min_distance) ? o.min_distance : -1.0, iterations;
    for (int b = 0; b < further; ++b) rows.row(k).segment<3>(17 + 3 * b) = o.body_centres[b].transpose();
  }
  write_csv((fs::path(dir) / "trajectory.csv").string(), header, rows);

  // ParaView series: deformed positions, displacement from q_0, velocity; materials per cell.
  std::vector<std::pair<double, std::string>> frames;
  if (options.vtu_every > 0) {
    fs::create_directories(fs::path(dir) / "frames", ec);
    if (ec) throw InputError(dir + "/frames: cannot create (" + ec.message() + ")");
    VtuFields cells;
    cells["Y"] = run.materials.Y;
    cells["nu"] = run.materials.nu;
    cells["rho"] = run.materials.rho;
    cells["alpha"] = run.materials.alpha;
    const int nv = run.mesh.num_vertices();
    for (int k = 0; k < n; k += options.vtu_every) {
      Vertices V = Eigen::Map<const Vertices>(t.q[k].data(), nv, 3);
      const Eigen::VectorXd v = t.velocity(k);
      VtuFields points;
      points["displacement"] = Eigen::Map<const Vertices>(t.q[k].data(), nv, 3) -
                               Eigen::Map<const Vertices>(t.q[0].data(), nv, 3);
      points["velocity"] = Eigen::Map<const Vertices>(v.data(), nv, 3);
      char name[32];
      std::snprintf(name, sizeof name, "frame_%05d.vtu", k);
      write_vtu((fs::path(dir) / "frames" / name).string(), V, run.mesh.T, points, cells);
      frames.emplace_back(t.time(k), std::string("frames/") + name);
    }
    write_pvd((fs::path(dir) / "trajectory.pvd").string(), frames);
  }

  // report.json
  nlohmann::json r;
  r["scene"] = scene.name;
  r["config"] = scene.source;
  r["mesh"] = {{"vertices", run.mesh.num_vertices()}, {"tets", run.mesh.num_tets()}};
  r["steps"] = t.num_steps();
  r["time_step"] = t.time_step;
  r["duration"] = t.time(t.num_steps());
  r["integrator"] = integrator_name(run.settings.integrator);
  if (t.resolving.substeps > 0) r["contact_resolving"] = contact_resolving_json(t);
  r["mass"] = mass_name(run.settings.mass);
  r["kappa"] = run.settings.kappa;
  r["kappa_source"] = run.kappa_from_rule ? "energy rule (SPEC 2)" : "config";
  r["d_hat"] = run.settings.d_hat;
  std::vector<int> iterations;
  StepStats sum;  // the run's counts and seconds
  int max_it = 0, exact = 0, floor_limited = 0;
  double floor_velocity = 0;
  double dmin = std::numeric_limits<double>::infinity();
  for (const StepStats& s : t.steps) {
    iterations.push_back(s.newton_iterations);
    sum += s;
    max_it = std::max(max_it, s.newton_iterations);
    exact += s.exact_factor ? 1 : 0;
    if (s.roundoff_limited) {
      ++floor_limited;
      floor_velocity = std::max(floor_velocity, s.floor_velocity);
    }
    dmin = std::min(dmin, s.min_distance);
  }
  // newton.tolerance is relative: Newton stops when ||dq||_inf / h is below it times the rest
  // mesh's bounding-box diagonal (m/s); both are reported.
  r["newton"] = {{"tolerance", run.settings.newton_tolerance},
                 {"tolerance_m_per_s", run.settings.newton_tolerance * bounding_box_diagonal(run.mesh)},
                 {"max_iterations", run.settings.newton_max_iterations},
                 {"iterations_per_step", iterations},
                 {"total_iterations", sum.newton_iterations},
                 {"max_iterations_in_a_step", max_it},
                 {"steps_ending_with_exact_factor", exact},
                 {"steps_stopped_at_roundoff_floor", floor_limited},
                 {"roundoff_floor_m_per_s", floor_velocity},
                 {"friction_iterations", run.settings.friction_iterations},
                 {"friction_relags", sum.friction_relags},
                 {"line_search_probes", sum.line_search_probes},
                 {"symbolic_analyses", sum.symbolic_analyses},
                 {"ccd_caps", sum.ccd_caps},
                 {"seconds", {{"gradients", sum.gradient_seconds},
                              {"assembly", sum.assembly_seconds},
                              {"factorisations", sum.factorization_seconds},
                              {"solves", sum.solve_seconds},
                              {"line_search", sum.line_search_seconds}}}};
  r["min_contact_distance"] = std::isfinite(dmin) ? nlohmann::json(dmin) : nlohmann::json(nullptr);
  nlohmann::json bounces = nlohmann::json::array();
  // One entry per contact episode; only a one-plane contact whose normal velocity reversed has a
  // restitution, every other kind says why it has none.
  for (const Bounce& b : run.bounces) {
    nlohmann::json entry = {
        {"kind", bounce_kind_name(b.kind)},
        {"planes", b.planes},
        {"first_step", b.first_step},
        {"last_step", b.last_step},
        {"time", run.observables.at(b.first_step).time},
        {"normal_velocity_in", b.normal_velocity_in},
        {"normal_velocity_out", b.normal_velocity_out},
        {"restitution",
         b.kind == BounceKind::kBounce ? nlohmann::json(b.restitution) : nlohmann::json(nullptr)}};
    if (!b.note.empty()) entry["note"] = b.note;
    bounces.push_back(entry);
  }
  r["bounces"] = bounces;
  const StepObservables& last = run.observables.back();
  r["final"] = {{"centre_of_mass", vec3(last.centre_of_mass)},
                {"velocity", vec3(last.com_velocity)},
                {"orientation_wxyz",
                 {last.orientation.w(), last.orientation.x(), last.orientation.y(), last.orientation.z()}}};
  r["timing"] = {{"setup_s", run.setup_seconds},
                 {"simulate_s", run.simulate_seconds},
                 {"per_step_s", t.num_steps() ? sum.seconds / t.num_steps() : 0.0},
                 {"per_iteration_s",
                  sum.newton_iterations ? sum.seconds / sum.newton_iterations : 0.0},
                 {"threads", simulation_threads()}, {"thread_setup", thread_setup()}};
  write_file_atomically((fs::path(dir) / "report.json").string(),
                        [&](std::ostream& os) { os << r.dump(2) << "\n"; });
}

Eigen::Vector3d body_velocity(const SimulationRun& run, int b, int frame) {
  const Eigen::VectorXd& v = run.trajectory.velocity(frame);
  if (run.bodies.empty()) return centre_of_mass(v, run.vertex_masses);
  const Body& body = run.bodies.at(b);
  return centre_of_mass(v.segment(3 * body.vertex_begin, 3 * body.num_vertices()),
                        run.vertex_masses.segment(body.vertex_begin, body.num_vertices()));
}

}  // namespace rbaa
