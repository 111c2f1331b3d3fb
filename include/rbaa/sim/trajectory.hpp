#pragma once
// What a forward simulation returns: the positions of every step (the adjoint needs them all,
// with the start-up history the first predictors used) and per-step solver statistics.

#include <Eigen/Core>

#include <vector>

#include "rbaa/sim/world.hpp"

namespace rbaa {

struct StepStats {
  int newton_iterations = 0;     ///< Hessians factorised (incl. the final convergence check)
  bool exact_factor = false;     ///< the last factor is of the exact Hessian at the returned q
  double step_velocity = 0;      ///< final Newton step's ||dq||_inf / h (m/s)
  /// Newton stopped above its tolerance at the round-off floor (NewtonResult::roundoff_limited);
  /// floor_velocity is the slowest step it reached
  bool roundoff_limited = false;
  double floor_velocity = 0;
  int line_search_halvings = 0;
  int ccd_limited_steps = 0;
  int projected_fallbacks = 0;
  int extrapolations = 0;        ///< Newton step doublings (newton_solver.cpp)
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
};

struct Trajectory {
  double time_step = 0;
  Integrator integrator = Integrator::kBdf2;
  double kappa = 0;
  std::vector<Eigen::VectorXd> history;  ///< q_{-1}, q_{-2}, q_{-3}: the ballistic past
  std::vector<Eigen::VectorXd> q;        ///< q[0] (initial) .. q[N]
  std::vector<StepStats> steps;          ///< steps[k] produced q[k + 1]

  int num_steps() const { return static_cast<int>(steps.size()); }
  double time(int k) const { return k * time_step; }
  /// q_k for k >= -3 (negative k: the history).
  const Eigen::VectorXd& position(int k) const { return k >= 0 ? q[k] : history[-k - 1]; }
  /// The integrator's velocity at step k (BDF-2: (3 q_k - 4 q_{k-1} + q_{k-2}) / 2h;
  /// BDF-1: (q_k - q_{k-1}) / h).
  Eigen::VectorXd velocity(int k) const;
};

}  // namespace rbaa
