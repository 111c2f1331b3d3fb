#include "rbaa/sim/incremental_potential.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace rbaa {

namespace {

// Adds the wall time of its scope to `seconds` (a few tens of ns per call).
class ScopeTimer {
 public:
  explicit ScopeTimer(double& seconds) : seconds_(seconds), start_(std::chrono::steady_clock::now()) {}
  ~ScopeTimer() {
    seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  double& seconds_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace

double IncrementalPotential::form_seconds(const Form& form) const {
  double s = 0;
  for (const Term& t : terms_) {
    if (t.form == &form) s += t.seconds;
  }
  return s;
}

void IncrementalPotential::reset_timers() {
  for (Term& t : terms_) t.seconds = 0;
}

void IncrementalPotential::set_weight(const Form& form, double weight) {
  for (Term& t : terms_) {
    if (t.form == &form) t.weight = weight;
  }
}

double IncrementalPotential::value(const Eigen::VectorXd& q) const {
  double sum = 0;
  for (const Term& t : terms_) {
    const ScopeTimer timer(t.seconds);
    sum += t.weight * t.form->value(q);
  }
  return sum;
}

double IncrementalPotential::value_difference(const Eigen::VectorXd& q0,
                                              const Eigen::VectorXd& q1) const {
  double sum = 0;
  for (const Term& t : terms_) {
    const ScopeTimer timer(t.seconds);
    sum += t.weight * t.form->value_difference(q0, q1);
  }
  return sum;
}

Eigen::VectorXd IncrementalPotential::unconstrained_gradient(const Eigen::VectorXd& q) const {
  Eigen::VectorXd g = Eigen::VectorXd::Zero(q.size());
  for (const Term& t : terms_) {
    const ScopeTimer timer(t.seconds);
    t.form->add_gradient(q, t.weight, g);
  }
  return g;
}

Eigen::VectorXd IncrementalPotential::gradient(const Eigen::VectorXd& q) const {
  Eigen::VectorXd g = unconstrained_gradient(q);
  zero_fixed(g);
  return g;
}

void IncrementalPotential::set_fixed_dofs(std::vector<int> dofs) {
  fixed_dofs_ = std::move(dofs);
  fixed_mask_.clear();
  if (fixed_dofs_.empty()) return;
  fixed_mask_.assign(hessian_.rows(), 0);
  for (int d : fixed_dofs_) fixed_mask_.at(d) = 1;
}

const Eigen::SparseMatrix<double>& IncrementalPotential::hessian(const Eigen::VectorXd& q,
                                                                 HessianKind kind) {
  hessian_.set_zero();
  // Forms writing element blocks last: the in-order element sums (SparseHessian::
  // begin_elements_in_order) start from the other forms' direct values. Only the order of
  // independent buffers changes: the matrix is the same.
  for (const bool elements : {false, true}) {
    for (const Term& t : terms_) {
      if (t.form->writes_element_blocks() != elements) continue;
      const ScopeTimer timer(t.seconds);
      t.form->add_hessian(q, t.weight, kind, hessian_);
    }
  }
  hessian_.assemble();
  if (!fixed_mask_.empty()) hessian_.eliminate_dofs(fixed_mask_);
  return hessian_.matrix();
}

double IncrementalPotential::max_step_size(const Eigen::VectorXd& q0,
                                           const Eigen::VectorXd& q1) const {
  double s = 1.0;
  for (const Term& t : terms_) {
    const ScopeTimer timer(t.seconds);
    s = std::min(s, t.form->max_step_size(q0, q1));
  }
  return s;
}

bool IncrementalPotential::is_step_valid(const Eigen::VectorXd& q0,
                                         const Eigen::VectorXd& q1) const {
  if (!q1.allFinite()) return false;
  for (const Term& t : terms_) {
    const ScopeTimer timer(t.seconds);
    if (!t.form->is_step_valid(q0, q1)) return false;
  }
  return true;
}

long IncrementalPotential::ccd_caps() const {
  long n = 0;
  for (const Term& t : terms_) n += t.form->ccd_caps();
  return n;
}

void IncrementalPotential::solution_changed(const Eigen::VectorXd& q) {
  for (const Term& t : terms_) {
    const ScopeTimer timer(t.seconds);
    t.form->solution_changed(q);
  }
}

void IncrementalPotential::lag(const Eigen::VectorXd& q_n, const Eigen::VectorXd& q_previous) {
  for (const Term& t : terms_) {
    const ScopeTimer timer(t.seconds);
    t.form->lag(q_n, q_previous);
  }
}

void IncrementalPotential::relag(const Eigen::VectorXd& x) {
  for (const Term& t : terms_) {
    const ScopeTimer timer(t.seconds);
    t.form->relag(x);
  }
}

void IncrementalPotential::add_history_adjoint(const Eigen::VectorXd& x, const Eigen::VectorXd& a,
                                               Eigen::VectorXd& bar_n,
                                               Eigen::VectorXd& bar_previous) const {
  for (const Term& t : terms_) t.form->add_history_adjoint(x, a, t.weight, bar_n, bar_previous);
}

void IncrementalPotential::add_history_tangent(const Eigen::VectorXd& x, const Eigen::VectorXd& dq_n,
                                               const Eigen::VectorXd& dq_previous,
                                               Eigen::VectorXd& out) const {
  for (const Term& t : terms_) t.form->add_history_tangent(x, dq_n, dq_previous, t.weight, out);
}

void IncrementalPotential::add_material_adjoint(const Eigen::VectorXd& x, const Eigen::VectorXd& a,
                                                const MaterialField& materials,
                                                MaterialGradient& g) const {
  for (const Term& t : terms_) t.form->add_material_adjoint(x, a, t.weight, materials, g);
}

void IncrementalPotential::add_material_tangent(const Eigen::VectorXd& x,
                                                const MaterialGradient& direction,
                                                const MaterialField& materials,
                                                Eigen::VectorXd& out) const {
  for (const Term& t : terms_) t.form->add_material_tangent(x, direction, t.weight, materials, out);
}

}  // namespace rbaa
