#pragma once
// The simulator's 3#V x 3#V sparse symmetric matrices (Hessians, the mass matrix), lower triangle
// only (CHOLMOD reads the lower triangle). The base pattern, fixed for a mesh, has a 3x3 block for
// every pair of vertices sharing a tet. Forms write per-element 12x12 blocks and per-vertex 3x3
// blocks into buffers from parallel loops; assemble() then sums every nonzero's contributions in
// a fixed order (by element, then by vertex), so the result does not depend on the thread count
// and no triplet list is sorted per Newton iteration.
//
// Contact between bodies couples vertices that share no tet. Such blocks (add_vertex_pair_block
// or add_matrix outside the base pattern) are kept apart, keyed by vertex pair, and assemble()
// returns the base pattern plus one 3x3 block per such pair. The extra pairs change only when
// the active contact pairs do, so the merged pattern is rebuilt (and pattern_version() changes,
// which makes the linear solvers redo their symbolic analysis) only when the set of extra pairs
// differs from the previous assemble's; otherwise only the values are written.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cstdint>
#include <map>
#include <utility>
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
  /// Identifies the pattern of the last assemble() (unique over all SparseHessians); changes
  /// whenever assemble() changes the set of extra blocks (never without body-body contact).
  std::uint64_t pattern_version() const { return pattern_version_; }

  /// Clears every buffer (element blocks, vertex blocks, direct values, extra blocks). The pattern
  /// of matrix() stays until the next assemble(). Element blocks are cleared lazily, each when it
  /// is first handed out (or by assemble() if none is): an assembly then writes the ~6 MB of
  /// element blocks once instead of zeroing them, reading them back and adding.
  void set_zero();
  /// Element e's packed 12x12 lower block; callers add to it. Safe from parallel loops over
  /// elements (each element by one thread).
  double* element_block(int e) {
    double* block = element_values_.data() + std::size_t(e) * kPacked;
    if (element_generation_[e] != generation_) {
      element_generation_[e] = generation_;
      std::fill(block, block + kPacked, 0.0);
    }
    return block;
  }
  /// Element e's block for a caller that writes all kPacked entries: returns true when nothing
  /// has been added to it since set_zero(), and then the caller must assign (=) every entry
  /// instead of adding (the block holds stale values); false: add to it as to element_block(e).
  /// The sums are the same either way (0 + x = x).
  bool element_block_for_writing(int e, double*& block) {
    block = element_values_.data() + std::size_t(e) * kPacked;
    if (element_generation_[e] == generation_) return false;
    element_generation_[e] = generation_;
    return true;
  }
  /// Vertex v's 3x3 diagonal block (full; its lower triangle is used); callers add to it. Not
  /// thread-safe across calls for different vertices (contact forms touch few vertices).
  Eigen::Matrix3d& vertex_block(int v);
  /// The buffer-free alternative to element_block() for a form that writes every element's block
  /// whole (the elasticity): when begin_elements_in_order() returns true, the caller hands every
  /// element's packed block to add_element_in_order() in ascending element order (0 .. #T - 1),
  /// and each is summed straight into the matrix in the order assemble() sums the buffers (the
  /// direct values, then the elements in order): the same matrix, bit for bit, without writing,
  /// zeroing and gathering the ~6 MB of element buffers on every assembly. The direct values
  /// (add_matrix, add_vertex_pair_block) should all be in before (IncrementalPotential runs
  /// element-block forms last): one added later is summed after the elements instead (the same
  /// matrix up to round-off). Returns false (use element_block) when an element block was
  /// already written in this assembly. Not thread-safe.
  bool begin_elements_in_order();
  void add_element_in_order(int e, const double* packed);
  /// Adds B to the block (row vertex a, column vertex b) and B^T to (b, a) for a != b (an extra
  /// block when a and b share no tet); a == b adds (B + B^T) / 2 to the diagonal block. Not
  /// thread-safe.
  void add_vertex_pair_block(int a, int b, const Eigen::Matrix3d& B);
  /// Adds scale * A, A a 3#V x 3#V lower triangle (e.g. the mass matrix, zero_matrix() or a
  /// previous assemble); its entries outside the base pattern become extra blocks.
  void add_matrix(double scale, const Eigen::SparseMatrix<double>& A);

  /// Forms call this when their PSD projection changed their exact Hessian by more than round-off
  /// (the assembled projected matrix is then not the exact Hessian). Cleared by set_zero().
  void mark_projection_active() { projection_active_ = true; }
  bool projection_active() const { return projection_active_; }

  /// Sums the buffers into the matrix (lower triangle, compressed column: the base pattern plus
  /// the extra blocks added since set_zero()) and returns it.
  const Eigen::SparseMatrix<double>& assemble();
  /// Decouples the dofs flagged in `fixed` (3 #V entries; nonzero: fixed) in the last assembled
  /// matrix: zeroes their rows and columns and puts 1 on their diagonals (Dirichlet elimination,
  /// the pattern kept). A solve with a right-hand side that is zero there gives exact zeros there.
  void eliminate_dofs(const std::vector<char>& fixed);
  /// The last assembled matrix.
  const Eigen::SparseMatrix<double>& matrix() const { return matrix_; }
  /// A matrix with the last assemble's pattern and zero values.
  Eigen::SparseMatrix<double> zero_matrix() const;
  /// Vertex pairs (row > column) of the extra blocks in the last assemble's pattern, ascending.
  const std::vector<std::pair<int, int>>& extra_pairs() const { return extra_pairs_; }

 private:
  // Index of entry (row, col) in the base pattern, or -1.
  int base_entry(int row, int col) const;
  // Rebuilds matrix_'s pattern as the base one plus the blocks of extra_ (a new pattern_version).
  void rebuild_pattern();
  // Zeroes direct_ unless it already holds this assembly's values (set_zero() leaves it stale).
  void use_direct();

  int num_elements_ = 0;
  int num_vertices_ = 0;
  std::uint64_t pattern_version_ = 0;
  std::vector<int> base_outer_, base_inner_;      // the base pattern (compressed column)
  Eigen::SparseMatrix<double> matrix_;            // last assembled pattern + values
  std::vector<int> base_position_;                // base nnz -> nnz of matrix_
  std::vector<std::pair<int, int>> extra_pairs_;  // extra blocks of matrix_'s pattern
  std::vector<int> extra_position_;     // 3 per extra pair: nnz of its block's column j, row 0
  std::vector<int> source_start_;       // base nnz -> range in sources_
  std::vector<int> sources_;            // flat indices into element_values_
  std::vector<int> diagonal_entries_;   // 6 per vertex: base nnz of its diagonal block's lower part
  std::vector<double> element_values_;  // #T * kPacked
  std::vector<int> element_target_;     // #T * kPacked: base nnz of each packed element entry
  Eigen::VectorXd in_order_sum_;        // base nnz: the direct values plus the elements so far
  int in_order_next_ = -1;              // next element in order; -1: no in-order pass yet
  // An element block holds this assembly's values iff its generation is generation_ (set_zero()
  // starts a new one); older blocks read as zero.
  std::uint64_t generation_ = 1;
  std::vector<std::uint64_t> element_generation_;
  std::vector<Eigen::Matrix3d> vertex_values_;
  std::vector<char> vertex_touched_;
  std::vector<int> touched_vertices_;
  Eigen::VectorXd direct_;  // base nnz values added through add_matrix / add_vertex_pair_block
  bool direct_used_ = false;  // direct_ holds this assembly's values (else it is stale)
  // Blocks between vertices sharing no tet, keyed (row vertex, column vertex), row > column.
  std::map<std::pair<int, int>, Eigen::Matrix3d> extra_;
  bool projection_active_ = false;
};

}  // namespace rbaa
