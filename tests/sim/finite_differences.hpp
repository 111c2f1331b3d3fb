#pragma once
// Central finite differences for the forms' derivative tests.

#include <Eigen/Core>

#include <functional>

namespace rbaa::test {

/// Central-difference gradient of f at x with step eps.
inline Eigen::VectorXd fd_gradient(const std::function<double(const Eigen::VectorXd&)>& f,
                                   const Eigen::VectorXd& x, double eps) {
  Eigen::VectorXd g(x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    Eigen::VectorXd xp = x, xm = x;
    xp[i] += eps;
    xm[i] -= eps;
    g[i] = (f(xp) - f(xm)) / (2 * eps);
  }
  return g;
}

/// Central-difference Jacobian of a vector function (the Hessian from a gradient).
inline Eigen::MatrixXd fd_jacobian(
    const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& g, const Eigen::VectorXd& x,
    double eps) {
  const Eigen::VectorXd g0 = g(x);
  Eigen::MatrixXd J(g0.size(), x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    Eigen::VectorXd xp = x, xm = x;
    xp[i] += eps;
    xm[i] -= eps;
    J.col(i) = (g(xp) - g(xm)) / (2 * eps);
  }
  return J;
}

/// |a - b| / |b| (Frobenius).
inline double relative_error(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).norm() / b.norm();
}

}  // namespace rbaa::test
