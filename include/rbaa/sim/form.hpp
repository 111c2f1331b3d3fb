#pragma once
// A form is one energy term of a time step's incremental potential (inertia, elasticity, gravity,
// contact): value, gradient and Hessian behind one interface, summed with weights by the
// IncrementalPotential. Besides derivatives every form answers max_step_size and is_step_valid,
// so the line search asks the forms (the contact form runs CCD) instead of knowing about contact
// (the PolyFEM design, STYLE.md). For the adjoint and the tangent-linear pass each form also
// answers how its term of the step equation depends on the history positions and on the
// materials (the hooks below), so that the backward pass sums over forms and names none.

#include <Eigen/Core>

#include "rbaa/material/material_field.hpp"
#include "rbaa/sim/sparse_hessian.hpp"

namespace rbaa {

/// Which Hessian a form assembles: the exact one, or its PSD projection (per element / pair).
enum class HessianKind { kExact, kProjected };

class Form {
 public:
  virtual ~Form() = default;

  /// Short name for reports and errors ("elastic", "contact", ...).
  virtual const char* name() const = 0;

  /// Energy at the stacked positions q (3 #V).
  virtual double value(const Eigen::VectorXd& q) const = 0;
  /// value(q1) - value(q0). Forms override this where subtracting two values would cancel.
  virtual double value_difference(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const {
    return value(q1) - value(q0);
  }
  /// grad += scale * dE/dq.
  virtual void add_gradient(const Eigen::VectorXd& q, double scale, Eigen::VectorXd& grad) const = 0;
  /// Adds scale * d2E/dq2 (exact or PSD-projected) to the Hessian's buffers.
  virtual void add_hessian(const Eigen::VectorXd& q, double scale, HessianKind kind,
                           SparseHessian& hessian) const = 0;
  /// Whether add_hessian writes element blocks (SparseHessian::element_block or the in-order
  /// sums): IncrementalPotential assembles such forms after the others, whose direct values
  /// the in-order sums need first.
  virtual bool writes_element_blocks() const { return false; }

  /// Largest fraction t in (0, 1] of the step q0 -> q1 that the form allows (CCD for contact).
  virtual double max_step_size(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const {
    return 1.0;
  }
  /// Whether q1 (reached from q0) is admissible (e.g. no vertex on or beyond an obstacle).
  virtual bool is_step_valid(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const {
    return true;
  }
  /// How many CCD searches of max_step_size and is_step_valid the iteration cap stopped since
  /// construction (contact/additive_ccd.hpp). Each such answer stays safe, only shorter than it
  /// need be: max_step_size then shortens the step, is_step_valid refuses it.
  virtual long ccd_caps() const { return 0; }
  /// Called by the solver whenever its iterate changes (contact forms rebuild their pair set).
  virtual void solution_changed(const Eigen::VectorXd& q) {}

  // History hooks, for forms whose energy at step n+1 depends on earlier positions other than
  // through the predictor q_hat (lagged friction: its normal forces, tangent bases and x~). The
  // simulator calls lag(q_n, q_{n-1}) before each step; the backward pass and the tangent-linear
  // pass call it again before linearising that step, then ask for the terms of the step equation
  // G = ... + scale grad E(x; q_n, q_{n-1}) = 0 in the history positions. The adjoint and the
  // tangent sum these over the forms and never name one.

  /// Fixes the form's dependence on the newest position q_n and the one before it.
  virtual void lag(const Eigen::VectorXd& q_n, const Eigen::VectorXd& q_previous) {}
  /// Re-takes the lag at x, the step's solution so far, keeping what lag() took from the history
  /// (friction's x~ from q_n and q_{n-1}): the pairs, normal forces and frames are then x's.
  /// Forward runs only (SimulationSettings::friction_iterations): the history hooks below
  /// differentiate the lag at q_n.
  virtual void relag(const Eigen::VectorXd& x) {}
  /// bar_n += -(dG/dq_n)^T a and bar_previous += -(dG/dq_{n-1})^T a for G's term scale grad E at x.
  virtual void add_history_adjoint(const Eigen::VectorXd& x, const Eigen::VectorXd& a, double scale,
                                   Eigen::VectorXd& bar_n, Eigen::VectorXd& bar_previous) const {}
  /// out += (dG/dq_n) dq_n + (dG/dq_{n-1}) dq_previous for G's term scale grad E at x.
  virtual void add_history_tangent(const Eigen::VectorXd& x, const Eigen::VectorXd& dq_n,
                                   const Eigen::VectorXd& dq_previous, double scale,
                                   Eigen::VectorXd& out) const {}

  // Material hooks: how G's term scale grad E at fixed positions x depends on the per-element
  // materials (Y, nu, rho, alpha; `materials` is the field the step was taken with). Forms whose
  // energy does not depend on the materials (contact, friction) keep the defaults.

  /// g += -(dG/dtheta)^T a, per element and field.
  virtual void add_material_adjoint(const Eigen::VectorXd& x, const Eigen::VectorXd& a, double scale,
                                    const MaterialField& materials, MaterialGradient& g) const {}
  /// out += (dG/dtheta) direction (a direction's empty fields are zero).
  virtual void add_material_tangent(const Eigen::VectorXd& x, const MaterialGradient& direction,
                                    double scale, const MaterialField& materials,
                                    Eigen::VectorXd& out) const {}
};

}  // namespace rbaa
