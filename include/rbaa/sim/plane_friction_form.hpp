#pragma once
// Lagged, smoothed Coulomb friction against analytic planes (IPC, Li et al. 2020, section 5):
//
//   D(x) = sum over lagged pairs k of  mu_k lambda_k f0(|u_k|),   u_k = P_k (x_v - x~_v),
//
// over the pairs (surface vertex v, plane k) closer than d_hat at q_n. The normal force lambda_k =
// -kappa b'(d_k(q_n)) and the tangent projector P_k = I - n n^T are lagged from q_n (for a plane,
// P_k does not depend on the state at all). x~ = q_n (BDF-1) or (4 q_n - q_{n-1}) / 3 (BDF-2), so
// that u = tau v_t with v_t the scheme's tangential velocity at the new step and tau = h or 2h / 3.
// f0 is IPC's C1 mollifier of |.| with eps = eps_v tau (eps_v in m/s):
//
//   f1(y) = 2 y / eps - y^2 / eps^2 (y < eps), 1 (y >= eps);  f0' = f1, f0(eps) = eps,
//
// so the friction force mu lambda f1(|u|) u / |u| is Coulomb's mu lambda for tangential speeds
// above eps_v, and vanishes linearly below (static friction holds a body to a creep <= eps_v).
// D is convex in x (its Hessian is PSD), so exact and projected Hessians agree. Like the other
// potentials it enters the step with the integrator's weight w.
//
// The adjoint: G = ... + w grad D(x; x~(q_n, q_{n-1}), lambda(q_n)) depends on the history through
// x~ (d grad D / d x~ = -hess D) and through the lagged normal forces (d lambda_k / d x_v(q_n) =
// -kappa b''(d_k) n_k); add_history_adjoint and history_tangent give those terms.

#include <Eigen/Core>

#include <vector>

#include "rbaa/contact/barrier.hpp"
#include "rbaa/sim/bdf.hpp"
#include "rbaa/sim/form.hpp"
#include "rbaa/sim/world.hpp"

namespace rbaa {

class PlaneFrictionForm : public Form {
 public:
  /// `mu`: one coefficient per plane (>= 0; planes with 0 are skipped). `eps_v` (m/s) > 0.
  PlaneFrictionForm(std::vector<int> surface_vertices, std::vector<Plane> planes,
                    std::vector<double> mu, double d_hat, double kappa, double eps_v,
                    Integrator integrator, double time_step);

  /// Lags the pairs, normal forces and x~ from the newest position q_n and the one before it.
  void lag(const Eigen::VectorXd& q_n, const Eigen::VectorXd& q_previous) override;
  /// The pairs and normal forces from x instead; x~ stays lag()'s.
  void relag(const Eigen::VectorXd& x) override;

  const char* name() const override { return "friction"; }
  double value(const Eigen::VectorXd& x) const override;
  /// D(x1) - D(x0) without the cancellation of subtracting two values.
  double value_difference(const Eigen::VectorXd& x0, const Eigen::VectorXd& x1) const override;
  void add_gradient(const Eigen::VectorXd& x, double scale, Eigen::VectorXd& grad) const override;
  void add_hessian(const Eigen::VectorXd& x, double scale, HessianKind kind,
                   SparseHessian& hessian) const override;

  /// bar_n += -(dG/dq_n)^T a and bar_previous += -(dG/dq_{n-1})^T a for G's term w grad D at x
  /// (the lag set by lag(q_n, q_{n-1})).
  void add_history_adjoint(const Eigen::VectorXd& x, const Eigen::VectorXd& a, double w,
                           Eigen::VectorXd& bar_n, Eigen::VectorXd& bar_previous) const override;
  /// (dG/dq_n) dq_n + (dG/dq_{n-1}) dq_previous for G's term w grad D at x.
  Eigen::VectorXd history_tangent(const Eigen::VectorXd& x, const Eigen::VectorXd& dq_n,
                                  const Eigen::VectorXd& dq_previous, double w) const;
  void add_history_tangent(const Eigen::VectorXd& x, const Eigen::VectorXd& dq_n,
                           const Eigen::VectorXd& dq_previous, double w,
                           Eigen::VectorXd& out) const override {
    out += history_tangent(x, dq_n, dq_previous, w);
  }

  int num_lagged_pairs() const { return static_cast<int>(pairs_.size()); }
  double eps() const { return eps_; }
  /// The rule of the next step (bdf.hpp): x~ = a0 q_n + a1 q_{n-1}, eps = eps_v b. Steps of
  /// another size than the scene's (contact-resolving steps) set it before lag().
  void set_step_rule(const BdfStepRule& rule) {
    a0_ = rule.a0;
    a1_ = rule.a1;
    eps_ = eps_v_ * rule.b;
  }

 private:
  struct Pair {
    int vertex;
    int plane;
    double normal_force;  // lambda_k
    double normal_force_derivative;  // d lambda_k / d d_k = -kappa b''(d_k)
    Eigen::Vector3d x_tilde;
  };
  // Per pair at x: u, y = |u|, f1(y) / y and (f1'(y) y - f1(y)) / y^3 (0 at y = 0).
  struct Slip {
    Eigen::Vector3d u;
    double y, f1_over_y, c1;
  };
  Slip slip(const Pair& p, const Eigen::VectorXd& x) const;
  // mu lambda hess f0(|u|) applied to the pair's block: mu lambda (c1 u u^T + f1/y P).
  Eigen::Matrix3d block(const Pair& p, const Slip& s) const;

  std::vector<int> surface_vertices_;
  std::vector<Plane> planes_;
  std::vector<double> mu_;
  contact::Barrier barrier_;
  double kappa_;
  double eps_v_;
  double eps_;
  // The pairs closer than d_hat at q_lag, with x~ from q_n_ and q_previous_.
  void lag_at(const Eigen::VectorXd& q_lag);

  double a0_, a1_;  // x~ = a0 q_n + a1 q_{n-1}
  Eigen::VectorXd q_n_, q_previous_;  // lag()'s history
  std::vector<Pair> pairs_;
};

}  // namespace rbaa
