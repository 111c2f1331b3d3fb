#pragma once
// BDF time stepping on positions, kept apart from the forms (SPEC section 2, paper supplement A).
// One step minimises 1/2 (q - q_hat)^T M (q - q_hat) + w (Psi + Phi_g + kappa B) with
//
//   BDF-2: q_hat = (24 q_n - 22 q_{n-1} + 8 q_{n-2} - q_{n-3}) / 9,  w = (4/9) h^2,
//          v_{n+1} = (3 q_{n+1} - 4 q_n + q_{n-1}) / (2 h);
//   BDF-1: q_hat = 2 q_n - q_{n-1},  w = h^2,  v_{n+1} = (q_{n+1} - q_n) / h.
//
// The history starts from the body's exact ballistic past q_{-k} = q_0 - k h v_0 + (k h)^2 / 2 g,
// on which both schemes are exact, so a free fall follows the analytic parabola.

#include <Eigen/Core>

#include <deque>
#include <vector>

#include "rbaa/sim/world.hpp"

namespace rbaa {

class BdfIntegrator {
 public:
  BdfIntegrator(Integrator kind, double time_step);

  /// Sets q_0 and the ballistic past from per-dof initial velocities v0 and the gravity g (3).
  void initialize(const Eigen::VectorXd& q0, const Eigen::VectorXd& v0, const Eigen::Vector3d& g);

  /// q_hat for the next step.
  Eigen::VectorXd predictor() const;
  /// Coefficients c_k of q_hat = sum_k c_k q_{n-k}, k = 0 .. order (the adjoint spreads dC/dq_hat
  /// back with them).
  const std::vector<double>& predictor_coefficients() const { return coefficients_; }
  /// The weight w of the potentials: (4/9) h^2 or h^2.
  double potential_weight() const { return weight_; }
  /// Replaces past(k) (k >= 1), e.g. with a prescribed motion's past after initialize().
  void set_past(int k, const Eigen::VectorXd& q) { history_.at(k) = q; }
  /// Appends q_{n+1}.
  void push(const Eigen::VectorXd& q_next);
  /// The newest position q_n.
  const Eigen::VectorXd& current() const { return history_.front(); }
  /// Position k steps back: past(0) = q_n.
  const Eigen::VectorXd& past(int k) const { return history_[k]; }
  /// The scheme's velocity at q_n.
  Eigen::VectorXd velocity() const;

  Integrator kind() const { return kind_; }
  double time_step() const { return h_; }
  /// Number of past positions the predictor uses (4 for BDF-2, 2 for BDF-1).
  int history_size() const { return static_cast<int>(coefficients_.size()); }

 private:
  Integrator kind_;
  double h_;
  double weight_;
  std::vector<double> coefficients_;
  std::deque<Eigen::VectorXd> history_;  // front = newest
};

}  // namespace rbaa
