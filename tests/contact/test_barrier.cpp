// The IPC log barrier b(d): C2 at d_hat, derivatives against finite differences, and the
// cancellation-free difference b(d0 + delta) - b(d0).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "rbaa/contact/barrier.hpp"

namespace rbaa::contact {
namespace {

// C2 at d_hat: with delta = d_hat - d, b ~ delta^3 / d_hat, b' ~ -3 delta^2 / d_hat and
// b'' ~ 6 delta / d_hat all vanish as d -> d_hat from below (so a pair entering the active set
// adds no jump to the energy, the forces or the Hessian), and all three are 0 at and beyond d_hat.
TEST(Barrier, TwiceContinuousAtDHat) {
  const double d_hat = 1e-3;
  const Barrier b(d_hat);
  for (double rel : {1e-2, 1e-3, 1e-4}) {
    const double delta = rel * d_hat, d = d_hat - delta;
    EXPECT_NEAR(b.value(d) / (std::pow(delta, 3) / d_hat), 1.0, 2 * rel) << rel;
    EXPECT_NEAR(b.first_derivative(d) / (-3 * delta * delta / d_hat), 1.0, 2 * rel) << rel;
    EXPECT_NEAR(b.second_derivative(d) / (6 * delta / d_hat), 1.0, 2 * rel) << rel;
  }
  for (double d : {d_hat, 1.5 * d_hat, 10 * d_hat}) {
    EXPECT_EQ(b.value(d), 0.0) << d;
    EXPECT_EQ(b.first_derivative(d), 0.0) << d;
    EXPECT_EQ(b.second_derivative(d), 0.0) << d;
  }
}

TEST(Barrier, DerivativesMatchFiniteDifferences) {
  const Barrier b(1e-3);
  for (double d : {1e-7, 1e-6, 1e-5, 1e-4, 5e-4, 9.9e-4}) {
    const double eps = 1e-4 * std::min(d, 1e-3 - d);
    const double fd1 = (b.value(d + eps) - b.value(d - eps)) / (2 * eps);
    const double fd2 = (b.first_derivative(d + eps) - b.first_derivative(d - eps)) / (2 * eps);
    EXPECT_NEAR(b.first_derivative(d), fd1, 1e-6 * std::abs(fd1)) << d;
    EXPECT_NEAR(b.second_derivative(d), fd2, 1e-6 * std::abs(fd2)) << d;
    EXPECT_GT(b.second_derivative(d), 0);
  }
  // The difference keeps its digits where subtracting values would not.
  for (double d : {1e-6, 4.6e-4, 9e-4}) {
    for (double delta : {1e-5 * d, -1e-5 * d}) {
      EXPECT_NEAR(b.difference(d, delta), b.value(d + delta) - b.value(d), 1e-9 * std::abs(b.value(d + delta) - b.value(d)));
    }
    const double tiny = 1e-9 * d;  // first order: b'(d) delta, second order 1e-18 relative
    EXPECT_NEAR(b.difference(d, tiny), b.first_derivative(d) * tiny, 1e-8 * std::abs(b.first_derivative(d) * tiny));
  }
  // C2 at d_hat, infinite at contact.
  EXPECT_EQ(b.value(1e-3), 0.0);
  EXPECT_NEAR(b.first_derivative(1e-3 * (1 - 1e-9)), 0.0, 1e-15);
  EXPECT_TRUE(std::isinf(b.value(0.0)));
}

}  // namespace
}  // namespace rbaa::contact
