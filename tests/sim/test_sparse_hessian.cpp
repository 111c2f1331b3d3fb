// The Hessian's pattern beyond the mesh's tets (sparse_hessian.hpp): blocks between vertices that
// share no tet (contact between bodies) are assembled like the others, and the pattern, with its
// version, changes exactly when the set of such blocks does.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>
#include <utility>
#include <vector>

#include "rbaa/sim/linear_solver.hpp"
#include "rbaa/sim/sparse_hessian.hpp"

namespace rbaa {
namespace {

// Two tets, vertices 0-3 and 4-7: no vertex of one shares a tet with a vertex of the other.
Tets two_tets() {
  Tets T(2, 4);
  T << 0, 1, 2, 3, 4, 5, 6, 7;
  return T;
}

// Fills H's buffers with random element blocks, vertex blocks and the given vertex pair blocks
// (row, column, any order), and adds the same to the dense reference D.
struct Filler {
  std::mt19937 rng{7};
  std::uniform_real_distribution<double> u{-1.0, 1.0};
  Eigen::Matrix3d block() {
    Eigen::Matrix3d B;
    for (int i = 0; i < 9; ++i) B.data()[i] = u(rng);
    return B;
  }
  void fill(SparseHessian& H, const Tets& T, const std::vector<std::pair<int, int>>& pairs,
            Eigen::MatrixXd& D) {
    H.set_zero();
    D = Eigen::MatrixXd::Zero(H.rows(), H.rows());
    for (int e = 0; e < T.rows(); ++e) {
      double* b = H.element_block(e);
      for (int c = 0; c < 12; ++c) {
        for (int r = c; r < 12; ++r) {
          const double x = u(rng);
          b[SparseHessian::packed_index(r, c)] += x;
          const int R = 3 * T(e, r / 3) + r % 3, C = 3 * T(e, c / 3) + c % 3;
          D(R, C) += x;
          if (r != c) D(C, R) += x;
        }
      }
    }
    for (int v = 0; v < H.num_vertices(); v += 3) {
      Eigen::Matrix3d B = block();
      B = (B + B.transpose()).eval();
      H.vertex_block(v) += B;
      D.block<3, 3>(3 * v, 3 * v) += B;
    }
    for (const auto& [a, b] : pairs) {
      const Eigen::Matrix3d B = block();
      H.add_vertex_pair_block(a, b, B);
      D.block<3, 3>(3 * a, 3 * b) += B;
      D.block<3, 3>(3 * b, 3 * a) += B.transpose();
    }
  }
};

Eigen::MatrixXd dense(const Eigen::SparseMatrix<double>& L) {
  return Eigen::MatrixXd(Eigen::SparseMatrix<double>(L.selfadjointView<Eigen::Lower>()));
}

TEST(SparseHessian, ExtraBlocksAssembleLikeADenseMatrixAndVersionTheirSet) {
  const Tets T = two_tets();
  SparseHessian H(T, 8);
  Filler f;
  Eigen::MatrixXd D;
  const std::uint64_t base_version = H.pattern_version();
  const Eigen::Index base_nnz = H.matrix().nonZeros();

  // Within the tets only: the base pattern, its version.
  f.fill(H, T, {{0, 3}, {2, 1}}, D);
  EXPECT_LE((dense(H.assemble()) - D).norm(), 1e-15 * D.norm());
  EXPECT_EQ(H.pattern_version(), base_version);
  EXPECT_EQ(H.matrix().nonZeros(), base_nnz);

  // Across the tets (both orders, one pair twice): 9 more entries per distinct pair.
  f.fill(H, T, {{1, 5}, {6, 2}, {5, 1}, {0, 3}}, D);
  EXPECT_LE((dense(H.assemble()) - D).norm(), 1e-15 * D.norm());
  const std::uint64_t v1 = H.pattern_version();
  EXPECT_NE(v1, base_version);
  EXPECT_EQ(H.matrix().nonZeros(), base_nnz + 18);
  EXPECT_EQ(H.extra_pairs(), (std::vector<std::pair<int, int>>{{5, 1}, {6, 2}}));

  // The same set with other values: values only, same version.
  f.fill(H, T, {{2, 6}, {1, 5}}, D);
  EXPECT_LE((dense(H.assemble()) - D).norm(), 1e-15 * D.norm());
  EXPECT_EQ(H.pattern_version(), v1);

  // add_matrix of an assembled matrix with extra blocks, and of a base-pattern one.
  const Eigen::SparseMatrix<double> A = H.matrix();
  const Eigen::MatrixXd DA = D;
  f.fill(H, T, {}, D);
  H.add_matrix(2.0, A);
  EXPECT_LE((dense(H.assemble()) - (D + 2.0 * DA)).norm(), 1e-15 * (D + 2.0 * DA).norm());
  EXPECT_EQ(H.pattern_version(), v1);  // A's extra pairs are the same set

  // Another set: a new version; and shrinking back to none.
  f.fill(H, T, {{7, 0}}, D);
  EXPECT_LE((dense(H.assemble()) - D).norm(), 1e-15 * D.norm());
  const std::uint64_t v2 = H.pattern_version();
  EXPECT_NE(v2, v1);
  EXPECT_NE(v2, base_version);
  const Eigen::SparseMatrix<double> B = H.matrix();
  f.fill(H, T, {}, D);
  EXPECT_LE((dense(H.assemble()) - D).norm(), 1e-15 * D.norm());
  EXPECT_NE(H.pattern_version(), v2);
  EXPECT_EQ(H.matrix().nonZeros(), base_nnz);
  EXPECT_TRUE(H.extra_pairs().empty());
  H.set_zero();
  H.add_matrix(1.0, B);  // entries outside the base pattern come back as an extra block
  EXPECT_LE((dense(H.assemble()) - dense(B)).norm(), 1e-15 * dense(B).norm());
  EXPECT_EQ(H.matrix().nonZeros(), base_nnz + 9);
}

// A solver keyed on pattern_version redoes its analysis when the extra set changes, and its
// factor solves the matrix with the extra blocks.
TEST(SparseHessian, LinearSolverFollowsTheGrowingPattern) {
  const Tets T = two_tets();
  SparseHessian H(T, 8);
  LinearSolver solver;
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(24, -1.0, 2.0);
  std::uint64_t last = 0;  // the version the solver last analysed
  for (const std::vector<std::pair<int, int>>& pairs :
       std::vector<std::vector<std::pair<int, int>>>{
           {}, {{1, 5}}, {{1, 5}}, {{1, 5}, {3, 4}}, {}}) {
    H.set_zero();
    for (int v = 0; v < 8; ++v) H.vertex_block(v) += 10.0 * Eigen::Matrix3d::Identity();
    for (const auto& [a, c] : pairs) H.add_vertex_pair_block(a, c, Eigen::Matrix3d::Constant(1.0));
    const int analyses = solver.num_analyses();
    const Eigen::SparseMatrix<double>& A = H.assemble();
    ASSERT_TRUE(solver.factorize(A, H.pattern_version()));
    EXPECT_EQ(solver.num_analyses() - analyses, H.pattern_version() != last ? 1 : 0);
    last = H.pattern_version();
    const Eigen::MatrixXd D = dense(H.matrix());
    EXPECT_LE((D * solver.solve(b) - b).norm(), 1e-14 * b.norm());
  }
  EXPECT_EQ(solver.num_analyses(), 4);  // base, +1 pair, +2 pairs, base again
}

}  // namespace
}  // namespace rbaa
