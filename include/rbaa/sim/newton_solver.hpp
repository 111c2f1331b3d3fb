#pragma once
// Projected Newton for one time step (SPEC section 2). Each iteration assembles the Hessian
// (element Hessians projected to PSD, barrier Hessians clamped PSD), factorises it with CHOLMOD,
// and takes the step dq = -H^-1 grad E. The step length starts at the largest fraction the forms
// allow (CCD) and halves until E decreases and the iterate is valid; after a halving, Brent's
// search between zero and twice that fraction finds the minimum of E along the step
// (newton_solver.cpp says why). Convergence: the step's
// velocity ||dq||_inf / h below the tolerance.
//
// After a full step (no backtracking) whose velocity is below exact_hessian_factor x the
// tolerance, the exact Hessian is factorised instead, with a fallback to the projected one if
// CHOLMOD finds it not positive definite; the projected Hessian differs from the exact one in
// every compressed element, and Newton with it converges only linearly (rate ~0.7 in the ball's
// contact step). The default factor is infinite, i.e. the exact Hessian is tried after every full
// step: on the Y = 1e13 ball's contact step that takes 9 iterations against 35 with the SPEC's
// "near the tolerance" switch at 1e3 x tolerance. The converged iterate is the one at which the last Hessian was
// factorised (its step was computed and found below tolerance, and not applied), so the adjoint
// can reuse that factor when it is exact.
//
// An optional subspace sub-step (set_subspace_step) is tried before every factorisation after the
// first; the simulator gives the body's six rigid motions (rigid_newton_step), which finishes the
// rotation that a Newton step on a stiff stressed body leaves behind to second order.
//
// The potential's fixed (Dirichlet) dofs never move: the step, its transform and the sub-step are
// zero there, so the iterate keeps the values the caller gave them.

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <functional>
#include <limits>
#include <string>

#include "rbaa/sim/incremental_potential.hpp"
#include "rbaa/sim/linear_solver.hpp"

namespace rbaa {

struct NewtonSettings {
  double time_step = 0.01;            ///< h (s), scales the step into a velocity
  double velocity_tolerance = 1e-9;   ///< on ||dq||_inf / h (m/s)
  int max_iterations = 100;
  /// try the exact Hessian after a full step slower than this x tolerance (infinity: always)
  double exact_hessian_factor = std::numeric_limits<double>::infinity();
  int max_line_search_halvings = 60;
  /// Start each minimize with a chord step: the previous call's factorisation (the last Hessian
  /// of the previous time step, at its converged iterate) solved against this iterate's gradient,
  /// a descent direction, line-searched like a Newton step but never a convergence test (the
  /// adjoint needs the factor of the converged iterate's own Hessian). A stiff body in free flight
  /// then needs one factorisation per step instead of two: the chord step removes the elastic
  /// correction the rigid predictor leaves, and the first factorisation finds the step converged.
  /// No chord step without a previous call since construction or forget_factor().
  bool chord_first_step = false;
};

struct NewtonResult {
  int iterations = 0;             ///< Hessians factorised and solved (incl. the final check)
  bool exact_factor = false;      ///< the last factorisation was of the exact Hessian (or of a
                                  ///< projected one the projection left unchanged)
  double step_velocity = 0;       ///< ||dq||_inf / h of the final, unapplied step (m/s)
  int line_search_halvings = 0;   ///< summed over the iterations
  int line_search_probes = 0;     ///< energies of the line minimisation after backtracking
  int symbolic_analyses = 0;      ///< CHOLMOD symbolic analyses (a new Hessian pattern)
  int projected_fallbacks = 0;    ///< exact Hessians found not positive definite
  int extrapolations = 0;         ///< step doublings taken after full steps (newton_solver.cpp)
  int chord_steps = 0;            ///< chord steps taken on the previous call's factor (0 or 1)
  /// Stopped above the tolerance at the round-off floor: kFloorWindow steps in a row, all below
  /// kFloorFactor x tolerance, none smaller than the smallest step before them (no
  /// progress at all, only noise). step_velocity is then the floor's latest step and
  /// floor_velocity the slowest step seen.
  bool roundoff_limited = false;
  double floor_velocity = 0;
  // Where the time went (wall seconds, summed over the iterations).
  double gradient_seconds = 0;       ///< energy gradients
  double assembly_seconds = 0;       ///< Hessian assembly (element Hessians, projection, sums)
  double factorization_seconds = 0;  ///< CHOLMOD numeric factorisations (incl. failed ones)
  double solve_seconds = 0;          ///< triangular solves
  double line_search_seconds = 0;    ///< step transform, CCD, energy differences

  /// This result followed by `later`, a further minimize from where this one stopped (friction
  /// re-lagged, simulator.cpp): counts and seconds add up; what describes the returned iterate
  /// (exact_factor, step_velocity, roundoff_limited, floor_velocity) is `later`'s.
  void append(const NewtonResult& later);
};

/// What one Newton iteration did (for progress reports and diagnosis).
struct NewtonIteration {
  int iteration = 0;
  bool exact_hessian = false;
  double step_velocity = 0;     ///< ||dq||_inf / h of the full Newton step (m/s)
  double max_step_fraction = 1; ///< the forms' max_step_size (CCD)
  double step_fraction = 1;     ///< accepted fraction after backtracking
  double energy_change = 0;     ///< E(x_new) - E(x)
  double directional_derivative = 0;  ///< grad E . dq
  Eigen::Index largest_dof = 0;  ///< dof of the largest |dq| component
};

class NewtonSolver {
 public:
  using IterationCallback = std::function<void(const std::string& context, const NewtonIteration&)>;

  explicit NewtonSolver(const NewtonSettings& settings) : settings_(settings) {}

  /// Minimises E from the valid iterate x (updated in place). `context` names the step in
  /// errors ("step 12 (t = 0.12 s)"). Throws rbaa::SolverError when the iteration limit is
  /// reached, the line search fails or no Hessian can be factorised.
  NewtonResult minimize(IncrementalPotential& E, Eigen::VectorXd& x, const std::string& context);

  /// Forgets the previous call's factorisation for chord_first_step (a new run starts: its first
  /// step must not depend on what the solver did before).
  void forget_factor() { factor_from_last_call_ = false; }
  /// Where the chord step finds the previous call's factor once the caller has taken it from
  /// this solver (the adjoint keeps each step's factor by exchanging value arrays,
  /// LinearSolver::give_factor_values): b -> A^-1 b with that factor, or an empty vector when
  /// the caller has none. Empty function: no chord step without this solver's own factor.
  using ChordSolve = std::function<Eigen::VectorXd(const Eigen::VectorXd& b)>;
  void set_chord_solve(ChordSolve solve) { chord_solve_ = std::move(solve); }
  /// How the chord step applies the previous factor at iterate x to the gradient g, given
  /// `solve` (b -> A^-1 b with it; an empty result: none): the simulator rotates g into the
  /// previous step's frame of each body and the solution back, because a stiff body's Hessian
  /// turns with the body (H_x ~ R H_prev R^T) and an unrotated stale factor gets the stiff
  /// directions wrong by the step's rotation. Empty function: solve(g).
  using ChordFrame = std::function<Eigen::VectorXd(const Eigen::VectorXd& x, const Eigen::VectorXd& g,
                                                   const ChordSolve& solve)>;
  void set_chord_frame(ChordFrame frame) { chord_frame_ = std::move(frame); }

  /// The factorisation of the last Hessian (at the returned iterate after minimize).
  const LinearSolver& linear_solver() const { return solver_; }
  LinearSolver& linear_solver() { return solver_; }
  const NewtonSettings& settings() const { return settings_; }
  /// The step the tolerance's velocity is measured over (steps of varying size).
  void set_time_step(double h) { settings_.time_step = h; }
  /// Optional map applied to every Newton step before the line search, dq <- f(x, dq). The
  /// simulator uses it to apply the step's rigid rotation as a finite rotation (see
  /// rigid_rotation_correction.hpp). Used only when the result is still a descent direction.
  using StepTransform = std::function<Eigen::VectorXd(const Eigen::VectorXd& x, const Eigen::VectorXd& dq)>;
  void set_step_transform(StepTransform transform) { transform_ = std::move(transform); }
  /// Optional cheap sub-step tried before each factorisation after the first: given the iterate,
  /// its gradient and the previous iteration's Hessian (lower triangle), a candidate step in a
  /// small subspace (the simulator: the body's rigid motions), or an empty vector. It is taken
  /// only when it is admissible (CCD, validity) and lowers the energy, so it cannot harm
  /// convergence; it removes what a Newton step on a stiff, stressed, spinning body leaves behind
  /// to second order: a rigid rotation of the soft rotational mode (see newton_solver.cpp).
  using SubspaceStep = std::function<Eigen::VectorXd(const Eigen::VectorXd& x, const Eigen::VectorXd& g,
                                                     const Eigen::SparseMatrix<double>& H_lower)>;
  void set_subspace_step(SubspaceStep step) { subspace_ = std::move(step); }
  /// Called after every accepted Newton step.
  void set_iteration_callback(IterationCallback callback) { callback_ = std::move(callback); }

 private:
  NewtonSettings settings_;
  IterationCallback callback_;
  StepTransform transform_;
  SubspaceStep subspace_;
  LinearSolver solver_;
  bool factor_from_last_call_ = false;  // the previous call converged (its factor is the chord's)
  ChordSolve chord_solve_;
  ChordFrame chord_frame_;

  // The chord step of chord_first_step; leaves x unchanged when no admissible decrease is found.
  // Returns the step's velocity ||dq||_inf / h when it was taken whole, else infinity.
  double chord_step(IncrementalPotential& E, Eigen::VectorXd& x, NewtonResult& result);
};

}  // namespace rbaa
