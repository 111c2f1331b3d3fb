// The backward pass's CHOLMOD factors (cholmod_factor.hpp) over changing patterns. Contact changes
// the Hessian's pattern from step to step, so a HessianFactorizer's analysis of a new version and
// a CholmodFactor's fresh copy of a factor of another structure must replace what they held, not
// add to it: over a long attack the leak would be one factor per contact change.

#include <gtest/gtest.h>

#include <Eigen/SparseCore>

#include <cstdio>
#include <memory>
#include <vector>

#include "rbaa/diff/cholmod_factor.hpp"
#include "rbaa/sim/linear_solver.hpp"

namespace rbaa {
namespace {

// The lower triangle of a symmetric positive definite n x n matrix: a tridiagonal (2, -1) plus,
// with `coupled`, a weak coupling of every i with i + n / 2 (another pattern, a larger factor).
Eigen::SparseMatrix<double> spd(int n, bool coupled) {
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 4.0);
    if (i + 1 < n) t.emplace_back(i + 1, i, -1.0);
    if (coupled && i + n / 2 < n) t.emplace_back(i + n / 2, i, -0.5);
  }
  Eigen::SparseMatrix<double> A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

TEST(HessianFactorizer, ANewPatternsAnalysisReplacesTheLastFactor) {
  const int n = 400;
  const Eigen::SparseMatrix<double> banded = spd(n, false), coupled = spd(n, true);
  HessianFactorizer f;
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
  std::vector<std::size_t> bytes;
  std::uint64_t version = 0;
  for (int round = 0; round < 3; ++round) {
    for (const Eigen::SparseMatrix<double>* A : {&banded, &coupled}) {
      f.factorize(*A, ++version);
      const Eigen::MatrixXd dense = Eigen::MatrixXd(*A).selfadjointView<Eigen::Lower>();
      EXPECT_LT((dense * f.solve(b) - b).norm(), 1e-12 * b.norm());
      bytes.push_back(f.cholmod_bytes_in_use());
    }
  }
  std::printf("CHOLMOD bytes in use after each factorisation:");
  for (std::size_t b : bytes) std::printf(" %zu", b);
  std::printf("\n");
  EXPECT_GT(bytes[1], bytes[0]);  // the coupled pattern's factor is larger
  // Once the workspace has grown to both patterns' needs, each pattern holds the same again.
  EXPECT_EQ(bytes[3], bytes[1]);
  EXPECT_EQ(bytes[4], bytes[2]);
  EXPECT_EQ(bytes[5], bytes[3]);
  // The same pattern again (same version) is refactorised in place.
  f.factorize(coupled, version);
  EXPECT_EQ(f.cholmod_bytes_in_use(), bytes[5]);
  EXPECT_EQ(f.num_factorizations(), 7);
}

// A stored step's factor (the forward pass keeps one per step and refills it with assign): a
// factor of another structure is copied afresh, and the old copy goes.
TEST(CholmodFactor, AssigningAnotherStructureReplacesTheCopy) {
  const int n = 400;
  LinearSolver banded, coupled;
  ASSERT_TRUE(banded.factorize(spd(n, false), 1));
  ASSERT_TRUE(coupled.factorize(spd(n, true), 1));
  ASSERT_FALSE(same_cholmod_structure(banded.cholmod_factor(), coupled.cholmod_factor()));
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
  std::unique_ptr<CholmodFactor> f = CholmodFactor::copy_of(banded.cholmod_factor());
  std::vector<std::size_t> bytes = {f->cholmod_bytes_in_use()};
  for (int round = 0; round < 2; ++round) {
    for (const LinearSolver* s : {&coupled, &banded}) {
      f->assign(s->cholmod_factor());
      EXPECT_LT((f->solve(b) - s->solve(b)).norm(), 1e-14 * s->solve(b).norm());
      bytes.push_back(f->cholmod_bytes_in_use());
    }
  }
  std::printf("CHOLMOD bytes in use after each copy:");
  for (std::size_t k : bytes) std::printf(" %zu", k);
  std::printf("\n");
  EXPECT_GT(bytes[1], bytes[0]);
  EXPECT_EQ(bytes[2], bytes[0]);
  EXPECT_EQ(bytes[3], bytes[1]);
  EXPECT_EQ(bytes[4], bytes[0]);
}

}  // namespace
}  // namespace rbaa
