#pragma once
// The energy one time step minimises: a weighted sum of forms, E(q) = sum_i w_i E_i(q). The
// integrator sets the weights (1 for inertia, (4/9) h^2 or h^2 for the potentials); the Newton
// solver sees only this object.
//
// Fixed (Dirichlet) dofs are eliminated here, so that Newton, the adjoint and the tangent, which
// all see this object, agree: the gradient is zero at them and the Hessian has identity rows and
// columns there (SparseHessian::eliminate_dofs), so a Newton step, an adjoint lambda = H^-1 qbar
// and a tangent solve are exactly zero at fixed dofs when their right-hand side is. The energy
// itself is unchanged (the fixed dofs stay where the caller put them).

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <vector>

#include "rbaa/sim/form.hpp"
#include "rbaa/sim/sparse_hessian.hpp"

namespace rbaa {

class IncrementalPotential {
 public:
  explicit IncrementalPotential(SparseHessian& hessian) : hessian_(hessian) {}

  /// Adds a term (not owned; it must outlive this object).
  void add(Form& form, double weight) { terms_.push_back({&form, weight}); }
  void set_weight(const Form& form, double weight);

  double value(const Eigen::VectorXd& q) const;
  /// E(q1) - E(q0) from the forms' cancellation-free differences.
  double value_difference(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const;
  /// dE/dq with zeros at the fixed dofs.
  Eigen::VectorXd gradient(const Eigen::VectorXd& q) const;
  /// dE/dq everywhere: at the fixed dofs, the step equation's residual that the prescribed
  /// positions leave (the Dirichlet reactions, times the potentials' weight).
  Eigen::VectorXd unconstrained_gradient(const Eigen::VectorXd& q) const;
  /// Assembles the (exact or projected) Hessian into the shared pattern, eliminates the fixed
  /// dofs, and returns it.
  const Eigen::SparseMatrix<double>& hessian(const Eigen::VectorXd& q, HessianKind kind);
  double max_step_size(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const;
  bool is_step_valid(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const;
  /// The forms' CCD searches stopped by their iteration cap so far (Form::ccd_caps).
  long ccd_caps() const;
  void solution_changed(const Eigen::VectorXd& q);

  /// The forms' history hooks (form.hpp), each term with its weight as scale.
  void lag(const Eigen::VectorXd& q_n, const Eigen::VectorXd& q_previous);
  /// Form::relag on every form.
  void relag(const Eigen::VectorXd& x);
  void add_history_adjoint(const Eigen::VectorXd& x, const Eigen::VectorXd& a,
                           Eigen::VectorXd& bar_n, Eigen::VectorXd& bar_previous) const;
  void add_history_tangent(const Eigen::VectorXd& x, const Eigen::VectorXd& dq_n,
                           const Eigen::VectorXd& dq_previous, Eigen::VectorXd& out) const;
  /// The forms' material hooks (form.hpp), each term with its weight as scale.
  void add_material_adjoint(const Eigen::VectorXd& x, const Eigen::VectorXd& a,
                            const MaterialField& materials, MaterialGradient& g) const;
  void add_material_tangent(const Eigen::VectorXd& x, const MaterialGradient& direction,
                            const MaterialField& materials, Eigen::VectorXd& out) const;

  const SparseHessian& hessian_pattern() const { return hessian_; }

  /// Dofs held where they are (ascending, < 3 #V): eliminated from gradient() and hessian().
  void set_fixed_dofs(std::vector<int> dofs);
  const std::vector<int>& fixed_dofs() const { return fixed_dofs_; }
  /// Sets v's fixed entries to zero.
  void zero_fixed(Eigen::VectorXd& v) const {
    for (int d : fixed_dofs_) v[d] = 0.0;
  }

  /// Wall seconds spent inside `form` (every call through this potential) since the last
  /// reset_timers(): what a benchmark weighs a form's cost with (e.g. contact's broad phase,
  /// narrow phase and CCD against a Newton iteration).
  double form_seconds(const Form& form) const;
  void reset_timers();

 private:
  struct Term {
    Form* form;
    double weight;
    mutable double seconds = 0;
  };
  std::vector<Term> terms_;
  SparseHessian& hessian_;
  std::vector<int> fixed_dofs_;
  std::vector<char> fixed_mask_;  // 3 #V flags, empty without fixed dofs
};

}  // namespace rbaa
