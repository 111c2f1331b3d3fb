#include "rbaa/opt/attack.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>

#include "rbaa/diff/trajectory_gradient.hpp"
#include "rbaa/diff/trajectory_objective.hpp"
#include "rbaa/error.hpp"
#include "rbaa/geometry/smoothing.hpp"
#include "rbaa/io/atomic_file.hpp"
#include "rbaa/io/materials_io.hpp"
#include "rbaa/io/tet_mesh_file.hpp"
#include "rbaa/io/vtu.hpp"
#include "rbaa/scene/scene_mesh.hpp"
#include "rbaa/sim/barrier_stiffness.hpp"
#include "rbaa/sim/mass_matrix.hpp"
#include "rbaa/sim/observables.hpp"
#include "rbaa/sim/simulator.hpp"

namespace rbaa {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

Eigen::VectorXd positions(const TetMesh& mesh) {
  return Eigen::Map<const Eigen::VectorXd>(mesh.V.data(), 3 * mesh.num_vertices());
}

double max_normalized_residual(const Moments& m, const Moments& reference) {
  return ((m.as_vector() - reference.as_vector()).array() / moment_normalisation(reference).array())
      .abs()
      .maxCoeff();
}

}  // namespace

AttackResult run_attack(const Scene& scene, const AttackOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  auto stage = [&](const std::string& s) {
    if (options.on_stage) options.on_stage(s);
  };
  AttackResult r;
  stage("meshing the reference object");
  r.mesh = make_scene_mesh(scene);
  r.kappa = scene_barrier_stiffness(scene, r.mesh);
  const SimulationSettings settings = simulation_settings(scene, r.kappa);
  const Eigen::VectorXd q0 = positions(r.mesh);
  const Eigen::VectorXd v0 = rigid_velocities(q0, scene.position, scene.velocity, scene.angular_velocity);
  const MaterialField reference_materials = MaterialField::uniform(
      r.mesh.num_tets(), scene.reference_Y, scene.reference_nu, scene.reference_rho, 1.0);
  r.reference_moments = compute_moments(r.mesh, reference_materials.effective_density());

  stage("simulating the reference object");
  Simulator reference_sim(r.mesh, reference_materials, settings);
  const Trajectory reference = reference_sim.run(q0, v0);
  const Eigen::VectorXd& q_ref = reference.q.back();
  const Eigen::VectorXd ref_masses = vertex_masses(r.mesh, reference_materials.effective_density());
  const Eigen::Vector3d ref_com = centre_of_mass(q_ref, ref_masses);
  auto objective = UndirectedTrajectoryObjective::from_reference(r.mesh, scene.reference_rho, q_ref);

  const DesignSpace design(r.mesh, DesignSpaceOptions::from_scene(scene));
  TrajectoryGradientFunction f(r.mesh, settings, q0, v0, design, objective, options.storage);
  // The moment term measures moments about the reference's centre of mass: the same zero set as
  // about the origin (an invertible linear map of the 10 moments), but with the object far from the
  // origin (the ball: 3.4 m, L = 0.075 m) the rows about the origin amplify first- and second-moment
  // errors by |c| / L and (|c| / L)^2 ~ 2000, so beta would mean something different in every scene.
  TetMesh centred = r.mesh;
  centred.V.rowwise() -= r.reference_moments.centre_of_mass().transpose();
  const MomentCostFunction moments(centred, design, compute_moments(centred, reference_materials.effective_density()));
  std::unique_ptr<GradientSmoother> smoother;
  if (design.optimises(DesignField::kAlpha)) smoother = std::make_unique<GradientSmoother>(r.mesh, scene.smoothing_gamma);

  auto com_gap = [&](const Trajectory& t, const MaterialField& m) {
    return (centre_of_mass(t.q.back(), vertex_masses(r.mesh, m.effective_density())) - ref_com).norm();
  };
  const TrajectoryTerm term = [&](const Eigen::VectorXd& theta, Eigen::VectorXd* gradient) {
    TrajectoryTermValue v;
    v.value = f.evaluate(theta, gradient);
    const TrajectoryEvaluation& e = f.last();
    v.gap = objective->gap(e.trajectory.q.back());
    v.com_gap = com_gap(e.trajectory, e.materials);
    v.forward_seconds = e.forward_seconds;
    v.adjoint_seconds = e.adjoint_seconds + e.objective_seconds;
    return v;
  };

  AttackLoopOptions loop;
  loop.iterations = scene.iterations;
  loop.beta = scene.beta;
  loop.adam.learning_rate = scene.learning_rate;
  loop.adam.beta1 = scene.adam_beta1;
  loop.adam.beta2 = scene.adam_beta2;
  loop.fingerprint = options.fingerprint;
  loop.resume = options.resume;
  loop.project_moments = scene.project_moments;
  loop.on_iteration = options.on_iteration;
  if (!options.out_dir.empty()) {
    loop.checkpoint_path = options.out_dir + "/checkpoint.json";
    loop.progress_path = options.out_dir + "/progress.csv";
  }
  const Eigen::VectorXd theta0 = design.initial_theta(true);
  stage("optimising (" + std::to_string(scene.iterations) + " iterations, " + std::to_string(design.size()) +
        " design variables)");
  r.loop = run_attack_loop(design, moments, smoother.get(), term, theta0, loop);
  if (!r.loop.stopped_early.empty()) {
    stage("stopped early, keeping the last design whose simulation succeeded: " + r.loop.stopped_early);
  }

  // The initial gap is the first iteration's; without iterations it is measured here.
  if (!r.loop.progress.empty()) {
    r.gap_initial = r.loop.progress.front().gap;
    r.com_gap_initial = r.loop.progress.front().com_gap;
    r.objective_initial = r.loop.progress.front().objective;
  } else {
    const TrajectoryTermValue v = term(r.loop.theta, nullptr);  // theta_0, retracted by the loop
    r.gap_initial = v.gap;
    r.com_gap_initial = v.com_gap;
    r.objective_initial = v.value + moments.penalty(r.loop.theta, scene.beta, nullptr);
  }
  const TrajectoryTermValue final_value = term(r.loop.theta, nullptr);
  r.gap_continuous = final_value.gap;
  r.com_gap_continuous = final_value.com_gap;
  r.objective_final = final_value.value + moments.penalty(r.loop.theta, scene.beta, nullptr);
  r.continuous = design.to_material(r.loop.theta);
  if (r.loop.failed_theta.size() > 0) r.failed = design.to_material(r.loop.failed_theta);
  r.continuous_max_residual = moments.residuals(r.loop.theta).cwiseAbs().maxCoeff();

  stage("post-processing: rounding, connectivity, density re-fit");
  r.post = post_process(r.mesh, design, r.continuous, r.reference_moments, scene.round_threshold);
  r.adversarial_moments = compute_moments(r.post.solid.mesh, r.post.solid.materials.effective_density());
  r.max_normalized_residual = max_normalized_residual(r.adversarial_moments, r.reference_moments);

  // The final object without its voids, simulated again; its gap is measured on the material
  // points it shares with the reference (the kept vertices), mass-weighted by the reference.
  stage("simulating the final object");
  const SolidObject& solid = r.post.solid;
  Simulator final_sim(solid.mesh, solid.materials, settings);
  const Eigen::VectorXd q0s = positions(solid.mesh);
  const Trajectory final_run =
      final_sim.run(q0s, rigid_velocities(q0s, scene.position, scene.velocity, scene.angular_velocity));
  const int ns = solid.mesh.num_vertices();
  Eigen::VectorXd d(3 * ns);
  for (int i = 0; i < ns; ++i) {
    d.segment<3>(3 * i) = final_run.q.back().segment<3>(3 * i) - q_ref.segment<3>(3 * solid.vertex_origin[i]);
  }
  // d^T Mref d over the kept vertices, element by element: (m_e / 20)(1 + delta_ab) d_a . d_b.
  std::vector<int> slot(r.mesh.num_vertices(), -1);
  for (int i = 0; i < ns; ++i) slot[solid.vertex_origin[i]] = i;
  const Eigen::VectorXd m_e = element_masses(r.mesh, reference_materials.effective_density());
  double weighted = 0, kept_mass = 0;
  for (int e = 0; e < r.mesh.num_tets(); ++e) {
    for (int a = 0; a < 4; ++a) {
      const int sa = slot[r.mesh.T(e, a)];
      if (sa < 0) continue;
      for (int b = 0; b < 4; ++b) {
        const int sb = slot[r.mesh.T(e, b)];
        if (sb < 0) continue;
        const double w = m_e[e] / 20.0 * (a == b ? 2.0 : 1.0);
        weighted += w * d.segment<3>(3 * sa).dot(d.segment<3>(3 * sb));
        kept_mass += w;
      }
    }
  }
  r.gap_final = std::sqrt(std::max(0.0, weighted) / kept_mass);
  r.com_gap_final =
      (centre_of_mass(final_run.q.back(), vertex_masses(solid.mesh, solid.materials.effective_density())) - ref_com).norm();

  r.forward_seconds = r.loop.forward_seconds;
  r.adjoint_seconds = r.loop.adjoint_seconds;
  // Wall time of the whole attack, including iterations done before a resume.
  double resumed_seconds = r.loop.elapsed_seconds;
  for (size_t k = static_cast<size_t>(r.loop.resumed_from); k < r.loop.progress.size(); ++k) {
    resumed_seconds -= r.loop.progress[k].seconds;
  }
  r.total_seconds = seconds_since(start) + resumed_seconds;
  return r;
}

void write_attack_outputs(const AttackResult& r, const Scene& scene, const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir + ": cannot create output folder (" + ec.message() + ")");
  const SolidObject& solid = r.post.solid;
  write_tet_mesh(dir + "/adversarial.msh", solid.mesh, material_element_data(solid.materials));
  write_tet_mesh(dir + "/continuous.msh", r.mesh, material_element_data(r.continuous));
  // The design the simulator failed on, for `rbaa simulate --materials=DIR/failed_design.msh`.
  if (r.failed.size() > 0) write_tet_mesh(dir + "/failed_design.msh", r.mesh, material_element_data(r.failed));
  VtuFields cells;
  for (const auto& [name, values] : material_element_data(solid.materials)) cells[name] = values;
  write_vtu(dir + "/adversarial.vtu", solid.mesh, {}, cells);

  auto to_vec = [](const Moments& m) {
    const MomentVector v = m.as_vector();
    return std::vector<double>(v.data(), v.data() + 10);
  };
  auto range = [](const Eigen::VectorXd& x) { return nlohmann::json{{"min", x.minCoeff()}, {"max", x.maxCoeff()}}; };
  const auto& refit = r.post.refit;
  const nlohmann::json report = {
      {"scene", scene.name},
      {"config", scene.source},
      {"iterations", static_cast<int>(r.loop.progress.size())},
      {"stopped_early", r.loop.stopped_early.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.loop.stopped_early)},
      {"kappa", r.kappa},
      {"fields", scene.fields},
      {"settings", {{"beta", scene.beta}, {"learning_rate", scene.learning_rate}, {"adam_beta1", scene.adam_beta1},
                    {"adam_beta2", scene.adam_beta2}, {"seed", scene.seed}, {"perturbation", scene.perturbation},
                    {"alpha0", scene.alpha0}, {"smoothing_gamma", scene.smoothing_gamma},
                    {"round_threshold", scene.round_threshold}, {"project_moments", scene.project_moments},
                    {"time_step", scene.time_step},
                    {"duration", scene.duration}}},
      {"mesh", {{"tets", r.mesh.num_tets()}, {"vertices", r.mesh.num_vertices()},
                {"final_tets", solid.mesh.num_tets()}, {"final_vertices", solid.mesh.num_vertices()}}},
      {"moments", {{"reference", to_vec(r.reference_moments)},
                   {"adversarial", to_vec(r.adversarial_moments)},
                   {"max_normalized_residual", r.max_normalized_residual},
                   {"continuous_max_normalized_residual", r.continuous_max_residual}}},
      {"gap", {{"initial", r.gap_initial}, {"continuous", r.gap_continuous}, {"final", r.gap_final},
               {"com_initial", r.com_gap_initial}, {"com_continuous", r.com_gap_continuous},
               {"com_final", r.com_gap_final}}},
      {"objective", {{"initial", r.objective_initial}, {"final", r.objective_final}}},
      {"occupancy", {{"void_fraction", r.post.void_fraction},
                     {"components", {{"before", r.post.connectivity.components_before},
                                     {"after", r.post.connectivity.components_after}}},
                     {"elements_added", r.post.connectivity.elements_added}}},
      {"refit", {{"max_residual_before", r.post.max_residual_before_refit},
                 {"max_residual_after", refit.max_residual}, {"iterations", refit.iterations}}},
      {"materials", {{"Y", range(solid.materials.Y)}, {"nu", range(solid.materials.nu)},
                     {"rho", range(solid.materials.rho)}, {"alpha", range(solid.materials.alpha)}}},
      {"timing", {{"forward_s", r.forward_seconds}, {"adjoint_s", r.adjoint_seconds}, {"total_s", r.total_seconds}}}};
  write_file_atomically(dir + "/report.json", [&](std::ostream& out) { out << report.dump(2) << "\n"; });
}

}  // namespace rbaa
