#pragma once
// The simulator's 3#V x 3#V sparse symmetric matrices (Hessians, the mass matrix) in one fixed
// pattern: a 3x3 block for every pair of vertices sharing a tet, lower triangle only (CHOLMOD reads
// the lower triangle). Forms write per-element 12x12 blocks and per-vertex 3x3 blocks into
// buffers from parallel loops; assemble() then sums every nonzero's contributions in a fixed
// order (by element, then by vertex), so the result does not depend on the thread count and no
// triplet list is sorted per Newton iteration.
//
// Contact pairs against analytic planes only touch a vertex's diagonal block, which the pattern
// always holds. Pairs that couple distinct vertices (vertex-triangle and edge-edge between bodies)
// will extend the pattern with extra blocks; pattern_version() then changes and the linear
// solver redoes its symbolic analysis.

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <cstdint>
#include <vector>

#include "rbaa/mesh/tet_mesh.hpp"

namespace rbaa {

class SparseHessian {
 public:
  /// Entries of one element's 12x12 block kept: the lower triangle, packed column by column.
  static constexpr int kPacked = 78;
  /// Index of local entry (r, c), r >= c, in the packed lower triangle (local dof = 3 a + i).
  static constexpr int packed_index(int r, int c) { return c * 12 - c * (c - 1) / 2 + (r - c); }

  SparseHessian(const Tets& tets, int num_vertices);

  int rows() const { return 3 * num_vertices_; }
  int num_elements() const { return num_elements_; }
  int num_vertices() const { return num_vertices_; }
  /// Changes whenever the pattern does (never, for vertex-plane contact).
  std::uint64_t pattern_version() const { return pattern_version_; }

  /// Clears every buffer (element blocks, vertex blocks, direct values).
  void set_zero();
  /// Element e's packed 12x12 lower block; callers add to it.
  double* element_block(int e) { return element_values_.data() + std::size_t(e) * kPacked; }
  /// Vertex v's 3x3 diagonal block (full; its lower triangle is used); callers add to it. Not
  /// thread-safe across calls for different vertices (contact forms touch few vertices).
  Eigen::Matrix3d& vertex_block(int v);
  /// Adds B to the block (row vertex a, column vertex b) and B^T to (b, a), for a != b sharing a
  /// tet (a body's surface edge or triangle always does); a == b adds (B + B^T) / 2 to the
  /// diagonal block. Throws std::logic_error for a pair outside the pattern. Not thread-safe.
  void add_vertex_pair_block(int a, int b, const Eigen::Matrix3d& B);
  /// Adds scale * A, A a matrix in this pattern (e.g. from zero_matrix() or a previous assemble).
  void add_matrix(double scale, const Eigen::SparseMatrix<double>& A);

  /// Forms call this when their PSD projection changed their exact Hessian by more than round-off
  /// (the assembled projected matrix is then not the exact Hessian). Cleared by set_zero().
  void mark_projection_active() { projection_active_ = true; }
  bool projection_active() const { return projection_active_; }

  /// Sums the buffers into the matrix (lower triangle, compressed column) and returns it.
  const Eigen::SparseMatrix<double>& assemble();
  /// The last assembled matrix.
  const Eigen::SparseMatrix<double>& matrix() const { return matrix_; }
  /// A matrix with this pattern and zero values.
  Eigen::SparseMatrix<double> zero_matrix() const;

 private:
  int num_elements_ = 0;
  int num_vertices_ = 0;
  std::uint64_t pattern_version_ = 0;
  Eigen::SparseMatrix<double> matrix_;  // pattern + last assembled values
  std::vector<int> source_start_;       // nnz -> range in sources_
  std::vector<int> sources_;            // flat indices into element_values_
  std::vector<int> diagonal_entries_;   // 6 per vertex: nnz of its diagonal block's lower triangle
  std::vector<double> element_values_;  // #T * kPacked
  std::vector<Eigen::Matrix3d> vertex_values_;
  std::vector<char> vertex_touched_;
  std::vector<int> touched_vertices_;
  Eigen::VectorXd direct_;  // nnz values added through add_matrix
  bool direct_used_ = false;
  bool projection_active_ = false;
};

}  // namespace rbaa
