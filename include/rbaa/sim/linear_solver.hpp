#pragma once
// Sparse symmetric positive definite solves with CHOLMOD's supernodal Cholesky (through Eigen's
// CholmodSupport). The symbolic analysis (fill-reducing ordering, elimination tree, supernodes)
// depends only on the sparsity pattern, which is fixed for a mesh, so it runs once per pattern and
// every Newton iteration pays the numeric factorisation only.

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <cstdint>
#include <memory>

struct cholmod_factor_struct;

namespace rbaa {

/// Whether two supernodal real CHOLMOD factors (int indices) share their symbolic structure, so
/// that their value arrays are interchangeable (the adjoint refills stored factors this way).
bool same_cholmod_structure(const cholmod_factor_struct* a, const cholmod_factor_struct* b);

class LinearSolver {
 public:
  LinearSolver();
  ~LinearSolver();
  LinearSolver(const LinearSolver&) = delete;
  LinearSolver& operator=(const LinearSolver&) = delete;

  /// Numeric factorisation of A (its lower triangle). `pattern_version` identifies A's pattern:
  /// the symbolic analysis is redone only when it changes. Returns false when CHOLMOD finds A
  /// not positive definite (the factor is then unusable until the next successful call).
  bool factorize(const Eigen::SparseMatrix<double>& A, std::uint64_t pattern_version);
  /// x = A^-1 b with the last successful factorisation.
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;
  bool has_factor() const { return factored_; }
  /// The CHOLMOD factor of the last successful factorisation (null without one), for callers
  /// that keep a copy (the adjoint's stored factors, cholmod_copy_factor); valid until the next
  /// factorize().
  const cholmod_factor_struct* cholmod_factor() const;
  /// Hands the numeric values of the last factorisation to `other`, a factor of the same
  /// symbolic structure (a copy of an earlier factor of this solver), by exchanging the value
  /// arrays instead of copying them; this solver takes other's old values and has no valid
  /// factor until the next factorize(). Returns false (and changes nothing) when there is no
  /// factor or the structures differ. The adjoint's stored factors use it to keep each step's
  /// factor without copying it.
  bool give_factor_values(cholmod_factor_struct* other);
  /// How many symbolic analyses and numeric factorisations ran (for reports and tests).
  int num_analyses() const { return analyses_; }
  int num_factorizations() const { return factorizations_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::uint64_t pattern_version_ = 0;
  bool factored_ = false;
  int analyses_ = 0;
  int factorizations_ = 0;
};

}  // namespace rbaa
