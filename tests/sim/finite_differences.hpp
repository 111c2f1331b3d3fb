#pragma once
// Central finite differences for the forms' derivative tests, and the Richardson-extrapolated one
// that the adjoint tests take of whole runs.

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

/// Five-point (fourth-order) central-difference gradient: truncation (eps / l)^4 for features of
/// size l, so that eps can stay well above round-off where l is small (contact at 1e-9 m).
inline Eigen::VectorXd fd_gradient5(const std::function<double(const Eigen::VectorXd&)>& f,
                                    const Eigen::VectorXd& x, double eps) {
  Eigen::VectorXd g(x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    auto at = [&](double h) {
      Eigen::VectorXd y = x;
      y[i] += h;
      return f(y);
    };
    g[i] = (8 * (at(eps) - at(-eps)) - (at(2 * eps) - at(-2 * eps))) / (12 * eps);
  }
  return g;
}

/// Five-point (fourth-order) central-difference Jacobian of a vector function.
inline Eigen::MatrixXd fd_jacobian5(
    const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& g, const Eigen::VectorXd& x,
    double eps) {
  Eigen::MatrixXd J;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    auto at = [&](double h) {
      Eigen::VectorXd y = x;
      y[i] += h;
      return g(y);
    };
    const Eigen::VectorXd col =
        (8 * (at(eps) - at(-eps)) - (at(2 * eps) - at(-2 * eps))) / (12 * eps);
    if (J.size() == 0) J.resize(col.size(), x.size());
    J.col(i) = col;
  }
  return J;
}

/// f'(0) from central differences at s and s / 2, Richardson-extrapolated:
///   (4 D(s / 2) - D(s)) / 3,  D(h) = (f(h) - f(-h)) / (2 h),
/// whose error is O(s^4) where D's is O(s^2); f is typically a run's objective along a direction.
inline double richardson_central_difference(const std::function<double(double)>& f, double s) {
  auto D = [&](double h) { return (f(h) - f(-h)) / (2 * h); };
  return (4 * D(s / 2) - D(s)) / 3;
}

/// |a - b| / |b| (Frobenius).
inline double relative_error(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).norm() / b.norm();
}

}  // namespace rbaa::test
