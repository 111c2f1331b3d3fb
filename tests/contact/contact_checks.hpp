#pragma once
// Shared by the contact tests: random configurations of four points and finite-difference checks
// of 12-dof functions (value -> gradient, gradient -> Hessian), in the directions of the unit
// vectors and along the gradient itself.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <random>

#include "rbaa/contact/fixed_size.hpp"

namespace rbaa::test {

using contact::Matrix12d;
using contact::Vector12d;
using Points4 = std::array<Eigen::Vector3d, 4>;

inline Vector12d stack(const Points4& x) {
  Vector12d v;
  v << x[0], x[1], x[2], x[3];
  return v;
}

inline Points4 unstack(const Vector12d& v) {
  return {v.segment<3>(0), v.segment<3>(3), v.segment<3>(6), v.segment<3>(9)};
}

inline Eigen::Vector3d random_point(std::mt19937& rng, double scale = 1.0) {
  std::uniform_real_distribution<double> u(-scale, scale);
  return {u(rng), u(rng), u(rng)};
}

inline Points4 random_points(std::mt19937& rng, double scale = 1.0) {
  return {random_point(rng, scale), random_point(rng, scale), random_point(rng, scale),
          random_point(rng, scale)};
}

/// Central difference of f at x along direction v (unit or not) with step h. The step actually
/// taken is measured after rounding x +- h v, so that steps far below a coordinate's size do not
/// carry its rounding into the quotient.
template <class F>
auto directional_fd(const F& f, const Vector12d& x, const Vector12d& v, double h) {
  const Vector12d xp = x + h * v, xm = x - h * v;
  const double taken = (xp - xm).dot(v) / v.squaredNorm();
  return (f(xp) - f(xm)) / taken;
}

/// Central-difference gradient of a 12-dof scalar function.
inline Vector12d fd_gradient12(const std::function<double(const Vector12d&)>& f, const Vector12d& x,
                               double h) {
  Vector12d g;
  for (int i = 0; i < 12; ++i) g[i] = directional_fd(f, x, Vector12d::Unit(i), h);
  return g;
}

/// Central-difference Jacobian of a 12-dof gradient (the Hessian), column by column.
inline Matrix12d fd_hessian12(const std::function<Vector12d(const Vector12d&)>& g,
                              const Vector12d& x, double h) {
  Matrix12d H;
  for (int i = 0; i < 12; ++i) {
    const Vector12d e = Vector12d::Unit(i);
    const Vector12d xp = x + h * e, xm = x - h * e;
    H.col(i) = (g(xp) - g(xm)) / (xp[i] - xm[i]);
  }
  return H;
}

/// |a - b| / |b|, or |a| if b vanishes.
template <class A, class B>
double rel_err(const A& a, const B& b) {
  const double nb = b.norm();
  return nb > 0 ? (a - b).norm() / nb : a.norm();
}

struct DerivativeErrors {
  double gradient = 0;        ///< FD of the value vs the gradient, all 12 directions
  double along_gradient = 0;  ///< FD of the value along g / |g| vs |g|
  double hessian = 0;         ///< FD of the gradient vs the Hessian, all 12 directions
  double hessian_along = 0;   ///< FD of the gradient along g / |g| vs H g / |g|
  double max() const { return std::max({gradient, along_gradient, hessian, hessian_along}); }
};

/// All four checks of (f, g, H) at x with step h.
inline DerivativeErrors check_derivatives(const std::function<double(const Vector12d&)>& f,
                                          const std::function<Vector12d(const Vector12d&)>& g,
                                          const std::function<Matrix12d(const Vector12d&)>& H,
                                          const Vector12d& x, double h) {
  DerivativeErrors e;
  const Vector12d g0 = g(x);
  const Matrix12d H0 = H(x);
  e.gradient = rel_err(g0, fd_gradient12(f, x, h));
  e.hessian = rel_err(H0, fd_hessian12(g, x, h));
  if (g0.norm() > 0) {
    const Vector12d v = g0.normalized();
    const double slope = directional_fd(f, x, v, h);
    e.along_gradient = std::abs(slope - g0.norm()) / g0.norm();
    const Vector12d xp = x + h * v, xm = x - h * v;
    const Vector12d Hv_fd = (g(xp) - g(xm)) / ((xp - xm).dot(v));
    e.hessian_along = rel_err(Vector12d(H0 * v), Hv_fd);
  }
  return e;
}

}  // namespace rbaa::test

namespace rbaa::test {

/// Sine of the angle between two directions.
inline double sin_angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return a.cross(b).norm() / (a.norm() * b.norm());
}

/// Smallest height of a triangle (twice its area over its longest edge).
inline double min_height(const Eigen::Vector3d& t0, const Eigen::Vector3d& t1,
                         const Eigen::Vector3d& t2) {
  const double longest = std::max({(t1 - t0).norm(), (t2 - t1).norm(), (t0 - t2).norm()});
  return (t1 - t0).cross(t2 - t0).norm() / longest;
}

}  // namespace rbaa::test
