#pragma once
// The attack's optimisation loop: Adam on theta for C = C_traj(theta) + beta ||r(theta)||^2
// (+ the occupancy penalty's terms, opt/occupancy_penalty.hpp, when one is given), with the
// occupancy gradient smoothed, an atomic checkpoint after every iteration and exact resumption
// from it.

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <functional>
#include <string>
#include <vector>

#include "rbaa/geometry/smoothing.hpp"
#include "rbaa/material/design_space.hpp"
#include "rbaa/opt/adam.hpp"
#include "rbaa/opt/moment_cost.hpp"
#include "rbaa/opt/occupancy_penalty.hpp"

namespace rbaa {

/// One evaluation of the trajectory term at theta.
struct TrajectoryTermValue {
  double value = 0;      ///< C_traj (normalised, dimensionless)
  double gap = 0;        ///< sqrt(||q_adv(T) - q_ref(T)||^2_Mref / m0_ref) (m)
  double com_gap = 0;    ///< centre-of-mass distance at T (m)
  double forward_seconds = 0;
  double adjoint_seconds = 0;
};

/// theta -> C_traj and, when gradient is not null, dC_traj/dtheta (forward + adjoint).
using TrajectoryTerm = std::function<TrajectoryTermValue(const Eigen::VectorXd& theta,
                                                         Eigen::VectorXd* gradient)>;

/// One row of progress.csv: the state *before* the iteration's Adam step.
struct ProgressRow {
  int iteration = 0;
  double objective = 0;
  double trajectory_term = 0;
  double moment_term = 0;
  double gap = 0;           ///< m
  double com_gap = 0;       ///< m
  double max_moment_residual = 0;  ///< max normalised |r| (moments about the reference centre)
  double seconds = 0;       ///< wall time of the iteration
  /// The occupancy penalty (occupancy_penalty.hpp): w_k this iteration (the ramp times the
  /// largest |trajectory term| so far: the objective's units), the greyness P in [0, 1], the
  /// repair term R (0 unless connectivity_weight > 0 or repair_in_loop: it costs the repair's
  /// search), the face-connected components of the rounded occupancy, and the share of
  /// interior volume with 0.05 < alpha < 0.95 (all 0 without alpha in the design or without a
  /// penalty). `objective`
  /// leaves the penalty out: it compares designs across iterations, and w_k changes with k.
  double occupancy_weight = 0;
  double occupancy_penalty = 0;
  double repair_share = 0;
  int components = 0;
  double grey_fraction = 0;
};

/// Everything needed to continue a run exactly where it stopped.
struct AttackCheckpoint {
  std::string fingerprint;  ///< identifies the scene and settings the run belongs to
  int iteration = 0;        ///< iterations completed
  Eigen::VectorXd theta;
  /// The last design whose simulation succeeded (theta before the last step): where the run can
  /// fall back to if the simulation of `theta` fails.
  Eigen::VectorXd evaluated_theta;
  AdamState adam;
  std::vector<ProgressRow> progress;
  double forward_seconds = 0, adjoint_seconds = 0, elapsed_seconds = 0;
  /// The evaluated design with the lowest objective so far (progress[best_iteration]); -1 and
  /// empty before any (or in a checkpoint written before they were kept).
  int best_iteration = -1;
  Eigen::VectorXd best_theta;
};

/// Writes the checkpoint atomically (write, then rename), doubles exactly.
void save_checkpoint(const std::string& path, const AttackCheckpoint& checkpoint);
/// Reads a checkpoint; throws rbaa::InputError naming the file when it is malformed or its
/// fingerprint differs from `expected_fingerprint` (another scene or other settings).
AttackCheckpoint load_checkpoint(const std::string& path, const std::string& expected_fingerprint,
                                 int expected_size);

/// progress.csv with a header and one row per iteration, written atomically.
void write_progress_csv(const std::string& path, const std::vector<ProgressRow>& rows);

struct AttackLoopOptions {
  int iterations = 50;
  double beta = 1e4;
  AdamOptions adam;
  std::string checkpoint_path;  ///< empty: no checkpoints
  std::string progress_path;    ///< empty: no progress.csv
  std::string fingerprint;
  bool resume = false;          ///< continue from checkpoint_path if it exists
  /// With `resume`, a checkpoint whose fingerprint differs is another start's, not an error: the
  /// loop starts over from theta0 and overwrites it. For a checkpoint that is never the only copy
  /// of a run's work: the polish's, whose fingerprint names the object it started from.
  bool restart_on_other_fingerprint = false;
  /// Descend along the moments' tangent: Adam gets the preconditioned gradient projected onto
  /// J z = 0 (J = dr/dtheta) in the preconditioner's metric (MetricTangentProjector), its step
  /// is projected the same way, and up to four Gauss-Newton steps theta -= J^T (J J^T)^-1 r take
  /// it back onto r = 0 (the second-order rest); a step whose retraction does not get there (to
  /// 1e-6, or to where the design was) is halved until it does, at most ten times, else not
  /// taken (retract_move_onto_moments; a design that did not move is not simulated again). The
  /// start's retraction and the repair_in_loop fills are guarded the same way. Without it Adam's
  /// first steps (about
  /// learning_rate in every entry) break the moments by 1e-2 and the loop spends its iterations
  /// restoring them.
  bool project_moments = true;
  /// The occupancy penalty whose terms join the descent (its gradient goes through the
  /// same smoothing, tangent projection and retraction as the rest), and whose P and grey
  /// fraction progress rows report; null: none (rows report 0).
  const OccupancyPenalty* occupancy = nullptr;
  /// Called after every iteration with its row and the number of iterations in all.
  std::function<void(const ProgressRow&, int)> on_iteration;
};

struct AttackLoopResult {
  Eigen::VectorXd theta;  ///< after the last step (or the last simulated design, if stopped early)
  /// Non-empty when a simulation failed (rbaa::SolverError, or a trajectory term, gap or gradient
  /// that is not finite) after at least one design had been simulated: the loop then stops, theta
  /// is the last design whose simulation succeeded, and this holds the error. A failure before
  /// any design was simulated is thrown (as rbaa::SolverError).
  std::string stopped_early;
  Eigen::VectorXd failed_theta;  ///< the design whose simulation failed (empty unless stopped early)
  /// The last design whose simulation succeeded (empty if none). After a resume with no
  /// iterations left, `theta` is the checkpoint's next design, never simulated: if it fails, this
  /// is where to fall back to.
  Eigen::VectorXd evaluated_theta;
  std::vector<ProgressRow> progress;
  /// The evaluated design with the lowest objective (objective incl. the moment term, the first
  /// on ties): progress[best_iteration] was measured at best_theta. -1 and empty if none was (or
  /// the run resumed from a checkpoint that did not keep it). The design after the last step,
  /// `theta`, is not evaluated by the loop: a caller that wants the best of all compares it too.
  int best_iteration = -1;
  Eigen::VectorXd best_theta;
  int resumed_from = 0;   ///< iterations loaded from the checkpoint
  double forward_seconds = 0, adjoint_seconds = 0, elapsed_seconds = 0;
};

/// Projection onto the tangent {z : J z = 0} of the moments' manifold in the metric of a
/// symmetric positive definite preconditioner M (the occupancy smoothing; identity elsewhere):
/// project(v) = v - W (J W)^-1 J v with W = M J^T. For a gradient g, z = project(M g) is tangent
/// and g . z = |M^1/2 g|^2 - |its M^1/2 J^T-part|^2 >= 0, so -z descends. The Euclidean
/// projection of M g has no such guarantee once M scales blocks differently.
class MetricTangentProjector {
 public:
  MetricTangentProjector(const Eigen::Matrix<double, 10, Eigen::Dynamic>& J,
                         const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& precondition);
  Eigen::VectorXd project(const Eigen::VectorXd& v) const;

 private:
  Eigen::Matrix<double, 10, Eigen::Dynamic> J_;
  Eigen::MatrixXd W_;
  Eigen::LDLT<Eigen::Matrix<double, 10, 10>> JW_;
};

/// Moves theta onto r(theta) = 0 with up to `max_steps` Gauss-Newton steps
/// theta -= J^T (J J^T)^-1 r (stops once max |r| < 1e-12). Returns max |r| where it ends.
double retract_onto_moments(const MomentCostFunction& moments, Eigen::VectorXd& theta, int max_steps = 4);

/// Retract, else back off: sets theta to from + s (to - from), retracted onto the moments, for the
/// first s of 1, 1/2, ..., 2^-max_halvings whose retraction ends within `tolerance`; if none
/// does, theta = from (unretracted) and it returns false. Where the design saturates (the tanh
/// map flat near its bounds, J J^T nearly singular) a retraction from far off can diverge and
/// leave a design off the moments for good; a shorter move from a design near them does not.
bool retract_move_onto_moments(const MomentCostFunction& moments, const Eigen::VectorXd& from,
                               const Eigen::VectorXd& to, double tolerance, Eigen::VectorXd& theta,
                               int max_halvings = 10);

/// Runs the loop from theta0 (or the checkpoint); with project_moments, theta0 is first retracted
/// onto the matched moments. `smoother` may be null (no occupancy field).
AttackLoopResult run_attack_loop(const DesignSpace& design, const MomentCostFunction& moments,
                                 const GradientSmoother* smoother, const TrajectoryTerm& trajectory,
                                 const Eigen::VectorXd& theta0, const AttackLoopOptions& options);

}  // namespace rbaa
