// Point-point, point-line and point-edge squared distances: gradients and Hessians against
// finite differences (in every coordinate and along the gradient), and the point-edge distance
// against brute-force sampling of the edge.

#include <gtest/gtest.h>

#include <cstdio>

#include "contact_checks.hpp"
#include "rbaa/contact/point_edge.hpp"
#include "rbaa/contact/point_line.hpp"
#include "rbaa/contact/point_point.hpp"

namespace rbaa::contact {
namespace {

using test::Points4;
using test::stack;
using test::unstack;

// The 6- and 9-dof functions as 12-dof ones of (x0, x1, x2, x3), the unused points' entries zero.
double pp(const Vector12d& v) {
  const Points4 x = unstack(v);
  return point_point_distance(x[0], x[1]);
}
Vector12d pp_grad(const Vector12d& v) {
  const Points4 x = unstack(v);
  Vector12d g = Vector12d::Zero();
  g.head<6>() = point_point_distance_gradient(x[0], x[1]);
  return g;
}
Matrix12d pp_hess(const Vector12d& v) {
  const Points4 x = unstack(v);
  Matrix12d H = Matrix12d::Zero();
  H.topLeftCorner<6, 6>() = point_point_distance_hessian(x[0], x[1]);
  return H;
}

template <class Dist, class Grad, class Hess>
test::DerivativeErrors check_9dof(Dist dist, Grad grad, Hess hess, const Points4& x, double h) {
  return test::check_derivatives(
      [&](const Vector12d& v) {
        const Points4 y = unstack(v);
        return dist(y[0], y[1], y[2]);
      },
      [&](const Vector12d& v) {
        const Points4 y = unstack(v);
        Vector12d g = Vector12d::Zero();
        g.head<9>() = grad(y[0], y[1], y[2]);
        return g;
      },
      [&](const Vector12d& v) {
        const Points4 y = unstack(v);
        Matrix12d H = Matrix12d::Zero();
        H.topLeftCorner<9, 9>() = hess(y[0], y[1], y[2]);
        return H;
      },
      stack(x), h);
}

TEST(ContactPointEdge, PointPointDerivatives) {
  std::mt19937 rng(1);
  double worst = 0;
  for (int i = 0; i < 200; ++i) {
    const Points4 x = test::random_points(rng);
    worst = std::max(worst, test::check_derivatives(pp, pp_grad, pp_hess, stack(x), 1e-6).max());
  }
  // A quadratic: central differences are exact up to rounding (1e-16 |d| / 1e-6 |g|).
  EXPECT_LT(worst, 1e-8);
}

// Random points and edges no shorter than 0.2 (the derivatives' third-order scale is the edge
// length): with h = 1e-6, truncation ~ (h / 0.2)^2 and rounding ~ 1e-16 / h leave ~1e-10.
TEST(ContactPointEdge, PointLineDerivatives) {
  std::mt19937 rng(2);
  double worst = 0;
  int n = 0;
  while (n < 300) {
    const Points4 x = test::random_points(rng);
    if ((x[2] - x[1]).norm() < 0.2) continue;
    ++n;
    const auto e =
        check_9dof([](const auto&... a) { return point_line_distance(a...); },
                   [](const auto&... a) { return point_line_distance_gradient(a...); },
                   [](const auto&... a) { return point_line_distance_hessian(a...); }, x, 1e-6);
    worst = std::max(worst, e.max());
  }
  std::printf("point-line: worst relative FD error %.2e\n", worst);
  EXPECT_LT(worst, 1e-7);
}

// The point-edge distance with the type fixed at the base point (the type is chosen once per
// evaluation; a finite difference across a region boundary would mix two formulas), and with the
// type chosen at every evaluation, whose gradient FD must match as well since the squared
// distance to a segment is C1.
TEST(ContactPointEdge, PointEdgeDerivativesInEveryRegion) {
  std::mt19937 rng(3);
  double worst = 0, worst_auto = 0;
  int per_type[3] = {0, 0, 0};
  int n = 0;
  while (n < 600) {
    const Points4 x = test::random_points(rng);
    if ((x[2] - x[1]).norm() < 0.2) continue;
    ++n;
    const PointEdgeDistanceType type = point_edge_distance_type(x[0], x[1], x[2]);
    ++per_type[static_cast<int>(type)];
    const auto e = check_9dof(
        [&](const auto&... a) { return point_edge_distance(a..., type); },
        [&](const auto&... a) { return point_edge_distance_gradient(a..., type); },
        [&](const auto&... a) { return point_edge_distance_hessian(a..., type); }, x, 1e-6);
    worst = std::max(worst, e.max());
    const auto automatic =
        check_9dof([&](const auto&... a) { return point_edge_distance(a...); },
                   [&](const auto&... a) { return point_edge_distance_gradient(a...); },
                   [&](const auto&... a) { return point_edge_distance_hessian(a...); }, x, 1e-6);
    worst_auto = std::max({worst_auto, automatic.gradient, automatic.along_gradient});
  }
  for (int count : per_type) EXPECT_GT(count, 50);
  std::printf("point-edge: worst FD error %.2e (fixed type), %.2e (gradient, type per call)\n",
              worst, worst_auto);
  EXPECT_LT(worst, 1e-7);
  EXPECT_LT(worst_auto, 1e-7);
}

// Points at distances 1e-1 .. 1e-9 from the middle of an edge of length 1 (down to 1e-9 d_hat
// for d_hat ~ the edge length). The squared distance has no singularity at d = 0, but its
// gradient shrinks like 2d while its third derivatives (through the edge's points) stay O(1):
// with step h the truncation error is ~h^2 / d relative, and rounding (the coordinates are ~1, so
// d^2 carries an absolute error ~2d eps) gives eps / h. Both balance at h = cbrt(eps d), where
// the error is ~(eps^2 / d)^(1/3): 2e-8 at d = 1e-9.
TEST(ContactPointEdge, PointLineDerivativesAtSmallDistances) {
  std::mt19937 rng(4);
  for (double d : {1e-1, 1e-3, 1e-6, 1e-9}) {
    double worst = 0;
    for (int i = 0; i < 50; ++i) {
      const Eigen::Vector3d e0 = test::random_point(rng, 0.5);
      const Eigen::Vector3d dir = test::random_point(rng).normalized();
      const Eigen::Vector3d e1 = e0 + dir;
      const Eigen::Vector3d off = test::random_point(rng).cross(dir).normalized();
      const Points4 x = {e0 + 0.4 * dir + d * off, e0, e1, Eigen::Vector3d::Zero()};
      EXPECT_NEAR(std::sqrt(point_line_distance(x[0], x[1], x[2])), d, 1e-15 + 1e-9 * d);
      const auto e = check_9dof([](const auto&... a) { return point_line_distance(a...); },
                                [](const auto&... a) { return point_line_distance_gradient(a...); },
                                [](const auto&... a) { return point_line_distance_hessian(a...); },
                                x, std::cbrt(1e-16 * d));
      worst = std::max(worst, std::max(e.gradient, e.along_gradient));
    }
    std::printf("point-line at d = %.0e: worst gradient FD error %.2e\n", d, worst);
    EXPECT_LT(worst, 1e-6) << d;
  }
}

TEST(ContactPointEdge, PointEdgeMatchesSampling) {
  std::mt19937 rng(5);
  for (int i = 0; i < 200; ++i) {
    const Points4 x = test::random_points(rng);
    double best = std::numeric_limits<double>::infinity();
    const int samples = 20000;
    for (int k = 0; k <= samples; ++k) {
      const double t = double(k) / samples;
      best = std::min(best, (x[0] - ((1 - t) * x[1] + t * x[2])).squaredNorm());
    }
    const double d = point_edge_distance(x[0], x[1], x[2]);
    EXPECT_LE(d, best + 1e-14);
    // The closest sample is within half a spacing (|e| / 2 samples) of the closest point.
    const double slack = (x[2] - x[1]).norm() / (2.0 * samples);
    EXPECT_LE(std::sqrt(best) - std::sqrt(d), slack + 1e-12);
  }
}

}  // namespace
}  // namespace rbaa::contact
