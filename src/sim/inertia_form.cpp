#include "rbaa/sim/inertia_form.hpp"

#include "rbaa/sim/parallel.hpp"

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

void InertiaForm::add_material_adjoint(const Eigen::VectorXd& x, const Eigen::VectorXd& a,
                                       double scale, const MaterialField& materials,
                                       MaterialGradient& g) const {
  const Eigen::VectorXd u = x - q_hat_;
  const int nt = unit_.num_elements();
#pragma omp parallel for schedule(static) if (nt > kParallelCheapElements)
  for (int e = 0; e < nt; ++e) unit_.add_mass_gradient(e, -scale * unit_.product(e, a, u), materials, g);
}

void InertiaForm::add_material_tangent(const Eigen::VectorXd& x, const MaterialGradient& direction,
                                       double scale, const MaterialField& materials,
                                       Eigen::VectorXd& out) const {
  if (direction.rho.size() == 0 && direction.alpha.size() == 0) return;
  const Eigen::VectorXd u = x - q_hat_;
  for (int e = 0; e < unit_.num_elements(); ++e) {
    const double dm = unit_.mass_change(e, materials, direction);
    if (dm != 0.0) unit_.add_times(e, scale * dm, u, out);
  }
}

}  // namespace rbaa
