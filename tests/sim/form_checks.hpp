#pragma once
// Shared checks of a form's gradient and Hessian against central finite differences.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "finite_differences.hpp"
#include "rbaa/sim/form.hpp"
#include "rbaa/sim/sparse_hessian.hpp"

namespace rbaa::test {

inline Eigen::VectorXd form_gradient(const Form& f, const Eigen::VectorXd& q) {
  Eigen::VectorXd g = Eigen::VectorXd::Zero(q.size());
  f.add_gradient(q, 1.0, g);
  return g;
}

inline Eigen::MatrixXd form_hessian(const Form& f, const Eigen::VectorXd& q, HessianKind kind,
                                    SparseHessian& H) {
  H.set_zero();
  f.add_hessian(q, 1.0, kind, H);
  Eigen::SparseMatrix<double> full = H.assemble().selfadjointView<Eigen::Lower>();
  return Eigen::MatrixXd(full);
}

struct FdErrors {
  double gradient = 0;  ///< relative error of the gradient (0 if both vanish)
  double hessian = 0;   ///< relative error of the exact Hessian
};

/// Relative errors of the analytic gradient and exact Hessian of `f` at q against central
/// differences with step eps (the gradient's error is measured against the Hessian's scale when
/// the gradient vanishes, e.g. at rest).
inline FdErrors check_form(const Form& f, const Eigen::VectorXd& q, double eps, SparseHessian& H) {
  FdErrors e;
  const Eigen::VectorXd g = form_gradient(f, q);
  const Eigen::VectorXd g_fd = fd_gradient([&](const Eigen::VectorXd& x) { return f.value(x); }, q, eps);
  const Eigen::MatrixXd Hx = form_hessian(f, q, HessianKind::kExact, H);
  const Eigen::MatrixXd H_fd =
      fd_jacobian([&](const Eigen::VectorXd& x) { return form_gradient(f, x); }, q, eps);
  const double g_scale = std::max(g_fd.norm(), Hx.norm() * eps);
  e.gradient = (g - g_fd).norm() / g_scale;
  e.hessian = H_fd.norm() > 0 ? relative_error(Hx, H_fd) : Hx.norm();
  return e;
}

}  // namespace rbaa::test
