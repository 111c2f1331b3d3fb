#pragma once
// Cholesky factors of the step Hessians for the backward pass (SPEC section 3), held through
// CHOLMOD's C API because Eigen's CholmodDecomposition cannot be copied:
//
// * CholmodFactor: one numeric factor L (L L^T = A, supernodal) that solves A x = b. Either a deep
//   copy of another factor (cholmod_copy_factor; the forward pass keeps Newton's last factor of
//   every step this way) or the product of a HessianFactorizer.
// * HessianFactorizer: analyses a sparsity pattern once and factorises numerically afterwards
//   (the backward pass's "rebuild" mode), with an LDL^T fallback (Eigen's SimplicialLDLT, no
//   pivoting) when CHOLMOD finds the matrix not positive definite.
//
// Matrices are the simulator's lower triangles (sparse_hessian.hpp).

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <cstddef>
#include <cstdint>
#include <memory>

struct cholmod_factor_struct;

namespace rbaa {

class LinearSolver;

/// A factor of a symmetric matrix A that solves A x = b. Move-only.
class CholmodFactor {
 public:
  /// Deep copy of a CHOLMOD factor (int indices, real double), e.g. the Newton solver's last.
  static std::unique_ptr<CholmodFactor> copy_of(const cholmod_factor_struct* L);

  ~CholmodFactor();
  CholmodFactor(const CholmodFactor&) = delete;
  CholmodFactor& operator=(const CholmodFactor&) = delete;

  /// Makes this a copy of L. When this already holds a factor of the same symbolic structure
  /// (same ordering and supernodes: a factor of the same pattern from the same analysis), only
  /// the numeric values are copied into the existing buffers; otherwise a fresh deep copy is
  /// made. The result is the same either way; reuse saves the allocation and page faults of a
  /// new factor (the forward pass keeps one per step, every evaluation of an attack).
  void assign(const cholmod_factor_struct* L);

  /// Takes the values of `solver`'s last factorisation without copying them
  /// (LinearSolver::give_factor_values: the arrays are exchanged), when this holds a factor of
  /// the same structure; returns false otherwise (nothing changes; use assign).
  bool take_values_from(LinearSolver& solver);

  /// x = A^-1 b.
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;
  /// Bytes held by the numeric factor and its index arrays.
  std::size_t bytes() const;
  /// What a copy of L would hold (0 for null): the memory one stored step costs.
  static std::size_t bytes_of(const cholmod_factor_struct* L);
  /// Bytes CHOLMOD holds for this object now (its common's count): assign's fresh copy replaces
  /// the factor it held.
  std::size_t cholmod_bytes_in_use() const;
  int rows() const;

 private:
  friend class HessianFactorizer;
  CholmodFactor();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Factorises symmetric matrices of one pattern: the symbolic analysis runs once per
/// pattern_version, every call after that pays the numeric factorisation only.
class HessianFactorizer {
 public:
  HessianFactorizer();
  ~HessianFactorizer();
  HessianFactorizer(const HessianFactorizer&) = delete;
  HessianFactorizer& operator=(const HessianFactorizer&) = delete;

  /// Factorises A (lower triangle, compressed). LL^T when A is positive definite; otherwise
  /// LDL^T without pivoting (counted in num_ldlt_fallbacks). Throws rbaa::SolverError when both
  /// fail (a singular matrix).
  void factorize(const Eigen::SparseMatrix<double>& A, std::uint64_t pattern_version);
  /// x = A^-1 b with the last factorisation.
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;

  int num_factorizations() const { return factorizations_; }
  int num_ldlt_fallbacks() const { return fallbacks_; }
  /// Wall time of the numeric factorisations so far (s).
  double factorization_seconds() const { return seconds_; }
  /// Bytes CHOLMOD holds for this factoriser now (its common's count: the factor of the current
  /// pattern and the workspace). A new pattern's analysis replaces the last one's factor.
  std::size_t cholmod_bytes_in_use() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::uint64_t pattern_version_ = 0;
  bool analysed_ = false;
  int factorizations_ = 0;
  int fallbacks_ = 0;
  double seconds_ = 0;
};

}  // namespace rbaa
