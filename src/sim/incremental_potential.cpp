#include "rbaa/sim/incremental_potential.hpp"

#include <algorithm>
#include <cmath>

namespace rbaa {

void IncrementalPotential::set_weight(const Form& form, double weight) {
  for (Term& t : terms_) {
    if (t.form == &form) t.weight = weight;
  }
}

double IncrementalPotential::value(const Eigen::VectorXd& q) const {
  double sum = 0;
  for (const Term& t : terms_) sum += t.weight * t.form->value(q);
  return sum;
}

double IncrementalPotential::value_difference(const Eigen::VectorXd& q0,
                                              const Eigen::VectorXd& q1) const {
  double sum = 0;
  for (const Term& t : terms_) sum += t.weight * t.form->value_difference(q0, q1);
  return sum;
}

Eigen::VectorXd IncrementalPotential::gradient(const Eigen::VectorXd& q) const {
  Eigen::VectorXd g = Eigen::VectorXd::Zero(q.size());
  for (const Term& t : terms_) t.form->add_gradient(q, t.weight, g);
  return g;
}

const Eigen::SparseMatrix<double>& IncrementalPotential::hessian(const Eigen::VectorXd& q,
                                                                 HessianKind kind) {
  hessian_.set_zero();
  for (const Term& t : terms_) t.form->add_hessian(q, t.weight, kind, hessian_);
  return hessian_.assemble();
}

double IncrementalPotential::max_step_size(const Eigen::VectorXd& q0,
                                           const Eigen::VectorXd& q1) const {
  double s = 1.0;
  for (const Term& t : terms_) s = std::min(s, t.form->max_step_size(q0, q1));
  return s;
}

bool IncrementalPotential::is_step_valid(const Eigen::VectorXd& q0,
                                         const Eigen::VectorXd& q1) const {
  if (!q1.allFinite()) return false;
  for (const Term& t : terms_) {
    if (!t.form->is_step_valid(q0, q1)) return false;
  }
  return true;
}

void IncrementalPotential::solution_changed(const Eigen::VectorXd& q) {
  for (const Term& t : terms_) t.form->solution_changed(q);
}

}  // namespace rbaa
