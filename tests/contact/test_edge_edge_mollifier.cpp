// The edge-edge mollifier: |a x b|^2 and the mollifier against finite differences (value,
// gradient and Hessian, in every coordinate and along the gradient), from exactly parallel edges
// up to and across the threshold eps_x, its derivative with respect to the rest positions, and the
// mollified distance m d that the edge-edge barrier will use.

#include <gtest/gtest.h>

#include <cstdio>

#include "contact_checks.hpp"
#include "rbaa/contact/edge_edge.hpp"
#include "rbaa/contact/edge_edge_mollifier.hpp"

namespace rbaa::contact {
namespace {

using test::Points4;
using test::stack;
using test::unstack;

double cross2(const Vector12d& v) {
  const Points4 x = unstack(v);
  return edge_edge_cross_squarednorm(x[0], x[1], x[2], x[3]);
}
Vector12d cross2_grad(const Vector12d& v) {
  const Points4 x = unstack(v);
  return edge_edge_cross_squarednorm_gradient(x[0], x[1], x[2], x[3]);
}
Matrix12d cross2_hess(const Vector12d& v) {
  const Points4 x = unstack(v);
  return edge_edge_cross_squarednorm_hessian(x[0], x[1], x[2], x[3]);
}

// Edge b turned out of parallel with edge a by an angle whose sin^2 is ratio * 1e-3, so that
// c = ratio * eps_x when the rest shape is this shape with b exactly parallel (same lengths).
Points4 edges_at_ratio(std::mt19937& rng, double ratio) {
  const Eigen::Vector3d ea0 = test::random_point(rng), dir = test::random_point(rng).normalized();
  const Eigen::Vector3d side = dir.cross(test::random_point(rng)).normalized();
  const double la = 0.5 + 0.5 * std::abs(test::random_point(rng).x());
  const double lb = 0.5 + 0.5 * std::abs(test::random_point(rng).x());
  const double s = std::sqrt(ratio * 1e-3);
  const Eigen::Vector3d eb0 = ea0 + 0.3 * dir + 0.2 * side + 0.1 * dir.cross(side);
  return {ea0, ea0 + la * dir, eb0, eb0 + lb * (std::sqrt(1 - s * s) * dir + s * side)};
}

double rest_threshold(const Points4& x) {
  // The rest shape has the same edge lengths: eps_x = 1e-3 |a|^2 |b|^2.
  return 1e-3 * (x[1] - x[0]).squaredNorm() * (x[3] - x[2]).squaredNorm();
}

TEST(ContactEdgeEdgeMollifier, CrossSquaredNormDerivatives) {
  std::mt19937 rng(31);
  double worst = 0;
  for (int i = 0; i < 300; ++i) {
    const Vector12d x = stack(test::random_points(rng));
    worst =
        std::max(worst, test::check_derivatives(cross2, cross2_grad, cross2_hess, x, 1e-6).max());
  }
  for (double ratio : {0.0, 1e-6, 0.5}) {  // parallel and nearly so
    const Vector12d x = stack(edges_at_ratio(rng, ratio));
    const auto e = test::check_derivatives(cross2, cross2_grad, cross2_hess, x, 1e-6);
    // At exactly parallel edges c and its gradient vanish: only the Hessian is checked.
    worst = std::max({worst, e.hessian, ratio > 0 ? e.gradient : 0.0});
  }
  std::printf("|a x b|^2: worst relative FD error %.2e\n", worst);
  // A quartic polynomial: truncation ~h^2 (1e-12), rounding ~eps / h (1e-10).
  EXPECT_LT(worst, 1e-8);
}

TEST(ContactEdgeEdgeMollifier, ScalarMollifier) {
  const double eps_x = 2e-4;
  for (double x : {0.0, 0.1, 0.5, 0.9, 0.999}) {
    const double c = x * eps_x, h = 1e-6 * eps_x;
    EXPECT_NEAR(mollifier(c, eps_x), (2 - x) * x, 1e-15);
    EXPECT_NEAR(mollifier_derivative(c, eps_x),
                (mollifier(c + h, eps_x) - mollifier(c - h, eps_x)) / (2 * h), 1e-6 / eps_x);
    EXPECT_NEAR(mollifier_second_derivative(c, eps_x),
                (mollifier_derivative(c + h, eps_x) - mollifier_derivative(c - h, eps_x)) / (2 * h),
                1e-6 / (eps_x * eps_x));
    const double he = 1e-6 * eps_x;
    EXPECT_NEAR(mollifier_derivative_wrt_eps_x(c, eps_x),
                (mollifier(c, eps_x + he) - mollifier(c, eps_x - he)) / (2 * he), 1e-6 / eps_x);
  }
  // C1 at eps_x: value 1 and slope 0 from both sides; the curvature jumps from -2 / eps_x^2 to 0.
  for (double rel : {1e-3, 1e-6, 1e-9}) {
    const double below = (1 - rel) * eps_x, above = (1 + rel) * eps_x;
    EXPECT_NEAR(mollifier(below, eps_x), 1.0, 2 * rel * rel);
    EXPECT_NEAR(mollifier_derivative(below, eps_x) * eps_x, 0.0, 2 * rel * (1 + 1e-9));
    EXPECT_EQ(mollifier(above, eps_x), 1.0);
    EXPECT_EQ(mollifier_derivative(above, eps_x), 0.0);
    EXPECT_DOUBLE_EQ(mollifier_second_derivative(below, eps_x), -2 / (eps_x * eps_x));
    EXPECT_EQ(mollifier_second_derivative(above, eps_x), 0.0);
    EXPECT_EQ(mollifier_derivative_wrt_eps_x(above, eps_x), 0.0);
    EXPECT_NEAR(mollifier_derivative_wrt_eps_x(below, eps_x) * eps_x, 0.0, 2 * rel * (1 + 1e-9));
  }
}

// The mollifier of the positions from exactly parallel edges up to the threshold. The step keeps
// the FD inside the mollified zone: the Hessian jumps at c = eps_x, so 2h |grad c| must stay below
// eps_x - c (at ratio 0.999: 1e-3 eps_x ~ 1e-7 over |grad c| ~ 2 |n| |b| ~ 0.06, > 1e-6 >> h).
// With h = 1e-8, truncation is negligible (m is a polynomial in x varying on the angle scale
// sqrt(1e-3) ~ 0.03: (h / 0.03)^2 ~ 1e-13); rounding of m ~ 1 gives eps / h = 1e-8 absolute in the
// gradient, which is smallest just below the threshold (|grad m| = 2 (1 - c / eps_x) |grad c| /
// eps_x ~ 0.1 at c = 0.999 eps_x): ~1e-7 relative there, ~1e-9 elsewhere.
TEST(ContactEdgeEdgeMollifier, DerivativesInsideTheMollifiedZone) {
  std::mt19937 rng(32);
  double worst = 0;
  for (double ratio : {0.0, 1e-6, 1e-2, 0.3, 0.9, 0.999}) {
    for (int i = 0; i < 40; ++i) {
      const Points4 x = edges_at_ratio(rng, ratio);
      const double eps_x = rest_threshold(x);
      const double c = edge_edge_cross_squarednorm(x[0], x[1], x[2], x[3]);
      ASSERT_NEAR(c / eps_x, ratio, 1e-9 + 1e-6 * ratio);
      const auto e = test::check_derivatives(
          [&](const Vector12d& v) {
            const Points4 y = unstack(v);
            return edge_edge_mollifier(y[0], y[1], y[2], y[3], eps_x);
          },
          [&](const Vector12d& v) {
            const Points4 y = unstack(v);
            return edge_edge_mollifier_gradient(y[0], y[1], y[2], y[3], eps_x);
          },
          [&](const Vector12d& v) {
            const Points4 y = unstack(v);
            return edge_edge_mollifier_hessian(y[0], y[1], y[2], y[3], eps_x);
          },
          stack(x), 1e-8);
      // Exactly parallel: m = 0 is a minimum, the gradient vanishes; check the Hessian only.
      const double err = ratio > 0 ? e.max() : e.hessian;
      EXPECT_LT(err, 1e-6) << "c / eps_x = " << ratio;
      worst = std::max(worst, err);
    }
  }
  std::printf("mollifier: worst relative FD error %.2e\n", worst);
}

// Across the threshold the mollifier is C1: finite differences of the value that straddle
// c = eps_x still match the gradient to first order in h, and beyond it everything is exactly 1 /
// 0.
TEST(ContactEdgeEdgeMollifier, AcrossTheThreshold) {
  std::mt19937 rng(33);
  for (double ratio : {1 - 1e-9, 1.0, 1 + 1e-9, 1.5, 1e3}) {
    const Points4 x = edges_at_ratio(rng, std::min(ratio, 999.0));
    const double eps_x = rest_threshold(x);
    const double m = edge_edge_mollifier(x[0], x[1], x[2], x[3], eps_x);
    EXPECT_NEAR(m, 1.0, 1e-12) << ratio;
    const Vector12d g = edge_edge_mollifier_gradient(x[0], x[1], x[2], x[3], eps_x);
    const Vector12d g_fd = test::fd_gradient12(
        [&](const Vector12d& v) {
          const Points4 y = unstack(v);
          return edge_edge_mollifier(y[0], y[1], y[2], y[3], eps_x);
        },
        stack(x), 1e-7);
    // |grad m| <= 2 |1 - c / eps_x| |grad c| / eps_x ~ 0 here; a wrong slope at the threshold
    // would show as O(|grad c| / eps_x) ~ 1e3.
    EXPECT_LT((g - g_fd).norm(), 1e-3) << ratio;
    EXPECT_LT(g.norm(), 1e-3) << ratio;
    if (ratio > 1) {
      EXPECT_EQ(m, 1.0);
      EXPECT_EQ(g.norm(), 0.0);
      EXPECT_EQ(edge_edge_mollifier_hessian(x[0], x[1], x[2], x[3], eps_x).norm(), 0.0);
    }
  }
}

// The derivative with respect to the rest positions (through eps_x): against finite differences
// of m in the rest positions, and demonstrably not the position gradient that a well-known
// library once used in its place.
TEST(ContactEdgeEdgeMollifier, GradientWithRespectToRestPositions) {
  std::mt19937 rng(34);
  for (double ratio : {1e-3, 0.2, 0.7, 0.99}) {
    const Points4 x = edges_at_ratio(rng, ratio);
    // A rest shape near the current one (a little longer), so that c / eps_x stays ~ratio.
    Points4 rest = x;
    for (auto& p : rest) p = 1.05 * p + test::random_point(rng, 0.01);
    const auto m_of_rest = [&](const Vector12d& v) {
      const Points4 r = unstack(v);
      return edge_edge_mollifier(x[0], x[1], x[2], x[3],
                                 edge_edge_mollifier_threshold(r[0], r[1], r[2], r[3]));
    };
    const Vector12d g = edge_edge_mollifier_gradient_wrt_rest(x[0], x[1], x[2], x[3], rest[0],
                                                              rest[1], rest[2], rest[3]);
    const Vector12d g_fd = test::fd_gradient12(m_of_rest, stack(rest), 1e-7);
    ASSERT_GT(g.norm(), 0) << ratio;
    EXPECT_LT(test::rel_err(g, g_fd), 1e-6) << ratio;
    const Vector12d eps_grad_fd = test::fd_gradient12(
        [](const Vector12d& v) {
          const Points4 r = unstack(v);
          return edge_edge_mollifier_threshold(r[0], r[1], r[2], r[3]);
        },
        stack(rest), 1e-7);
    EXPECT_LT(
        test::rel_err(edge_edge_mollifier_threshold_gradient(rest[0], rest[1], rest[2], rest[3]),
                      eps_grad_fd),
        1e-8);
    // The bug: dm/d eps_x times the position gradient of m.
    const double eps_x = edge_edge_mollifier_threshold(rest[0], rest[1], rest[2], rest[3]);
    const double c = edge_edge_cross_squarednorm(x[0], x[1], x[2], x[3]);
    const Vector12d wrong = mollifier_derivative_wrt_eps_x(c, eps_x) *
                            edge_edge_mollifier_gradient(x[0], x[1], x[2], x[3], eps_x);
    EXPECT_GT(test::rel_err(wrong, g_fd), 0.5) << ratio;
  }
}

// The product the edge-edge barrier builds on, m(x) d(x) with d the squared segment distance:
// its gradient m grad d + d grad m and Hessian m H_d + grad m grad d^T + grad d grad m^T + d H_m
// against finite differences, for nearly parallel edges in contact range, in every feature case
// the near-parallel geometry produces.
TEST(ContactEdgeEdgeMollifier, MollifiedDistance) {
  std::mt19937 rng(35);
  double worst = 0;
  for (double ratio : {1e-4, 0.1, 0.5, 0.95}) {
    for (int i = 0; i < 30; ++i) {
      const Points4 x = edges_at_ratio(rng, ratio);
      const double eps_x = rest_threshold(x);
      const EdgeEdgeDistanceType type = edge_edge_distance_type(x[0], x[1], x[2], x[3]);
      const auto f = [&](const Vector12d& v) {
        const Points4 y = unstack(v);
        return edge_edge_mollifier(y[0], y[1], y[2], y[3], eps_x) *
               edge_edge_distance(y[0], y[1], y[2], y[3], type);
      };
      const auto g = [&](const Vector12d& v) -> Vector12d {
        const Points4 y = unstack(v);
        return edge_edge_mollifier(y[0], y[1], y[2], y[3], eps_x) *
                   edge_edge_distance_gradient(y[0], y[1], y[2], y[3], type) +
               edge_edge_distance(y[0], y[1], y[2], y[3], type) *
                   edge_edge_mollifier_gradient(y[0], y[1], y[2], y[3], eps_x);
      };
      const auto H = [&](const Vector12d& v) -> Matrix12d {
        const Points4 y = unstack(v);
        const Vector12d gm = edge_edge_mollifier_gradient(y[0], y[1], y[2], y[3], eps_x);
        const Vector12d gd = edge_edge_distance_gradient(y[0], y[1], y[2], y[3], type);
        return edge_edge_mollifier(y[0], y[1], y[2], y[3], eps_x) *
                   edge_edge_distance_hessian(y[0], y[1], y[2], y[3], type) +
               gm * gd.transpose() + gd * gm.transpose() +
               edge_edge_distance(y[0], y[1], y[2], y[3], type) *
                   edge_edge_mollifier_hessian(y[0], y[1], y[2], y[3], eps_x);
      };
      const auto e = test::check_derivatives(f, g, H, stack(x), 1e-8);
      worst = std::max(worst, e.max());
      EXPECT_LT(e.max(), 1e-6) << ratio << " " << to_string(type);
    }
  }
  std::printf("mollified distance: worst relative FD error %.2e\n", worst);
}

}  // namespace
}  // namespace rbaa::contact
