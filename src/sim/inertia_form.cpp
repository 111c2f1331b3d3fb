#include "rbaa/sim/inertia_form.hpp"

namespace rbaa {

Eigen::VectorXd InertiaForm::multiply(const Eigen::VectorXd& x) const {
  return M_.selfadjointView<Eigen::Lower>() * x;
}

double InertiaForm::value(const Eigen::VectorXd& q) const {
  const Eigen::VectorXd d = q - q_hat_;
  return 0.5 * d.dot(multiply(d));
}

double InertiaForm::value_difference(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const {
  const Eigen::VectorXd dq = q1 - q0;
  const Eigen::VectorXd Mdq = multiply(dq);
  return Mdq.dot(q0 - q_hat_) + 0.5 * dq.dot(Mdq);
}

void InertiaForm::add_gradient(const Eigen::VectorXd& q, double scale, Eigen::VectorXd& grad) const {
  grad += scale * multiply(q - q_hat_);
}

void InertiaForm::add_hessian(const Eigen::VectorXd& q, double scale, HessianKind kind,
                              SparseHessian& hessian) const {
  hessian.add_matrix(scale, M_);
}

}  // namespace rbaa
