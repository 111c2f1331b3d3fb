#include "rbaa/opt/attack.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "rbaa/diff/trajectory_gradient.hpp"
#include "rbaa/diff/trajectory_objective.hpp"
#include "rbaa/error.hpp"
#include "rbaa/geometry/smoothing.hpp"
#include "rbaa/io/atomic_file.hpp"
#include "rbaa/io/materials_io.hpp"
#include "rbaa/io/tet_mesh_file.hpp"
#include "rbaa/io/vtu.hpp"
#include "rbaa/opt/attack_problem.hpp"
#include "rbaa/opt/density_refit.hpp"
#include "rbaa/scene/scene_fingerprint.hpp"
#include "rbaa/scene/scene_world.hpp"
#include "rbaa/sim/mass_matrix.hpp"
#include "rbaa/sim/observables.hpp"
#include "rbaa/sim/simulator.hpp"

namespace rbaa {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

double max_normalized_residual(const Moments& m, const Moments& reference) {
  return ((m.as_vector() - reference.as_vector()).array() / moment_normalisation(reference).array())
      .abs()
      .maxCoeff();
}


AttackLoopOptions attack_loop_options(const Scene& scene, const AttackOptions& options, const std::string& prefix) {
  AttackLoopOptions loop;
  loop.iterations = scene.iterations;
  loop.beta = scene.beta;
  loop.adam.learning_rate = scene.learning_rate;
  loop.adam.beta1 = scene.adam_beta1;
  loop.adam.beta2 = scene.adam_beta2;
  loop.fingerprint = options.fingerprint + (prefix.empty() ? "" : ":" + prefix);
  loop.resume = options.resume;
  loop.project_moments = scene.project_moments;
  loop.on_iteration = options.on_iteration;
  if (!options.out_dir.empty()) {
    loop.checkpoint_path = options.out_dir + "/" + prefix + "checkpoint.json";
    loop.progress_path = options.out_dir + "/" + prefix + "progress.csv";
  }
  return loop;
}

// The loop's trajectory term: C_traj and its gradient from f, plus the gaps a progress row reports
// (the attacked body's mass-weighted gap and centre-of-mass distance to the reference's).
// `scored_com`, if given, receives the scored body's final centre of mass of every evaluation.
TrajectoryTerm trajectory_term(
    TrajectoryGradientFunction& f,
    std::function<BodyFinalState(const Eigen::VectorXd&, const MaterialField&)> final_state,
    Eigen::Vector3d* scored_com = nullptr) {
  return [&f, final_state, scored_com](const Eigen::VectorXd& theta, Eigen::VectorXd* gradient) {
    TrajectoryTermValue v;
    v.value = f.evaluate(theta, gradient);
    const TrajectoryEvaluation& e = f.last();
    const BodyFinalState s = final_state(e.trajectory.q.back(), e.materials);
    v.gap = s.gap;
    v.com_gap = s.com_gap;
    if (scored_com != nullptr) *scored_com = s.scored_com;
    v.forward_seconds = e.forward_seconds;
    v.adjoint_seconds = e.adjoint_seconds + e.objective_seconds;
    return v;
  };
}

struct FinalGap {
  double gap = 0;      ///< m
  double com_gap = 0;  ///< m
  Eigen::Vector3d scored_com = Eigen::Vector3d::Zero();  ///< the scored body's at T (m)
  double objective = 0;                                  ///< the objective's trajectory term
};

// A reference run at a finer step (the refinement check): the step divisor, the run's final
// positions and the attacked body's centre of mass at T.
struct RefinedReference {
  int factor = 1;
  Eigen::VectorXd final_positions;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
};

SimulationSettings refined_settings(SimulationSettings s, int factor) {
  s.time_step /= factor;
  s.num_steps *= factor;
  return s;
}

// The object without its voids, simulated from the scene's initial state with the other bodies;
// its gap is measured on the material points it shares with the reference (the kept vertices),
// mass-weighted by the reference: d^T Mref d over the kept vertices, element by element,
// (m_e / 20)(1 + delta_ab) d_a . d_b. With `refined`, both runs are at the finer step.
FinalGap measure_solid(const AttackProblem& problem,
                       const Eigen::VectorXd& reference_element_masses, const SolidObject& solid,
                       const RefinedReference* refined = nullptr) {
  const TetMesh& mesh = problem.body_mesh;
  ReplacedWorld world = problem.with_body(solid.mesh, solid.materials, solid.vertex_origin,
                                          refined ? &refined->final_positions : nullptr);
  if (refined) world.settings = refined_settings(world.settings, refined->factor);
  const Body& body = world.bodies[problem.attacked];
  Simulator sim(world.mesh, world.materials, world.settings);
  const Trajectory run = sim.run(world.q0, world.v0);
  const Eigen::VectorXd d = (run.q.back() - world.reference_final)
                                .segment(3 * body.vertex_begin, 3 * body.num_vertices());
  std::vector<int> slot(mesh.num_vertices(), -1);
  for (size_t i = 0; i < solid.vertex_origin.size(); ++i) slot[solid.vertex_origin[i]] = static_cast<int>(i);
  double weighted = 0, kept_mass = 0;
  for (int e = 0; e < mesh.num_tets(); ++e) {
    for (int a = 0; a < 4; ++a) {
      const int sa = slot[mesh.T(e, a)];
      if (sa < 0) continue;
      for (int b = 0; b < 4; ++b) {
        const int sb = slot[mesh.T(e, b)];
        if (sb < 0) continue;
        const double w = reference_element_masses[e] / 20.0 * (a == b ? 2.0 : 1.0);
        weighted += w * d.segment<3>(3 * sa).dot(d.segment<3>(3 * sb));
        kept_mass += w;
      }
    }
  }
  FinalGap g;
  g.gap = std::sqrt(std::max(0.0, weighted) / kept_mass);
  // The attacked body's vertex masses only (all of them for a single body).
  Eigen::VectorXd masses = sim.vertex_masses();
  for (int v = 0; v < masses.size(); ++v) {
    if (v < body.vertex_begin || v >= body.vertex_end) masses[v] = 0.0;
  }
  g.com_gap = (centre_of_mass(run.q.back(), masses) - (refined ? refined->com : problem.reference_com)).norm();
  g.scored_com = body_centre_of_mass(run.q.back(), world.mesh, world.materials.effective_density(),
                                     world.bodies[problem.scored]);
  g.objective = world.objective->evaluate(run, world.materials, nullptr);
  return g;
}

// The solid object's elements and materials, bit for bit: what the polish starts from.
std::string solid_object_fingerprint(const SolidObject& solid) {
  std::string bytes;
  auto append = [&bytes](const void* data, size_t size) {
    bytes.append(static_cast<const char*>(data), size);
  };
  append(solid.element_origin.data(),
         solid.element_origin.size() * sizeof(solid.element_origin[0]));
  const MaterialField& m = solid.materials;
  for (const Eigen::VectorXd* x : {&m.Y, &m.nu, &m.rho, &m.alpha}) {
    append(x->data(), static_cast<size_t>(x->size()) * sizeof(double));
  }
  return fingerprint_hex(bytes);
}

// Moves every optimised value at least 1e-9 of its range inside it, so that the tanh map can be
// inverted (a value can sit on a bound to round-off after the re-fit).
MaterialField inside_bounds(MaterialField m, const DesignSpace& design) {
  auto nudge = [](Eigen::VectorXd& x, const TanhBoxMap& map) {
    const double margin = 1e-9 * (map.hi() - map.lo());
    x = x.cwiseMax(map.lo() + margin).cwiseMin(map.hi() - margin);
  };
  if (design.optimises(DesignField::kY)) nudge(m.Y, design.map(DesignField::kY));
  if (design.optimises(DesignField::kNu)) nudge(m.nu, design.map(DesignField::kNu));
  if (design.optimises(DesignField::kRho)) nudge(m.rho, design.map(DesignField::kRho));
  return m;
}

// The polish stage: rounding and the connectivity repair change the design the loop found (the
// ball's 50-iteration design lost 85 % of its gap to them: pieces of its shell cut loose under it,
// hinged on edges and vertices, that the repair joins; attack.occupancy_penalty.repair_in_loop
// keeps them joined during the loop). With the occupancy now fixed, a few more Adam
// iterations on Y, nu and rho of the solid object, moments projected as in the main loop, recover
// what these fields can. The polished object replaces the post-processed one only if its gap is
// larger.
void polish(AttackResult& r, const AttackProblem& problem, const AttackOptions& options,
            const Eigen::VectorXd& reference_element_masses,
            const Moments& centred_reference_moments,
            const std::function<void(const std::string&)>& stage) {
  const Scene& scene = problem.scene;
  DesignSpaceOptions po = design_space_options(scene);
  po.fields.erase(std::remove(po.fields.begin(), po.fields.end(), DesignField::kAlpha), po.fields.end());
  if (po.fields.empty()) return;
  po.perturbation = 0;
  const SolidObject& solid = r.post.solid;
  // The fields the polish does not move (alpha, and any the attack left out) are the solid
  // object's, not the design space's initial ones (a field left out of attack.fields, say rho,
  // would otherwise come back uniform at reference_rho, undoing the re-fit).
  DesignSpace design(solid.mesh, po);
  design.hold_fixed_fields(solid.materials);
  const Eigen::VectorXd theta0 = design.to_theta(inside_bounds(solid.materials, design));

  // The solid object in the world (alone, or among the scene's other bodies), the design masked
  // to it: the same layout as `design`.
  const ReplacedWorld world = problem.with_body(solid.mesh, solid.materials, solid.vertex_origin);
  const Body& body = world.bodies[problem.attacked];
  std::vector<char> mask(world.mesh.num_tets(), 0);
  for (int e = body.element_begin; e < body.element_end; ++e) mask[e] = 1;
  DesignSpace world_design(world.mesh, po, std::move(mask));
  world_design.hold_fixed_elements(world.materials);
  world_design.hold_fixed_fields(world.materials);
  TrajectoryGradientFunction f(world.mesh, world.settings, world.q0, world.v0, world_design,
                               world.objective, options.storage);
  TetMesh centred = solid.mesh;
  centred.V.rowwise() -= r.reference_moments.centre_of_mass().transpose();
  const MomentCostFunction moments(centred, design, centred_reference_moments);
  const TrajectoryTerm term = trajectory_term(f, [&world, &body, &problem](const Eigen::VectorXd& q,
                                                                           const MaterialField& m) {
    BodyFinalState s;
    s.gap = world.gap->gap(q);
    s.com_gap =
        (body_centre_of_mass(q, world.mesh, m.effective_density(), body) - problem.reference_com)
            .norm();
    return s;
  });
  AttackLoopOptions loop = attack_loop_options(scene, options, "polish_");
  loop.iterations = scene.polish_iterations;
  // A polish checkpoint belongs to the solid object it started from, which the scene's
  // fingerprint does not name (a resume may extend attack.iterations, or go on after stopping
  // early): its fingerprint names the start too, and one of another start is polished over. Whether
  // the main loop moved on in this process does not tell: a resume that extended the loop and was
  // killed before the polish's first checkpoint left the old object's one for the next resume,
  // which adds nothing to the loop (it then polished the new object from the old one's design).
  loop.fingerprint += ":start " + solid_object_fingerprint(solid);
  loop.restart_on_other_fingerprint = true;
  stage("polishing Y, nu, rho of the solid object (" + std::to_string(loop.iterations) + " iterations, " +
        std::to_string(design.size()) + " design variables)");
  r.polish = run_attack_loop(design, moments, nullptr, term, theta0, loop);
  if (!r.polish.stopped_early.empty()) {
    stage("polish stopped early, keeping its last design whose simulation succeeded: " + r.polish.stopped_early);
  }

  SolidObject polished = solid;
  polished.materials = design.to_material(r.polish.theta);
  FinalGap g;
  DensityRefitResult refit;
  try {
    // The retraction leaves the moments about the reference centre matched to ~1e-12; the re-fit
    // brings those about the origin within the post-process's tolerance as well.
    refit = refit_density(polished.mesh, polished.materials.alpha, polished.materials.rho,
                          r.reference_moments, design.map(DesignField::kRho));
    polished.materials.rho = refit.rho;
    stage("simulating the polished object");
    g = measure_solid(problem, reference_element_masses, polished);
  } catch (const SolverError& e) {
    // The polish's last design is simulated only here, after its re-fit: if either fails, the
    // post-processed object stays the result instead of the whole attack failing at its end.
    r.polish_failure = e.what();
    stage("the polished object failed, keeping the post-processed object: " + r.polish_failure);
    return;
  }
  r.polish_gap = g.gap;
  // The undirected attack wants the larger gap; any other objective its lower value.
  const bool undirected = problem.scored == problem.attacked &&
                          scene.objective.kind == ObjectiveSpec::Kind::kUndirected;
  r.polish_kept =
      undirected ? g.gap > r.gap_post_processed : g.objective < r.objective_post_processed;
  if (r.polish_kept) {
    for (size_t i = 0; i < polished.element_origin.size(); ++i) {
      const int e = polished.element_origin[i];
      r.post.rounded.Y[e] = polished.materials.Y[i];
      r.post.rounded.nu[e] = polished.materials.nu[i];
      r.post.rounded.rho[e] = polished.materials.rho[i];
    }
    r.post.solid = std::move(polished);
    // The report's re-fit is the final object's: the polished one's own.
    r.post.max_residual_before_refit = refit.initial_max_residual;
    r.post.refit = std::move(refit);
    r.gap_final = g.gap;
    r.com_gap_final = g.com_gap;
    r.scored_com_final = g.scored_com;
    r.objective_final_object = g.objective;
  }
}

// Survival under refinement (issue 20 item 5): the reference and the final object re-simulated at
// the attack's step divided by attack.refinement_factor, the object's gap measured against that
// reference. A gap that lives on the step size (an impact's phase within a step, SPEC section 2)
// shrinks here; one that belongs to the object stays. A run that fails is reported, not thrown:
// the attack's result stands without it.
void refinement_check(AttackResult& r, const AttackProblem& problem,
                      const Eigen::VectorXd& reference_element_masses,
                      const std::function<void(const std::string&)>& stage) {
  RefinementCheck& c = r.refinement;
  c.factor = problem.scene.refinement_factor;
  c.time_step = problem.settings.time_step / c.factor;
  c.gap_at_attack_step = r.gap_final;
  std::ostringstream what;
  what << "re-simulating the reference and the final object at h / " << c.factor << " = "
       << c.time_step << " s";
  stage(what.str());
  const auto start = std::chrono::steady_clock::now();
  try {
    const ReferenceRun run = problem.run_reference(refined_settings(problem.settings, c.factor));
    RefinedReference ref;
    ref.factor = c.factor;
    ref.final_positions = run.trajectory.q.back();
    ref.com = run.com;
    c.reference_com_shift = (ref.com - problem.reference_com).norm();
    c.scored_com_reference = run.scored_com;
    const FinalGap g = measure_solid(problem, reference_element_masses, r.post.solid, &ref);
    c.gap = g.gap;
    c.com_gap = g.com_gap;
    c.scored_com_final = g.scored_com;
    c.objective = g.objective;
    c.measured = true;
  } catch (const SolverError& e) {
    c.failure = e.what();
    stage("the refinement check failed (the result stands without it): " + c.failure);
  }
  c.seconds = seconds_since(start);
}

}  // namespace

AttackResult run_attack(const Scene& scene, const AttackOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  auto stage = [&](const std::string& s) {
    if (options.on_stage) options.on_stage(s);
  };
  if (scene.friction_iterations > 1) {
    throw InputError(scene.source + ": contact.friction_iterations " +
                     std::to_string(scene.friction_iterations) +
                     " re-lags friction within each step, which only forward runs (simulate, "
                     "evaluate) do: an attack's gradient takes the lag at q_n (set 1)");
  }
  AttackResult r;
  // Mesh, kappa, settings, reference run, objective, design: the attacked body A is designed in
  // the scene's world (alone, or among its further bodies, which keep their materials).
  AttackProblemOptions problem_options;
  problem_options.storage = options.storage;
  problem_options.on_stage = stage;
  AttackProblem problem = build_attack_problem(scene, problem_options);
  if (scene.start_best_uniform) {
    // Issue 20 item 3: start from the uniform material the objective likes best.
    stage("evaluating 9 uniform starts (Y, nu at the ends and middle of their ranges)");
    r.start = find_best_uniform_start(problem, [&stage](const UniformCandidate& c) {
      std::ostringstream line;
      line.precision(4);
      line << "  uniform Y = " << c.Y << " Pa, nu = " << c.nu << ": objective " << c.objective
           << ", gap " << c.gap << " m";
      stage(line.str());
    });
    const UniformCandidate& best = r.start.best();
    problem.start_from(best.Y, best.nu);
    std::ostringstream line;
    line.precision(4);
    line << "starting from the best uniform material Y = " << best.Y << " Pa, nu = " << best.nu
         << " (objective " << best.objective << ", gap " << best.gap << " m)";
    stage(line.str());
  }
  auto name = [&scene](int i) { return body_name(scene, i); };
  r.attacked_body = name(problem.attacked);
  r.scored_body = name(problem.scored);
  r.mesh = problem.body_mesh;
  r.kappa = problem.kappa;
  r.reference_moments = problem.reference_moments;
  r.reference_steps = problem.reference.num_steps();
  r.reference_resolving = problem.reference.resolving;
  r.scored_com_reference = problem.scored_reference_com;
  const MaterialField reference_materials = problem.body_materials(problem.reference_materials);

  TrajectoryGradientFunction& f = *problem.gradient;
  // Moments, smoothing and post-processing work on A's own mesh, in the same layout as the
  // world's masked design that f maps theta with.
  const DesignSpace& design = *problem.body_design;
  r.start_Y = design.initial_material().Y[0];
  r.start_nu = design.initial_material().nu[0];
  // The moment term measures moments about the reference's centre of mass: the same zero set as
  // about the origin (an invertible linear map of the 10 moments), but with the object far from the
  // origin (the ball: 3.4 m, L = 0.075 m) the rows about the origin amplify first- and second-moment
  // errors by |c| / L and (|c| / L)^2 ~ 2000, so beta would mean something different in every scene.
  TetMesh centred = r.mesh;
  centred.V.rowwise() -= r.reference_moments.centre_of_mass().transpose();
  const Moments centred_reference_moments = compute_moments(centred, reference_materials.effective_density());
  const MomentCostFunction moments(centred, design, centred_reference_moments);
  const Eigen::VectorXd reference_element_masses = element_masses(r.mesh, reference_materials.effective_density());
  std::unique_ptr<GradientSmoother> smoother;
  if (design.optimises(DesignField::kAlpha)) smoother = std::make_unique<GradientSmoother>(r.mesh, scene.smoothing_gamma);

  Eigen::Vector3d scored_com = Eigen::Vector3d::Zero();
  const TrajectoryTerm term = trajectory_term(
      f,
      [&problem](const Eigen::VectorXd& q, const MaterialField& m) {
        return problem.final_state(q, m);
      },
      &scored_com);

  // The occupancy penalty's P and grey fraction are reported whenever alpha is designed; its
  // term joins the descent only with attack.occupancy_penalty.weight > 0.
  std::unique_ptr<OccupancyPenalty> occupancy;
  if (design.optimises(DesignField::kAlpha)) {
    occupancy = std::make_unique<OccupancyPenalty>(
        r.mesh, design, scene.round_threshold,
        OccupancyPenaltyOptions{scene.occupancy_weight, scene.occupancy_connectivity_weight,
                                scene.occupancy_ramp_start, scene.occupancy_ramp_end,
                                scene.occupancy_repair_in_loop});
  }
  AttackLoopOptions loop = attack_loop_options(scene, options, "");
  loop.occupancy = occupancy.get();
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
  TrajectoryTermValue final_value;
  try {
    final_value = term(r.loop.theta, nullptr);
  } catch (const SolverError& e) {
    // A run resumed after it had stopped early, with no iterations left, ends on its checkpoint's
    // next design, which is the one that failed: keep the last design that simulated instead.
    if (r.loop.evaluated_theta.size() == 0 || r.loop.evaluated_theta == r.loop.theta) throw;
    r.loop.stopped_early = e.what();
    r.loop.failed_theta = r.loop.theta;
    r.loop.theta = r.loop.evaluated_theta;
    stage("stopped early, keeping the last design whose simulation succeeded: " + r.loop.stopped_early);
    final_value = term(r.loop.theta, nullptr);
  }
  r.objective_final = final_value.value + moments.penalty(r.loop.theta, scene.beta, nullptr);
  // Stopped early, the loop's theta is its last evaluated design (progress.back()'s).
  r.kept_iteration = static_cast<int>(r.loop.progress.size()) - (r.loop.stopped_early.empty() ? 0 : 1);
  const int best = r.loop.best_iteration;
  if (scene.start_best_uniform && best >= 0 && best != r.kept_iteration &&
      r.loop.progress[best].objective < r.objective_final) {
    // The attack must not end below its start (issue 20 item 3): Adam's last step can overshoot,
    // so the best evaluated design is the result when the last one is worse.
    std::ostringstream line;
    line.precision(6);
    line << "the last design (objective " << r.objective_final << ") is worse than iteration "
         << best << "'s (" << r.loop.progress[best].objective << "): keeping iteration " << best << "'s";
    stage(line.str());
    r.loop.theta = r.loop.best_theta;
    r.kept_iteration = best;
    final_value = term(r.loop.theta, nullptr);
    r.objective_final = final_value.value + moments.penalty(r.loop.theta, scene.beta, nullptr);
  }
  r.gap_continuous = final_value.gap;
  r.com_gap_continuous = final_value.com_gap;
  r.scored_com_continuous = scored_com;
  r.continuous = design.to_material(r.loop.theta);
  if (r.loop.failed_theta.size() > 0) r.failed = design.to_material(r.loop.failed_theta);
  r.continuous_max_residual = moments.residuals(r.loop.theta).cwiseAbs().maxCoeff();
  if (occupancy) {
    r.occupancy_penalty_continuous = occupancy->value(r.loop.theta);
    r.grey_fraction_continuous = occupancy->grey_fraction(r.loop.theta);
    r.repair_share_continuous =
        occupancy->repair_share(r.loop.theta, nullptr, &r.components_continuous);
  }

  // The optimised design is written before post-processing, which can fail (a density re-fit that
  // cannot match the moments with the rounded occupancy): hours of iterations are never lost to it.
  std::string continuous_path;
  if (!options.out_dir.empty()) {
    continuous_path = options.out_dir + "/continuous.msh";
    write_tet_mesh(continuous_path, r.mesh, material_element_data(r.continuous));
  }
  stage("post-processing: rounding, connectivity, density re-fit");
  try {
    // The design holds the driven vertices' elements solid: they stay in the object.
    r.post = post_process(r.mesh, design, r.continuous, r.reference_moments, scene.round_threshold);
  } catch (const SolverError& e) {
    if (continuous_path.empty()) throw;
    throw SolverError(std::string(e.what()) + "; the optimised continuous design is kept in " + continuous_path);
  }

  stage("simulating the post-processed object");
  const FinalGap post_gap = measure_solid(problem, reference_element_masses, r.post.solid);
  r.gap_post_processed = post_gap.gap;
  r.com_gap_post_processed = post_gap.com_gap;
  r.objective_post_processed = post_gap.objective;
  r.gap_final = post_gap.gap;
  r.com_gap_final = post_gap.com_gap;
  r.scored_com_final = post_gap.scored_com;
  r.objective_final_object = post_gap.objective;

  if (scene.polish_iterations > 0 && design.optimises(DesignField::kAlpha)) {
    polish(r, problem, options, reference_element_masses, centred_reference_moments, stage);
  }
  if (scene.refinement_factor > 1) refinement_check(r, problem, reference_element_masses, stage);
  r.adversarial_moments = compute_moments(r.post.solid.mesh, r.post.solid.materials.effective_density());
  r.max_normalized_residual = max_normalized_residual(r.adversarial_moments, r.reference_moments);

  r.forward_seconds = r.loop.forward_seconds + r.polish.forward_seconds;
  r.adjoint_seconds = r.loop.adjoint_seconds + r.polish.adjoint_seconds;
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
  nlohmann::json report = {
      {"scene", scene.name},
      {"config", scene.source},
      {"iterations", static_cast<int>(r.loop.progress.size())},
      {"stopped_early", r.loop.stopped_early.empty() ? nlohmann::json(nullptr)
                                                     : nlohmann::json(r.loop.stopped_early)},
      {"kappa", r.kappa},
      {"fields", scene.fields},
      {"settings",
       {{"beta", scene.beta},
        {"learning_rate", scene.learning_rate},
        {"adam_beta1", scene.adam_beta1},
        {"adam_beta2", scene.adam_beta2},
        {"seed", scene.seed},
        {"perturbation", scene.perturbation},
        {"alpha0", scene.alpha0},
        {"smoothing_gamma", scene.smoothing_gamma},
        {"round_threshold", scene.round_threshold},
        {"occupancy_penalty",
         {{"weight", scene.occupancy_weight},
          {"connectivity_weight", scene.occupancy_connectivity_weight},
          {"ramp_start", scene.occupancy_ramp_start},
          {"ramp_end", scene.occupancy_ramp_end},
          {"repair_in_loop", scene.occupancy_repair_in_loop}}},
        {"project_moments", scene.project_moments},
        {"polish_iterations", scene.polish_iterations},
        {"time_step", scene.time_step},
        {"contact_substeps", scene.contact_substeps},
        {"reference_steps_taken", r.reference_steps},
        {"reference_steps_shorter_than_h", r.reference_resolving.refined_steps},
        {"reference_contacts", r.reference_resolving.contacts},
        {"duration", scene.duration}}},
      {"mesh",
       {{"tets", r.mesh.num_tets()},
        {"vertices", r.mesh.num_vertices()},
        {"final_tets", solid.mesh.num_tets()},
        {"final_vertices", solid.mesh.num_vertices()}}},
      {"moments",
       {{"reference", to_vec(r.reference_moments)},
        {"adversarial", to_vec(r.adversarial_moments)},
        {"max_normalized_residual", r.max_normalized_residual},
        {"continuous_max_normalized_residual", r.continuous_max_residual}}},
      {"gap",
       {{"initial", r.gap_initial},
        {"continuous", r.gap_continuous},
        {"final", r.gap_final},
        {"com_initial", r.com_gap_initial},
        {"com_continuous", r.com_gap_continuous},
        {"com_final", r.com_gap_final},
        {"post_processed", r.gap_post_processed},
        {"com_post_processed", r.com_gap_post_processed}}},
      {"polish",
       {{"iterations", static_cast<int>(r.polish.progress.size())},
        {"gap", r.polish.progress.empty() || !r.polish_failure.empty()
                    ? nlohmann::json(nullptr)
                    : nlohmann::json(r.polish_gap)},
        {"kept", r.polish_kept},
        {"failed",
         r.polish_failure.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.polish_failure)},
        {"stopped_early", r.polish.stopped_early.empty()
                              ? nlohmann::json(nullptr)
                              : nlohmann::json(r.polish.stopped_early)}}},
      {"objective",
       {{"initial", r.objective_initial},
        {"final", r.objective_final},
        {"kind", objective_kind_name(scene.objective.kind)},
        {"body", r.scored_body},
        {"final_object", r.objective_final_object}}},
      {"attacked_body", r.attacked_body},
      {"loop", {{"kept_iteration", r.kept_iteration}}},
      {"occupancy",
       {{"void_fraction", r.post.void_fraction},
        {"penalty_continuous", r.occupancy_penalty_continuous},
        {"grey_fraction_continuous", r.grey_fraction_continuous},
        {"repair_share_continuous", r.repair_share_continuous},
        {"components_continuous", r.components_continuous},
        {"components",
         {{"before", r.post.connectivity.components_before},
          {"after", r.post.connectivity.components_after}}},
        {"elements_added", r.post.connectivity.elements_added}}},
      {"refit",
       {{"object", r.polish_kept ? "polished" : "post-processed"},
        {"max_residual_before", r.post.max_residual_before_refit},
        {"max_residual_after", refit.max_residual},
        {"iterations", refit.iterations}}},
      {"materials",
       {{"Y", range(solid.materials.Y)},
        {"nu", range(solid.materials.nu)},
        {"rho", range(solid.materials.rho)},
        {"alpha", range(solid.materials.alpha)}}},
      {"timing",
       {{"forward_s", r.forward_seconds},
        {"adjoint_s", r.adjoint_seconds},
        {"refinement_s", r.refinement.seconds},
        {"total_s", r.total_seconds}}}};
  auto vec = [](const Eigen::Vector3d& v) { return std::vector<double>{v.x(), v.y(), v.z()}; };
  {
    // The loop's start; with best_uniform the candidates it was chosen from.
    nlohmann::json start = {{"kind", scene.start_best_uniform ? "best_uniform" : "given"},
                            {"Y", r.start_Y},
                            {"nu", r.start_nu}};
    if (!r.start.candidates.empty()) {
      start["objective"] = r.start.best().objective;
      start["gap"] = r.start.best().gap;
      nlohmann::json candidates = nlohmann::json::array();
      for (const UniformCandidate& c : r.start.candidates) {
        candidates.push_back({{"Y", c.Y}, {"nu", c.nu}, {"objective", c.objective}, {"gap", c.gap}});
      }
      start["candidates"] = candidates;
    }
    report["start"] = start;
  }
  {
    const RefinementCheck& c = r.refinement;
    auto measured = [&c](double x) { return c.measured ? nlohmann::json(x) : nlohmann::json(nullptr); };
    report["refinement"] = {
        {"factor", c.factor},
        {"time_step", c.factor > 0 ? nlohmann::json(c.time_step) : nlohmann::json(nullptr)},
        {"gap_at_attack_step", c.factor > 0 ? nlohmann::json(c.gap_at_attack_step) : nlohmann::json(nullptr)},
        {"gap", measured(c.gap)},
        {"com_gap", measured(c.com_gap)},
        {"kept_fraction", measured(c.gap_at_attack_step > 0 ? c.gap / c.gap_at_attack_step : 0.0)},
        {"reference_com_shift", measured(c.reference_com_shift)},
        {"objective", measured(c.objective)},
        {"failed", c.failure.empty() ? nlohmann::json(nullptr) : nlohmann::json(c.failure)}};
    if (c.measured && scene.objective.kind != ObjectiveSpec::Kind::kUndirected) {
      report["refinement"]["scored_centre_of_mass"] = {{"reference", vec(c.scored_com_reference)},
                                                       {"final", vec(c.scored_com_final)}};
    }
  }
  if (scene.objective.kind != ObjectiveSpec::Kind::kUndirected) {
    // Where the scored body's centre of mass ended (m): the directed attack's own measure.
    report["score"] = {{"body", r.scored_body},
                       {"kind", objective_kind_name(scene.objective.kind)},
                       {"centre_of_mass",
                        {{"reference", vec(r.scored_com_reference)},
                         {"continuous", vec(r.scored_com_continuous)},
                         {"final", vec(r.scored_com_final)}}}};
    if (scene.objective.kind == ObjectiveSpec::Kind::kTarget) {
      report["score"]["component"] = std::string(1, "xyz"[scene.objective.component]);
      report["score"]["value"] = scene.objective.value;
    }
  }
  write_file_atomically(dir + "/report.json", [&](std::ostream& out) { out << report.dump(2) << "\n"; });
}

}  // namespace rbaa
