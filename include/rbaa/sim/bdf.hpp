#pragma once
// BDF time stepping on positions, kept apart from the forms (SPEC section 2, paper supplement A).
// One step minimises 1/2 (q - q_hat)^T M (q - q_hat) + w (Psi + Phi_g + kappa B) with, at a
// constant step h,
//
//   BDF-2: q_hat = (24 q_n - 22 q_{n-1} + 8 q_{n-2} - q_{n-3}) / 9,  w = (4/9) h^2,
//          v_{n+1} = (3 q_{n+1} - 4 q_n + q_{n-1}) / (2 h);
//   BDF-1: q_hat = 2 q_n - q_{n-1},  w = h^2,  v_{n+1} = (q_{n+1} - q_n) / h.
//
// Steps may change size (contact-resolving steps, simulator.hpp). BDF-2 at a step h_{n+1} after
// h_n, ratio r = h_{n+1} / h_n, applies one rule to positions and to velocities:
//
//   y_{n+1} - a0 y_n - a1 y_{n-1} = b y'_{n+1},  a0 = (1+r)^2/(1+2r), a1 = -r^2/(1+2r),
//                                               b = h_{n+1} (1+r)/(1+2r)
//
// (second order for any r, zero-stable for ratios below 1 + sqrt 2). Eliminating the velocities
// v_n and v_{n-1} with the two previous steps' rules gives q_hat = sum_j c_j q_{n-j} (j = 0..3)
// and w = b^2; with r = 1 throughout this is the constant-step rule above. BDF-1: a0 = 1, a1 = 0,
// b = h_{n+1}.
//
// The history starts from the body's exact ballistic past q_{-k} = q_0 - k h v_0 + (k h)^2 / 2 g
// at the scene's step, on which both schemes are exact, so a free fall follows the parabola.

#include <Eigen/Core>

#include <deque>
#include <vector>

#include "rbaa/sim/world.hpp"

namespace rbaa {

/// One step's rule y_{n+1} - a0 y_n - a1 y_{n-1} = b y'_{n+1}.
struct BdfStepRule {
  double a0 = 1, a1 = 0, b = 0;
  bool operator==(const BdfStepRule& o) const { return a0 == o.a0 && a1 == o.a1 && b == o.b; }
};

/// The rule of a step of size h after one of size h_previous. Equal sizes give the constant-step
/// rule exactly (4/3, -1/3, 2h/3 for BDF-2).
BdfStepRule bdf_step_rule(Integrator kind, double h, double h_previous);

/// A step's predictor: q_hat = sum_j c[j] q_{n-j} and the potentials' weight w.
struct BdfPredictor {
  std::vector<double> c;  ///< 4 coefficients (BDF-2) or 2 (BDF-1); they sum to 1
  double weight = 0;
  bool constant_step = true;  ///< all three rules equal: the constant-step formulas apply
};

/// From the rules of this step and of the two before it (the velocities v_n and v_{n-1}).
/// Three equal rules give the constant-step coefficients bit for bit (24/9, ... and (4/9) h^2).
BdfPredictor bdf_predictor(Integrator kind, const BdfStepRule& now, const BdfStepRule& previous,
                           const BdfStepRule& before, double h);

/// q_hat from the newest positions (past[0] = q_n, ...), in differences of consecutive positions.
Eigen::VectorXd bdf_predict(Integrator kind, const BdfPredictor& p,
                            const std::vector<const Eigen::VectorXd*>& past);

/// The velocity at q_n by the rule that produced it: (q_n - a0 q_{n-1} - a1 q_{n-2}) / b.
Eigen::VectorXd bdf_velocity(Integrator kind, const BdfStepRule& rule, double h,
                             const Eigen::VectorXd& q_n, const Eigen::VectorXd& q_n1,
                             const Eigen::VectorXd& q_n2);

class BdfIntegrator {
 public:
  BdfIntegrator(Integrator kind, double time_step);

  /// Sets q_0 and the ballistic past from per-dof initial velocities v0 and the gravity g (3),
  /// and the step back to the scene's h.
  void initialize(const Eigen::VectorXd& q0, const Eigen::VectorXd& v0, const Eigen::Vector3d& g);

  /// The size of the next step (default: the scene's h); sets the predictor and weight.
  void set_next_step(double h);
  /// q_hat for the next step.
  Eigen::VectorXd predictor() const;
  /// Coefficients c_k of q_hat = sum_k c_k q_{n-k}, k = 0 .. order, of the next step (the
  /// adjoint spreads dC/dq_hat back with them).
  const std::vector<double>& predictor_coefficients() const { return predictor_.c; }
  /// The weight w of the potentials: (4/9) h^2 or h^2 at a constant step.
  double potential_weight() const { return predictor_.weight; }
  /// Replaces past(k) (k >= 1), e.g. with a prescribed motion's past after initialize().
  void set_past(int k, const Eigen::VectorXd& q) { history_.at(k) = q; }
  /// Appends q_{n+1}, produced by the next step.
  void push(const Eigen::VectorXd& q_next);
  /// The newest position q_n.
  const Eigen::VectorXd& current() const { return history_.front(); }
  /// Position k steps back: past(0) = q_n.
  const Eigen::VectorXd& past(int k) const { return history_[k]; }
  /// The scheme's velocity at q_n.
  Eigen::VectorXd velocity() const;

  Integrator kind() const { return kind_; }
  /// The scene's step h.
  double time_step() const { return h_; }
  /// The next step's size and rule.
  double next_step() const { return next_h_; }
  const BdfStepRule& next_rule() const { return next_rule_; }
  /// Number of past positions the predictor uses (4 for BDF-2, 2 for BDF-1).
  int history_size() const { return static_cast<int>(predictor_.c.size()); }

 private:
  Integrator kind_;
  double h_;
  double next_h_;
  BdfStepRule next_rule_;
  BdfPredictor predictor_;
  std::deque<Eigen::VectorXd> history_;  // front = newest
  std::deque<BdfStepRule> rules_;        // rules that produced history_[0], history_[1]
  std::deque<double> sizes_;             // their step sizes
};

}  // namespace rbaa
