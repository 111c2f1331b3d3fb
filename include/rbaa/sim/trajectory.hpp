#pragma once
// What a forward simulation returns: the positions of every step (the adjoint needs them all,
// with the start-up history the first predictors used) and per-step solver statistics.

#include <Eigen/Core>

#include <vector>

#include "rbaa/sim/bdf.hpp"
#include "rbaa/sim/world.hpp"

namespace rbaa {

struct NewtonResult;

/// One step's solver statistics. A counter of Newton's is a NewtonResult field (summed over a
/// step's solves by NewtonResult::append), a field here, and a line in add() and operator+=.
struct StepStats {
  int newton_iterations = 0;     ///< Hessians factorised (incl. the final convergence check)
  bool exact_factor = false;     ///< the last factor is of the exact Hessian at the returned q
  /// Newton stopped above its tolerance at the round-off floor (NewtonResult::roundoff_limited);
  /// floor_velocity is the slowest step it reached
  bool roundoff_limited = false;
  double floor_velocity = 0;
  int projected_fallbacks = 0;
  int extrapolations = 0;        ///< Newton step doublings (newton_solver.cpp)
  int chord_steps = 0;           ///< chord steps on the previous step's factor (0 or 1)
  int line_search_probes = 0;    ///< energies of Newton's line minimisation (newton_solver.cpp)
  int symbolic_analyses = 0;     ///< CHOLMOD symbolic analyses: the Hessian's pattern changed
  /// CCD searches of the step stopped by their iteration cap (Form::ccd_caps): the driven move's
  /// check, the start guesses' and Newton's line search (which may search one pair several times)
  long ccd_caps = 0;
  /// Friction re-lagged from the step's solution and solved again (friction_iterations > 1);
  /// newton_iterations includes those solves' iterations
  int friction_relags = 0;
  double min_distance = 0;       ///< smallest vertex-obstacle distance at the new q (m)
  int active_pairs = 0;          ///< contact pairs closer than d_hat at the new q
  /// Sum of the forces (N) the drives exert on their driven vertices at the new q: the full
  /// step equation's residual at the driven dofs over the potentials' weight (zero without).
  Eigen::Vector3d dirichlet_force = Eigen::Vector3d::Zero();
  double seconds = 0;            ///< wall time of the step
  // Of which (NewtonResult's split): gradients, Hessian assembly, factorisations, solves,
  // line search.
  double gradient_seconds = 0, assembly_seconds = 0, factorization_seconds = 0,
         solve_seconds = 0, line_search_seconds = 0;

  /// Adds a Newton solve of this step: its counts and seconds add up; what describes the
  /// returned iterate (exact_factor, roundoff_limited, floor_velocity) is the solve's.
  void add(const NewtonResult& solve);
  /// Adds the counts and seconds (friction_relags and the step's own seconds too) of `other`:
  /// a run's totals over its steps. What describes one step's end is left as it is.
  StepStats& operator+=(const StepStats& other);
};

/// What contact-resolving steps did in a run (SimulationSettings::contact_substeps).
struct ContactResolvingStats {
  int substeps = 0;           ///< k: the finest step is h/k (0: constant steps)
  int refined_steps = 0;      ///< steps taken shorter than h
  int contacts = 0;           ///< contact episodes (a step in contact after one that was not)
  int predicted_halvings = 0;  ///< steps halved before Newton: their ballistic guess met contact
  int rejected_steps = 0;     ///< steps tried, found in contact and taken again at half the size
  int rejected_newton_iterations = 0;
  double rejected_seconds = 0;
};

struct Trajectory {
  double time_step = 0;       ///< the scene's h
  Integrator integrator = Integrator::kBdf2;
  double kappa = 0;
  std::vector<Eigen::VectorXd> history;  ///< q_{-1}, q_{-2}, q_{-3}: the ballistic past
  std::vector<Eigen::VectorXd> q;        ///< q[0] (initial) .. q[N]
  std::vector<StepStats> steps;          ///< steps[k] produced q[k + 1]
  /// Steps of varying size (contact-resolving steps): step_sizes[k] of steps[k] and times[k] of
  /// q[k]. Empty: every step is time_step long.
  std::vector<double> step_sizes;
  std::vector<double> times;
  /// With step_sizes: the indices k of the q[k] on the grid of time_step (q[0] and the end of
  /// every step of h, sub-stepped or not).
  std::vector<int> grid;
  ContactResolvingStats resolving;

  int num_steps() const { return static_cast<int>(steps.size()); }
  double time(int k) const { return times.empty() ? k * time_step : times[k]; }
  /// The size of step k (which produced q_{k+1}); the ballistic past (k < 0) is time_step apart.
  double step_size(int k) const {
    return k < 0 || step_sizes.empty() ? time_step : step_sizes[k];
  }
  /// The indices of the positions at 0, h, 2h, ... (all of them with constant steps): what a
  /// consumer comparing runs step by step (the rigid twin, bounce detection) reads.
  std::vector<int> grid_frames() const;
  /// The BDF rule of step k (bdf.hpp), and its predictor and the potentials' weight.
  BdfStepRule rule(int k) const;
  BdfPredictor predictor(int k) const;
  /// q_k for k >= -3 (negative k: the history).
  const Eigen::VectorXd& position(int k) const { return k >= 0 ? q[k] : history[-k - 1]; }
  /// The integrator's velocity at step k by the rule of the step that produced q_k (constant
  /// steps: BDF-2 (3 q_k - 4 q_{k-1} + q_{k-2}) / 2h; BDF-1 (q_k - q_{k-1}) / h).
  Eigen::VectorXd velocity(int k) const;
};

}  // namespace rbaa
