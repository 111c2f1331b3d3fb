// Line-line and edge-edge squared distances: gradients and Hessians against finite differences
// for every feature pair, nearly parallel (1e-6 rad) and exactly parallel edges, against
// brute-force sampling of both edges, and symmetry (swapping or reversing the edges, rigid motion).

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <limits>

#include "contact_checks.hpp"
#include "rbaa/contact/edge_edge.hpp"
#include "rbaa/contact/line_line.hpp"

namespace rbaa::contact {
namespace {

using test::Points4;
using test::stack;
using test::unstack;
using T = EdgeEdgeDistanceType;

test::DerivativeErrors check_lines(const Points4& x, double h) {
  return test::check_derivatives(
      [](const Vector12d& v) {
        const Points4 y = unstack(v);
        return line_line_distance(y[0], y[1], y[2], y[3]);
      },
      [](const Vector12d& v) {
        const Points4 y = unstack(v);
        return line_line_distance_gradient(y[0], y[1], y[2], y[3]);
      },
      [](const Vector12d& v) {
        const Points4 y = unstack(v);
        return line_line_distance_hessian(y[0], y[1], y[2], y[3]);
      },
      stack(x), h);
}

test::DerivativeErrors check_edges(const Points4& x, T type, double h) {
  return test::check_derivatives(
      [=](const Vector12d& v) {
        const Points4 y = unstack(v);
        return edge_edge_distance(y[0], y[1], y[2], y[3], type);
      },
      [=](const Vector12d& v) {
        const Points4 y = unstack(v);
        return edge_edge_distance_gradient(y[0], y[1], y[2], y[3], type);
      },
      [=](const Vector12d& v) {
        const Points4 y = unstack(v);
        return edge_edge_distance_hessian(y[0], y[1], y[2], y[3], type);
      },
      stack(x), h);
}

test::DerivativeErrors check_edges_auto(const Points4& x, double h) {
  return test::check_derivatives(
      [](const Vector12d& v) {
        const Points4 y = unstack(v);
        return edge_edge_distance(y[0], y[1], y[2], y[3]);
      },
      [](const Vector12d& v) {
        const Points4 y = unstack(v);
        return edge_edge_distance_gradient(y[0], y[1], y[2], y[3]);
      },
      [](const Vector12d& v) {
        const Points4 y = unstack(v);
        return edge_edge_distance_hessian(y[0], y[1], y[2], y[3]);
      },
      stack(x), h);
}

// Edges no shorter than 0.2 and at least asin(0.2) from parallel: the scale of the derivatives'
// third order, so that h = 1e-6 leaves truncation ~(h / 0.2)^2 and rounding ~1e-16 / h.
Points4 random_edges(std::mt19937& rng) {
  for (;;) {
    const Points4 x = test::random_points(rng);
    const Eigen::Vector3d a = x[1] - x[0], b = x[3] - x[2];
    if (a.norm() >= 0.2 && b.norm() >= 0.2 && test::sin_angle(a, b) >= 0.2) return x;
  }
}

TEST(ContactEdgeEdge, LineLineDerivatives) {
  std::mt19937 rng(21);
  double worst = 0;
  for (int i = 0; i < 300; ++i) worst = std::max(worst, check_lines(random_edges(rng), 1e-6).max());
  std::printf("line-line: worst relative FD error %.2e\n", worst);
  EXPECT_LT(worst, 1e-7);
}

TEST(ContactEdgeEdge, DerivativesForEveryFeaturePair) {
  std::mt19937 rng(22);
  double worst = 0, worst_auto = 0;
  int per_type[9] = {};
  for (int i = 0; i < 3000; ++i) {
    Points4 x = random_edges(rng);
    // Shorter edges spread apart reach the endpoint-endpoint cases more often.
    if (i % 2) {
      x[1] = x[0] + 0.3 * (x[1] - x[0]);
      x[3] = x[2] + 0.3 * (x[3] - x[2]);
    }
    const T type = edge_edge_distance_type(x[0], x[1], x[2], x[3]);
    ++per_type[static_cast<int>(type)];
    worst = std::max(worst, check_edges(x, type, 1e-6).max());
    const auto a = check_edges_auto(x, 1e-6);
    worst_auto = std::max({worst_auto, a.gradient, a.along_gradient});
  }
  for (int t = 0; t < 9; ++t) EXPECT_GT(per_type[t], 30) << to_string(static_cast<T>(t));
  std::printf("edge-edge: worst FD error %.2e (fixed type), %.2e (gradient, type per call)\n",
              worst, worst_auto);
  EXPECT_LT(worst, 1e-7);
  EXPECT_LT(worst_auto, 1e-7);
}

#ifdef __SIZEOF_FLOAT128__
// The line-line distance in quadruple precision (GCC's __float128, 113-bit significand), as the
// reference for finite differences where double precision cannot resolve them.
double line_line_distance_quad_fd(const Vector12d& x, int i, double h) {
  using Q = __float128;
  const auto f = [](const Vector12d& v) {
    Q a[3], b[3], r[3];
    for (int k = 0; k < 3; ++k) {
      a[k] = Q(v[3 + k]) - Q(v[k]);
      b[k] = Q(v[9 + k]) - Q(v[6 + k]);
      r[k] = Q(v[k]) - Q(v[6 + k]);
    }
    const Q n[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                    a[0] * b[1] - a[1] * b[0]};
    const Q s = r[0] * n[0] + r[1] * n[1] + r[2] * n[2];
    return s * s / (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  };
  Vector12d xp = x, xm = x;
  xp[i] += h;
  xm[i] -= h;
  return static_cast<double>((f(xp) - f(xm)) / Q(xp[i] - xm[i]));
}
#endif

// Edges 1e-6 rad from parallel whose lines cross (in projection) inside both: the line-line case
// at its worst conditioning before the parallel switch (1e-10 rad). Here |g| ~ 2 gap while
// |H| ~ gap^2 / theta^2 (turning an edge by h / |a| swings the common normal by h / (|a| theta)),
// so the gradient is ill-conditioned: rounding the inputs by eps |x| alone moves it by
// eps |H| |x|, a relative ~eps |H| |x| / |g| (~4e-5 here), and no double formula can do much
// better. A double finite difference of the value cannot check it (the value's own rounding,
// ~eps / theta relative, over h is far larger than |g|), so the value is differenced in quadruple
// precision. The Hessian is differenced from the gradient in double: truncation ~(h / theta)^2,
// rounding ~eps |H| |x| / (h |H|) = eps |x| / h; at h = 1e-4 theta both are ~1e-8 .. 1e-6.
TEST(ContactEdgeEdge, NearlyParallelLines) {
#ifndef __SIZEOF_FLOAT128__
  GTEST_SKIP() << "needs __float128 for the reference";
#else
  const double theta = 1e-6, eps = std::numeric_limits<double>::epsilon();
  std::mt19937 rng(23);
  double worst_g = 0, worst_H = 0;
  for (int i = 0; i < 50; ++i) {
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(i, test::random_point(rng).normalized()).toRotationMatrix();
    const Eigen::Vector3d dir(std::cos(theta), std::sin(theta), 0);
    const double gap = 0.1 + 0.01 * i;
    Points4 x = {Eigen::Vector3d(-0.5, 0, 0), Eigen::Vector3d(0.5, 0, 0),
                 Eigen::Vector3d(0.1, 0, gap) - 0.5 * dir,
                 Eigen::Vector3d(0.1, 0, gap) + 0.5 * dir};
    for (auto& p : x) p = R * p;
    ASSERT_EQ(edge_edge_distance_type(x[0], x[1], x[2], x[3]), T::EA_EB);
    EXPECT_NEAR(std::sqrt(edge_edge_distance(x[0], x[1], x[2], x[3])), gap, 1e-9);

    const Vector12d v = stack(x);
    const Vector12d g = line_line_distance_gradient(x[0], x[1], x[2], x[3]);
    const Matrix12d H = line_line_distance_hessian(x[0], x[1], x[2], x[3]);
    Vector12d g_fd;
    for (int k = 0; k < 12; ++k) g_fd[k] = line_line_distance_quad_fd(v, k, 1e-12);
    const double conditioning = eps * H.norm() * v.cwiseAbs().maxCoeff() / g.norm();
    const double err_g = test::rel_err(g, g_fd);
    EXPECT_LT(err_g, conditioning) << i;
    worst_g = std::max(worst_g, err_g / conditioning);

    const auto e = check_lines(x, 1e-4 * theta);
    // Along the gradient, H g / |g| is ~1e-3 |H| (the gradient points away from the stiff
    // turning directions) while the rounding is relative to |H|: measure it so.
    const double along = e.hessian_along * (H * g.normalized()).norm() / H.norm();
    worst_H = std::max({worst_H, e.hessian, along});
  }
  std::printf("line-line at 1e-6 rad: gradient error <= %.2f x its conditioning, Hessian FD %.2e\n",
              worst_g, worst_H);
  EXPECT_LT(worst_H, 1e-5);
#endif
}

// Exactly parallel edges, overlapping and not: an endpoint case is chosen and its derivatives
// are smooth (the line-line formula is never reached).
TEST(ContactEdgeEdge, ExactlyParallelEdges) {
  const Points4 cases[] = {{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
                            Eigen::Vector3d(0.5, 0, 0.1), Eigen::Vector3d(1.5, 0, 0.1)},
                           {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
                            Eigen::Vector3d(0.9, 0.3, 0), Eigen::Vector3d(-0.4, 0.3, 0)},
                           {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
                            Eigen::Vector3d(2, 0, 0.1), Eigen::Vector3d(3, 0, 0.1)}};
  const double expected[] = {0.01, 0.09, 1.01};
  for (int i = 0; i < 3; ++i) {
    const Points4& x = cases[i];
    const T type = edge_edge_distance_type(x[0], x[1], x[2], x[3]);
    EXPECT_NE(type, T::EA_EB);
    EXPECT_NEAR(edge_edge_distance(x[0], x[1], x[2], x[3]), expected[i], 1e-15);
    EXPECT_LT(check_edges(x, type, 1e-6).max(), 1e-7) << i << " " << to_string(type);
  }
}

// Edges within 1e-3 .. 1e-9 of each other at a random pair of points, of the interiors, an
// interior and an endpoint, or two endpoints, each type checked with its own formula, with the
// step cbrt(eps d) and the conditioning allowance of point-triangle's DerivativesNearTheTriangle
// (the distance is a sum of terms of size |r| cancelling to d).
TEST(ContactEdgeEdge, DerivativesAtSmallDistances) {
  std::mt19937 rng(27);
  std::uniform_real_distribution<double> u(0, 1);
  double worst = 0;
  for (double d : {1e-3, 1e-6, 1e-9}) {
    for (int i = 0; i < 300; ++i) {
      Points4 x = random_edges(rng);
      const double s = i % 3 == 2 ? 0.0 : u(rng), t = i % 3 == 0 ? u(rng) : 1.0;
      const Eigen::Vector3d offset = x[0] + s * (x[1] - x[0]) - x[2] - t * (x[3] - x[2]) +
                                     d * test::random_point(rng).normalized();
      x[2] += offset;
      x[3] += offset;
      const T type = edge_edge_distance_type(x[0], x[1], x[2], x[3]);
      const double dist = std::sqrt(edge_edge_distance(x[0], x[1], x[2], x[3]));
      ASSERT_LE(dist, d * (1 + 1e-6));
      const auto e = check_edges(x, type, std::cbrt(1e-16 * dist));
      double r = 0;
      for (int k = 0; k < 4; ++k) r = std::max(r, (x[k] - x[(k + 2) % 4]).norm());
      const double conditioning = 10 * std::numeric_limits<double>::epsilon() * r / dist;
      EXPECT_LT(e.max(), 1e-6 + conditioning) << d << " " << to_string(type) << " " << dist;
      EXPECT_LT(std::max(e.hessian, e.hessian_along), 1e-6) << d << " " << to_string(type);
      worst = std::max(worst, e.max() / (1e-6 + conditioning));
    }
  }
  std::printf("edge-edge at small distances: worst FD error %.2f of (1e-6 + 10 eps |r| / d)\n",
              worst);
}

TEST(ContactEdgeEdge, MatchesSampling) {
  std::mt19937 rng(24);
  const int n = 400;
  for (int i = 0; i < 100; ++i) {
    const Points4 x = test::random_points(rng);
    double best = std::numeric_limits<double>::infinity();
    for (int a = 0; a <= n; ++a)
      for (int b = 0; b <= n; ++b) {
        const double s = double(a) / n, t = double(b) / n;
        best = std::min(best, (x[0] + s * (x[1] - x[0]) - x[2] - t * (x[3] - x[2])).squaredNorm());
      }
    const double d = edge_edge_distance(x[0], x[1], x[2], x[3]);
    EXPECT_LE(d, best + 1e-14);
    const double cell = ((x[1] - x[0]).norm() + (x[3] - x[2]).norm()) / (2.0 * n);
    EXPECT_LE(std::sqrt(best) - std::sqrt(d), cell + 1e-12);
  }
}

// An independent reference for the squared segment distance: g(s) = min over t of
// |ea(s) - eb(t)|^2 is convex in s (the squared distance to a convex set, composed with an affine
// map), so a ternary search over s with the exact inner minimum converges to the true minimum.
double segment_distance_reference(const Points4& x) {
  const Eigen::Vector3d b = x[3] - x[2];
  const auto g = [&](double s) {
    const Eigen::Vector3d p = x[0] + s * (x[1] - x[0]);
    const double t = std::clamp((p - x[2]).dot(b) / b.squaredNorm(), 0.0, 1.0);
    return (p - x[2] - t * b).squaredNorm();
  };
  double lo = 0, hi = 1;
  for (int k = 0; k < 200; ++k) {
    const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
    (g(m1) < g(m2) ? hi : lo) = g(m1) < g(m2) ? m2 : m1;
  }
  return std::min({g(0.0), g(1.0), g((lo + hi) / 2)});
}

// Nearly parallel edges (1e-9 .. 1e-3 rad), where the type comes from line parameters divided by
// |a x b|^2 and the line-line formula loses digits: the distance must still be the segments'
// distance, within the formula's rounding: n = a x b has a relative error ~eps / theta, and so has
// the line-line distance (2e-7 at 1e-9 rad); endpoint cases are exact to ~eps.
TEST(ContactEdgeEdge, NearlyParallelMatchesReference) {
  std::mt19937 rng(26);
  double worst = 0;
  for (int i = 0; i < 700; ++i) {
    const double angle = std::pow(10.0, -9 + 6 * (i % 7) / 6.0);
    const Eigen::Vector3d dir = test::random_point(rng).normalized();
    const Eigen::Vector3d side = dir.cross(test::random_point(rng)).normalized();
    const Eigen::Vector3d ea0 = test::random_point(rng), eb0 = ea0 + test::random_point(rng, 0.5);
    const Points4 x = {ea0, ea0 + dir, eb0,
                       eb0 + 0.8 * (std::cos(angle) * dir + std::sin(angle) * side)};
    const double d = edge_edge_distance(x[0], x[1], x[2], x[3]);
    const double ref = segment_distance_reference(x);
    const double err = std::abs(d - ref) / ref;
    EXPECT_LT(err, 1e-15 + 10 * std::numeric_limits<double>::epsilon() / angle)
        << angle << " " << to_string(edge_edge_distance_type(x[0], x[1], x[2], x[3]));
    worst = std::max(worst, err * angle);
  }
  std::printf("nearly parallel edges: |d - reference| / d <= %.2f eps / angle\n",
              worst / std::numeric_limits<double>::epsilon());
}

TEST(ContactEdgeEdge, Symmetries) {
  std::mt19937 rng(25);
  for (int i = 0; i < 300; ++i) {
    const Points4 x = test::random_points(rng);
    const double d = edge_edge_distance(x[0], x[1], x[2], x[3]);
    EXPECT_NEAR(edge_edge_distance(x[2], x[3], x[0], x[1]), d, 1e-14);  // swap edges
    EXPECT_NEAR(edge_edge_distance(x[1], x[0], x[2], x[3]), d, 1e-14);  // reverse ea
    EXPECT_NEAR(edge_edge_distance(x[0], x[1], x[3], x[2]), d, 1e-14);  // reverse eb
    const Vector12d g = edge_edge_distance_gradient(x[0], x[1], x[2], x[3]);
    const Vector12d g_swapped = edge_edge_distance_gradient(x[2], x[3], x[0], x[1]);
    EXPECT_LT((g.head<6>() - g_swapped.tail<6>()).norm(), 1e-12 * (1 + g.norm()));
    EXPECT_LT((g.tail<6>() - g_swapped.head<6>()).norm(), 1e-12 * (1 + g.norm()));
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(0.3 * i, test::random_point(rng).normalized()).toRotationMatrix();
    const Eigen::Vector3d s = test::random_point(rng, 3);
    EXPECT_NEAR(edge_edge_distance(R * x[0] + s, R * x[1] + s, R * x[2] + s, R * x[3] + s), d,
                1e-13);
  }
}

}  // namespace
}  // namespace rbaa::contact
