// CHOLMOD factors of one pattern share their symbolic structure, which is what lets the adjoint
// refill stored factors by exchanging value arrays; factors of another pattern do not.

#include <gtest/gtest.h>

#include <Eigen/SparseCore>

#include <algorithm>
#include <vector>

#include "rbaa/sim/linear_solver.hpp"

namespace rbaa {
namespace {

// A banded SPD matrix of size n with bandwidth b, its diagonal scaled by `diag`.
Eigen::SparseMatrix<double> banded(int n, int b, double diag) {
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, diag + 2.0 * b);
    for (int j = i + 1; j <= std::min(n - 1, i + b); ++j) t.emplace_back(j, i, -1.0);  // lower
  }
  Eigen::SparseMatrix<double> A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

TEST(LinearSolver, SamePatternSharesTheStructureAndHandsOverValues) {
  LinearSolver a, b, c;
  ASSERT_TRUE(a.factorize(banded(300, 12, 1.0), 1));
  ASSERT_TRUE(b.factorize(banded(300, 12, 5.0), 1));
  ASSERT_TRUE(c.factorize(banded(300, 4, 1.0), 1));
  EXPECT_TRUE(same_cholmod_structure(a.cholmod_factor(), b.cholmod_factor()));
  EXPECT_TRUE(same_cholmod_structure(a.cholmod_factor(), a.cholmod_factor()));
  EXPECT_FALSE(same_cholmod_structure(a.cholmod_factor(), c.cholmod_factor()));
  // Handing a's values to b's factor: b then solves with a's matrix.
  const Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(300, -1.0, 2.0);
  const Eigen::VectorXd x_a = a.solve(rhs);
  ASSERT_TRUE(a.give_factor_values(const_cast<cholmod_factor_struct*>(b.cholmod_factor())));
  EXPECT_LE((b.solve(rhs) - x_a).norm(), 1e-14 * x_a.norm());
}

}  // namespace
}  // namespace rbaa
