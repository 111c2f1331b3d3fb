#pragma once
// `rbaa attack` as a library call (SPEC sections 4 and 5): from a scene to an adversarial object.
// The problem (mesh, kappa, reference run, objective, design) is opt/attack_problem.hpp's; in a
// scene with further bodies the attacked body A is designed among them and the objective may
// score another body B.
//
//   reference run -> Adam on C = C_traj + beta ||r||^2 (forward + adjoint per iteration, smoothed
//   occupancy gradient, checkpoints) -> rounding, connectivity, density re-fit, void removal ->
//   re-simulation -> optional polish (Adam on Y, nu, rho of the solid object, occupancy fixed;
//   kept only if it widens the gap) -> the final object.

#include <Eigen/Core>

#include <functional>
#include <string>
#include <vector>

#include "rbaa/diff/adjoint.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/material/material_field.hpp"
#include "rbaa/mesh/tet_mesh.hpp"
#include "rbaa/opt/attack_loop.hpp"
#include "rbaa/opt/post_process.hpp"
#include "rbaa/opt/uniform_start.hpp"
#include "rbaa/scene/scene.hpp"
#include "rbaa/sim/trajectory.hpp"

namespace rbaa {

struct AttackOptions {
  std::string out_dir;          ///< checkpoint.json and progress.csv go here (empty: none)
  bool resume = false;
  std::string fingerprint;      ///< identifies scene and settings for --resume
  FactorStorage storage = FactorStorage::kStore;
  /// Progress after every iteration (row, iterations in all).
  std::function<void(const ProgressRow&, int)> on_iteration;
  /// Free-form stage messages ("reference run", "post-processing", ...).
  std::function<void(const std::string&)> on_stage;
};

/// The final object and the reference re-simulated at a finer step (attack.refinement_factor).
struct RefinementCheck {
  int factor = 0;          ///< the attack's step divided by this; 0: not done
  double time_step = 0;    ///< s
  bool measured = false;   ///< false when not done or a run failed (failure says why)
  std::string failure;
  double gap_at_attack_step = 0;  ///< the final object's gap at the attack's step (m)
  double gap = 0, com_gap = 0;    ///< the final object's gap at the finer step (m)
  double reference_com_shift = 0;  ///< |c_A,ref(T) at the finer step - at the attack's| (m)
  Eigen::Vector3d scored_com_reference = Eigen::Vector3d::Zero();  ///< c_B(T), finer step
  Eigen::Vector3d scored_com_final = Eigen::Vector3d::Zero();
  double objective = 0;  ///< the final object's trajectory term at the finer step
  double seconds = 0;
};

struct AttackResult {
  std::string attacked_body;  ///< the designed body A ("object" or its bodies[].name)
  std::string scored_body;    ///< the objective's body B
  TetMesh mesh;               ///< A's placed reference mesh (the design's domain)
  double kappa = 0;
  Moments reference_moments;
  /// The reference run's steps taken and, with contact-resolving steps, what they did.
  int reference_steps = 0;
  ContactResolvingStats reference_resolving;
  MaterialField continuous;      ///< after the Adam loop (full mesh)
  MaterialField failed;          ///< the design whose simulation stopped the loop (if it stopped early)
  PostProcessResult post;        ///< rounded field, solid object, repair and re-fit reports
  Moments adversarial_moments;   ///< of the final solid object
  double max_normalized_residual = 0;  ///< final object vs reference
  double continuous_max_residual = 0;  ///< before the re-fit (continuous field)
  /// The continuous design's greyness P (opt/occupancy_penalty.hpp) and share of interior volume
  /// with 0.05 < alpha < 0.95 (0 without alpha in the design).
  double occupancy_penalty_continuous = 0;
  double grey_fraction_continuous = 0;
  /// Its repair term R and the components of its rounded occupancy (what the repair joins).
  double repair_share_continuous = 0;
  int components_continuous = 0;
  AttackLoopResult loop;
  /// The polish stage (attack.polish_iterations): Adam on Y, nu, rho of the solid object.
  AttackLoopResult polish;
  double polish_gap = 0;     ///< gap of the polished object (m), whether kept or not
  bool polish_kept = false;  ///< the polished object beat the post-processed one and is the result
  /// Why the polished object could not be measured (its re-fit or its simulation failed): then it
  /// is not kept and polish_gap stays 0. Empty when it was measured.
  std::string polish_failure;
  double gap_initial = 0, gap_continuous = 0, gap_final = 0;          ///< m
  double com_gap_initial = 0, com_gap_continuous = 0, com_gap_final = 0;  ///< m
  double gap_post_processed = 0, com_gap_post_processed = 0;          ///< before polishing (m)
  double objective_initial = 0, objective_final = 0;
  /// The trajectory term of the post-processed and of the final object (no moment term).
  double objective_post_processed = 0, objective_final_object = 0;
  /// B's centre of mass at T (m): reference run, continuous design, final object.
  Eigen::Vector3d scored_com_reference = Eigen::Vector3d::Zero();
  Eigen::Vector3d scored_com_continuous = Eigen::Vector3d::Zero();
  Eigen::Vector3d scored_com_final = Eigen::Vector3d::Zero();
  RefinementCheck refinement;
  /// The loop's start: Y0, nu0 of its initial material (Pa, -), and with attack.start:
  /// best_uniform the candidates it was chosen from (uniform_start.hpp; empty otherwise).
  double start_Y = 0, start_nu = 0;
  UniformStart start;
  /// Which design is the continuous result: progress[kept_iteration]'s, or, when it equals the
  /// number of iterations, the design after the last step. With best_uniform the loop's best
  /// evaluated design is kept when the last one is worse.
  int kept_iteration = 0;
  double forward_seconds = 0, adjoint_seconds = 0, total_seconds = 0;
};

/// Runs the whole attack. Throws rbaa::InputError on bad input, rbaa::SolverError naming the step
/// when a simulation fails.
AttackResult run_attack(const Scene& scene, const AttackOptions& options);

/// DIR/adversarial.msh (+ .vtu): the final solid object with element data Y, nu, rho, alpha,
/// placed at the scene's initial pose; DIR/continuous.msh: the continuous field on the full mesh;
/// DIR/failed_design.msh: the design whose simulation stopped the loop early (only then);
/// DIR/report.json with the keys of SPEC section 8.
void write_attack_outputs(const AttackResult& result, const Scene& scene, const std::string& dir);

}  // namespace rbaa
