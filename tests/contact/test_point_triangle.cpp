// Point-plane and point-triangle squared distances: gradients and Hessians against finite
// differences in every region of the triangle (random and hand-placed points, points over an edge
// and a corner, small distances), against brute-force sampling of the triangle, and invariance
// under rigid motions and relabelling.

#include <gtest/gtest.h>

#include <cstdio>
#include <limits>

#include "contact_checks.hpp"
#include "rbaa/contact/point_plane.hpp"
#include "rbaa/contact/point_triangle.hpp"

namespace rbaa::contact {
namespace {

using test::Points4;
using test::stack;
using test::unstack;
using T = PointTriangleDistanceType;

test::DerivativeErrors check_plane(const Points4& x, double h) {
  return test::check_derivatives(
      [](const Vector12d& v) {
        const Points4 y = unstack(v);
        return point_plane_distance(y[0], y[1], y[2], y[3]);
      },
      [](const Vector12d& v) {
        const Points4 y = unstack(v);
        return point_plane_distance_gradient(y[0], y[1], y[2], y[3]);
      },
      [](const Vector12d& v) {
        const Points4 y = unstack(v);
        return point_plane_distance_hessian(y[0], y[1], y[2], y[3]);
      },
      stack(x), h);
}

test::DerivativeErrors check_triangle(const Points4& x, T type, double h) {
  return test::check_derivatives(
      [=](const Vector12d& v) {
        const Points4 y = unstack(v);
        return point_triangle_distance(y[0], y[1], y[2], y[3], type);
      },
      [=](const Vector12d& v) {
        const Points4 y = unstack(v);
        return point_triangle_distance_gradient(y[0], y[1], y[2], y[3], type);
      },
      [=](const Vector12d& v) {
        const Points4 y = unstack(v);
        return point_triangle_distance_hessian(y[0], y[1], y[2], y[3], type);
      },
      stack(x), h);
}

test::DerivativeErrors check_triangle_auto(const Points4& x, double h) {
  return test::check_derivatives(
      [](const Vector12d& v) {
        const Points4 y = unstack(v);
        return point_triangle_distance(y[0], y[1], y[2], y[3]);
      },
      [](const Vector12d& v) {
        const Points4 y = unstack(v);
        return point_triangle_distance_gradient(y[0], y[1], y[2], y[3]);
      },
      [](const Vector12d& v) {
        const Points4 y = unstack(v);
        return point_triangle_distance_hessian(y[0], y[1], y[2], y[3]);
      },
      stack(x), h);
}

// A random point and a random triangle whose heights are all >= 0.2 (the scale of the
// derivatives' third order): truncation ~(1e-6 / 0.2)^2, rounding ~1e-16 / 1e-6.
Points4 random_point_and_triangle(std::mt19937& rng) {
  for (;;) {
    const Points4 x = test::random_points(rng);
    if (test::min_height(x[1], x[2], x[3]) >= 0.2) return x;
  }
}

TEST(ContactPointTriangle, PointPlaneDerivatives) {
  std::mt19937 rng(11);
  double worst = 0;
  for (int i = 0; i < 300; ++i)
    worst = std::max(worst, check_plane(random_point_and_triangle(rng), 1e-6).max());
  std::printf("point-plane: worst relative FD error %.2e\n", worst);
  EXPECT_LT(worst, 1e-7);
}

TEST(ContactPointTriangle, DerivativesInEveryRegion) {
  std::mt19937 rng(12);
  double worst = 0, worst_auto = 0;
  int per_type[7] = {};
  for (int i = 0; i < 2000; ++i) {
    // Points spread over a box three times the triangle's so that every region is visited.
    Points4 x = random_point_and_triangle(rng);
    x[0] *= 2.5;
    const T type = point_triangle_distance_type(x[0], x[1], x[2], x[3]);
    ++per_type[static_cast<int>(type)];
    worst = std::max(worst, check_triangle(x, type, 1e-6).max());
    const auto a = check_triangle_auto(x, 1e-6);
    worst_auto = std::max({worst_auto, a.gradient, a.along_gradient});
  }
  for (int t = 0; t < 7; ++t) EXPECT_GT(per_type[t], 30) << to_string(static_cast<T>(t));
  std::printf("point-triangle: worst FD error %.2e (fixed type), %.2e (gradient, type per call)\n",
              worst, worst_auto);
  EXPECT_LT(worst, 1e-7);
  EXPECT_LT(worst_auto, 1e-7);
}

// A vertex exactly over an edge and over a corner, at heights 1e-9 .. 1: every type that touches
// the point gives derivatives that match finite differences of its own formula, and their
// gradients agree (so the barrier's force does not depend on which one rounding picks).
TEST(ContactPointTriangle, VertexOverAnEdgeAndACorner) {
  const Eigen::Vector3d t0(0, 0, 0), t1(1, 0, 0), t2(0, 1, 0);
  for (double z : {1.0, 1e-3, 1e-6, 1e-9}) {
    const struct {
      Eigen::Vector3d p;
      std::vector<T> types;
    } cases[] = {{Eigen::Vector3d(0.5, 0, z), {T::P_E0, T::P_T}},
                 {Eigen::Vector3d(0.5, 0.5, z), {T::P_E1, T::P_T}},
                 {Eigen::Vector3d(0, 0, z), {T::P_T0, T::P_E0, T::P_E2, T::P_T}},
                 {Eigen::Vector3d(0, 1, -z), {T::P_T2, T::P_E1, T::P_E2, T::P_T}}};
    for (const auto& c : cases) {
      const Points4 x = {c.p, t0, t1, t2};
      const Vector12d g = point_triangle_distance_gradient(c.p, t0, t1, t2);
      for (T type : c.types) {
        // Step cbrt(eps z): the gradient is ~2z while the third derivatives (through the
        // triangle's corners) are O(1), so truncation is ~h^2 / z and rounding ~eps / h (see
        // PointLineDerivativesAtSmallDistances); both ~2e-8 at z = 1e-9.
        const auto e = check_triangle(x, type, std::cbrt(1e-16 * z));
        EXPECT_LT(e.max(), 1e-6) << z << " " << to_string(type);
        EXPECT_LT((point_triangle_distance_gradient(c.p, t0, t1, t2, type) - g).norm(),
                  1e-15 * g.norm())
            << z << " " << to_string(type);
      }
    }
  }
}

// Random triangles with the point within 1e-3 .. 1e-9 of a random spot of the face, of an edge or
// at a corner (most near a region boundary; an offset nearly in the plane leaves it much closer),
// each type checked with its own formula; the step cbrt(eps d) as above. Here the corners are not
// exact: the signed distance (p - t0).n / |n| sums terms of size |p - t0| that cancel to d, so the
// distance, and with it the analytic gradient 2 d n / |n|, carry a relative error ~eps |r| / d
// (|r| the largest corner distance): the conditioning of the input, 1e-4 at d = 1e-12.
TEST(ContactPointTriangle, DerivativesNearTheTriangle) {
  std::mt19937 rng(15);
  std::uniform_real_distribution<double> u(0, 1);
  double worst = 0;
  for (double d : {1e-3, 1e-6, 1e-9}) {
    for (int i = 0; i < 300; ++i) {
      Points4 x = random_point_and_triangle(rng);
      double a = u(rng), b = u(rng);
      if (a + b > 1) a = 1 - a, b = 1 - b;
      if (i % 3 == 1) b = 0;         // on edge t0t1
      if (i % 3 == 2) a = 0, b = 0;  // at corner t0
      const Eigen::Vector3d on = x[1] + a * (x[2] - x[1]) + b * (x[3] - x[1]);
      x[0] = on + d * test::random_point(rng).normalized();
      const T type = point_triangle_distance_type(x[0], x[1], x[2], x[3]);
      const double dist = std::sqrt(point_triangle_distance(x[0], x[1], x[2], x[3]));
      ASSERT_LE(dist, d * (1 + 1e-6));
      const auto e = check_triangle(x, type, std::cbrt(1e-16 * dist));
      double r = 0;
      for (int k = 1; k < 4; ++k) r = std::max(r, (x[k] - x[0]).norm());
      const double conditioning = 10 * std::numeric_limits<double>::epsilon() * r / dist;
      EXPECT_LT(e.max(), 1e-6 + conditioning) << d << " " << to_string(type) << " " << dist;
      EXPECT_LT(std::max(e.hessian, e.hessian_along), 1e-6) << d << " " << to_string(type);
      worst = std::max(worst, e.max() / (1e-6 + conditioning));
    }
  }
  std::printf("point-triangle near the triangle: worst FD error %.2f of (1e-6 + 10 eps |r| / d)\n",
              worst);
}

TEST(ContactPointTriangle, MatchesSampling) {
  std::mt19937 rng(13);
  const int n = 300;  // samples per side of the barycentric grid
  for (int i = 0; i < 100; ++i) {
    Points4 x = test::random_points(rng);
    x[0] *= 2;
    double best = std::numeric_limits<double>::infinity();
    for (int a = 0; a <= n; ++a)
      for (int b = 0; a + b <= n; ++b) {
        const double u = double(a) / n, v = double(b) / n;
        const Eigen::Vector3d y = x[1] + u * (x[2] - x[1]) + v * (x[3] - x[1]);
        best = std::min(best, (x[0] - y).squaredNorm());
      }
    const double d = point_triangle_distance(x[0], x[1], x[2], x[3]);
    EXPECT_LE(d, best + 1e-14);
    // The grid's cells have diameter <= the longest edge / n.
    const double longest =
        std::max({(x[2] - x[1]).norm(), (x[3] - x[2]).norm(), (x[1] - x[3]).norm()});
    EXPECT_LE(std::sqrt(best) - std::sqrt(d), longest / n + 1e-12);
  }
}

TEST(ContactPointTriangle, InvariantUnderRigidMotionAndRelabelling) {
  std::mt19937 rng(14);
  for (int i = 0; i < 200; ++i) {
    Points4 x = random_point_and_triangle(rng);
    x[0] *= 2;
    const double d = point_triangle_distance(x[0], x[1], x[2], x[3]);
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(i * 0.1, test::random_point(rng).normalized()).toRotationMatrix();
    const Eigen::Vector3d s = test::random_point(rng, 3);
    Points4 y;
    for (int k = 0; k < 4; ++k) y[k] = R * x[k] + s;
    EXPECT_NEAR(point_triangle_distance(y[0], y[1], y[2], y[3]), d, 1e-13);
    EXPECT_NEAR(point_triangle_distance(x[0], x[2], x[3], x[1]), d, 1e-14);
    EXPECT_NEAR(point_triangle_distance(x[0], x[3], x[2], x[1]), d, 1e-14);
    // The gradient turns with the pair, and its entries sum to zero (translation invariance).
    const Vector12d g = point_triangle_distance_gradient(x[0], x[1], x[2], x[3]);
    const Vector12d gy = point_triangle_distance_gradient(y[0], y[1], y[2], y[3]);
    for (int k = 0; k < 4; ++k)
      EXPECT_LT((gy.segment<3>(3 * k) - R * g.segment<3>(3 * k)).norm(), 1e-12);
    EXPECT_LT((g.segment<3>(0) + g.segment<3>(3) + g.segment<3>(6) + g.segment<3>(9)).norm(),
              1e-13);
  }
}

}  // namespace
}  // namespace rbaa::contact
