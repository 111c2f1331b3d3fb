#pragma once
// Lagged, smoothed Coulomb friction on the primitive pairs of mesh contact (IPC, Li et al. 2020,
// section 5): body vertex - obstacle triangle, obstacle vertex - body triangle and body edge -
// obstacle edge against triangle-mesh obstacles (mesh_obstacle_form.hpp), vertex - triangle and
// edge - edge between bodies (body_contact_form.hpp):
//
//   D(x) = sum over lagged pairs k of  mu_k lambda_k f0(|u_k|),
//   u_k  = T_k^T sum_i gamma_ki (x_i - x~_i)  =  Gamma_k^T (x - x~)   (Gamma_k: 12 x 2),
//
// over the pairs closer than d_hat at q_n, each with everything but x lagged from q_n:
//
// * lambda_k = -kappa m_k b'(d_k), the pair's normal force: b the barrier, d_k its distance and
//   m_k the edge-edge mollifier (1 for vertex-triangle pairs) at q_n. Including m_k makes the
//   friction of two edges turning parallel vanish with their normal force (m_k -> 0) instead of
//   jumping; IPC Toolkit drops such pairs (m_k < 1) from friction altogether.
// * the distance type of the pair at q_n, held fixed within the step, and for that type the
//   closest-point weights gamma_k and the tangent basis T_k (contact/tangent_frame.hpp).
// * x~ = q_n (BDF-1) or (4 q_n - q_{n-1}) / 3 (BDF-2) on body vertices, as for the plane form
//   (plane_friction_form.hpp), so that u is tau times the tangential relative velocity with
//   tau = h or 2h / 3, and f0 (contact/smooth_friction.hpp) uses eps = eps_v tau. Obstacle points
//   do not move: for them x = x~.
// * mu_k: the coefficient of the pair's surfaces, per obstacle mesh, or per pair of bodies.
//
// With everything lagged, D is convex in x; its exact Hessian mu lambda Gamma (c1 u u^T + f1/y I)
// Gamma^T is PSD, so exact and projected Hessians agree.
//
// The adjoint: the step equation's term w grad D = w mu lambda Gamma (f1/y) u depends on q_n
// through lambda, Gamma (gamma and T) and x~, and on q_{n-1} through x~; add_history_adjoint and
// add_history_tangent give those terms exactly, with the derivatives of gamma and T by
// forward-mode automatic differentiation and those of lambda from the distance's and mollifier's
// gradients, all for the lagged (fixed) distance type. What stays piecewise: a pair whose distance
// type changes, or that enters or leaves d_hat, between q_n and a perturbed q_n (a set of measure
// zero for the gradient; finite differences across it see a jump the adjoint does not).

#include <Eigen/Core>
#include <vector>

#include "rbaa/contact/fixed_size.hpp"
#include "rbaa/sim/bdf.hpp"
#include "rbaa/sim/body_contact_form.hpp"
#include "rbaa/sim/contact_pair.hpp"
#include "rbaa/sim/form.hpp"
#include "rbaa/sim/mesh_obstacle_form.hpp"
#include "rbaa/sim/world.hpp"

namespace rbaa {

/// One lagged pair, for tests and reports. "At the lag": at q_n after lag(), at the step's
/// solution after relag(); x~ is lag()'s either way.
struct LaggedFrictionPair {
  ContactPairPoints points;      ///< at the lag, with the simulator vertices (-1: obstacle point)
  int type = 0;                  ///< the lag's distance type (PointTriangle or EdgeEdge, as int)
  int mesh = -1;                 ///< obstacle mesh index, or -1 between two bodies
  int body_a = -1, body_b = -1;  ///< body ids of the two primitives (between bodies)
  double mu = 0;                 ///< the pair's coefficient
  double normal_force = 0;       ///< lambda = -kappa m b'(d) at the lag (N per unit step weight)
  /// Gamma: rows 3i..3i+2 are gamma_i T.
  Eigen::Matrix<double, 12, 2> gamma_basis = Eigen::Matrix<double, 12, 2>::Zero();
  /// x~ per point: a0 q_n + a1 q_{n-1} for a body's vertex, the point itself on an obstacle
  contact::Vector12d x_tilde = contact::Vector12d::Zero();
};

class PairFrictionForm : public Form {
 public:
  /// `obstacles` (or null): contact against obstacle meshes, with `mesh_mu` one coefficient per
  /// obstacle mesh. `bodies` (or null): contact between bodies, with `body_mu` the coefficients
  /// between the bodies of ids i and j at (i, j) (square, symmetric). Coefficients must be finite
  /// and >= 0 (0: no friction for those pairs); `eps_v` (m/s) > 0. Throws rbaa::InputError.
  PairFrictionForm(const MeshObstacleForm* obstacles, std::vector<double> mesh_mu,
                   const BodyContactForm* bodies, Eigen::MatrixXd body_mu, double eps_v,
                   Integrator integrator, double time_step);

  /// Lags the pairs closer than d_hat at q_n (the contact forms' active pairs there), their
  /// normal forces, frames and x~ from q_n and q_{n-1}.
  void lag(const Eigen::VectorXd& q_n, const Eigen::VectorXd& q_previous) override;
  /// The pairs closer than d_hat at x, their normal forces and frames from x; x~ from lag()'s
  /// q_n and q_{n-1}.
  void relag(const Eigen::VectorXd& x) override;

  const char* name() const override { return "pair friction"; }
  double value(const Eigen::VectorXd& x) const override;
  /// D(x1) - D(x0) without the cancellation of subtracting two values.
  double value_difference(const Eigen::VectorXd& x0, const Eigen::VectorXd& x1) const override;
  void add_gradient(const Eigen::VectorXd& x, double scale, Eigen::VectorXd& grad) const override;
  void add_hessian(const Eigen::VectorXd& x, double scale, HessianKind kind,
                   SparseHessian& hessian) const override;

  /// bar_n += -(dG/dq_n)^T a and bar_previous += -(dG/dq_{n-1})^T a for G's term w grad D at x.
  void add_history_adjoint(const Eigen::VectorXd& x, const Eigen::VectorXd& a, double w,
                           Eigen::VectorXd& bar_n, Eigen::VectorXd& bar_previous) const override;
  /// out += (dG/dq_n) dq_n + (dG/dq_{n-1}) dq_previous for G's term w grad D at x.
  void add_history_tangent(const Eigen::VectorXd& x, const Eigen::VectorXd& dq_n,
                           const Eigen::VectorXd& dq_previous, double w,
                           Eigen::VectorXd& out) const override;

  int num_lagged_pairs() const { return static_cast<int>(pairs_.size()); }
  const std::vector<LaggedFrictionPair>& lagged_pairs() const { return pairs_; }
  double eps() const { return eps_; }
  /// The rule of the next step (bdf.hpp): x~ = a0 q_n + a1 q_{n-1}, eps = eps_v b. Steps of
  /// another size than the scene's (contact-resolving steps) set it before lag().
  void set_step_rule(const BdfStepRule& rule) {
    a0_ = rule.a0;
    a1_ = rule.a1;
    eps_ = eps_v_ * rule.b;
  }

 private:
  struct Slip {
    Eigen::Vector2d u;
    double y, f1_over_y, c1;
  };
  Slip slip(const LaggedFrictionPair& p, const Eigen::VectorXd& x) const;
  // The pairs closer than d_hat at q_lag, with x~ from q_n_ and q_previous_.
  void lag_at(const Eigen::VectorXd& q_lag);
  // Appends the pair at its points' positions (skipped when mu is 0).
  void add_pair(LaggedFrictionPair p, const contact::Barrier& barrier, double kappa);
  // d lambda / d(the pair's 12 coordinates at q_n), for the lagged distance type.
  contact::Vector12d normal_force_gradient(const LaggedFrictionPair& p) const;
  // J_n = dG_k/dz and J_p = dG_k/dz_previous over the pair's 12 coordinates at q_n and q_{n-1}
  // (without the weight w); rows and columns of obstacle points are zero.
  void history_jacobians(const LaggedFrictionPair& p, const Eigen::VectorXd& x,
                         contact::Matrix12d& J_n, contact::Matrix12d& J_p) const;

  const MeshObstacleForm* obstacles_;
  std::vector<double> mesh_mu_;
  const BodyContactForm* bodies_;
  Eigen::MatrixXd body_mu_;
  double eps_v_;
  double eps_;
  double a0_, a1_;  // x~ = a0 q_n + a1 q_{n-1}
  Eigen::VectorXd q_n_, q_previous_;  // lag()'s history
  std::vector<LaggedFrictionPair> pairs_;
};

/// Whether any coefficient is positive (a PairFrictionForm would do anything).
bool any_pair_friction(const std::vector<double>& mesh_mu, const Eigen::MatrixXd& body_mu);

}  // namespace rbaa
