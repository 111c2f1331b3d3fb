#include "rbaa/diff/cholmod_factor.hpp"

#include <cholmod.h>

#include <Eigen/SparseCholesky>

#include <chrono>
#include <cstring>

#include "rbaa/error.hpp"
#include "rbaa/sim/linear_solver.hpp"

namespace rbaa {

namespace {

// One cholmod_common per object: CHOLMOD's workspace is not shared between threads, and copies
// and solves need a started common of their own.
struct Common {
  cholmod_common c;
  Common() {
    cholmod_start(&c);
    c.print = 0;  // not-positive-definite is an expected outcome, reported by return value
    c.final_asis = 1;
    c.supernodal = CHOLMOD_SUPERNODAL;
  }
  ~Common() { cholmod_finish(&c); }
  Common(const Common&) = delete;
  Common& operator=(const Common&) = delete;
};

// A CHOLMOD view (no copy) of the lower triangle of a compressed Eigen matrix.
cholmod_sparse view_lower(const Eigen::SparseMatrix<double>& A) {
  cholmod_sparse s;
  std::memset(&s, 0, sizeof(s));
  s.nrow = static_cast<size_t>(A.rows());
  s.ncol = static_cast<size_t>(A.cols());
  s.nzmax = static_cast<size_t>(A.nonZeros());
  s.p = const_cast<int*>(A.outerIndexPtr());
  s.i = const_cast<int*>(A.innerIndexPtr());
  s.x = const_cast<double*>(A.valuePtr());
  s.stype = -1;
  s.itype = CHOLMOD_INT;
  s.xtype = CHOLMOD_REAL;
  s.dtype = CHOLMOD_DOUBLE;
  s.sorted = 1;
  s.packed = 1;
  return s;
}

Eigen::VectorXd cholmod_solve_with(cholmod_factor* L, const Eigen::VectorXd& b, cholmod_common* c) {
  cholmod_dense B;
  std::memset(&B, 0, sizeof(B));
  B.nrow = static_cast<size_t>(b.size());
  B.ncol = 1;
  B.nzmax = B.nrow;
  B.d = B.nrow;
  B.x = const_cast<double*>(b.data());
  B.xtype = CHOLMOD_REAL;
  B.dtype = CHOLMOD_DOUBLE;
  cholmod_dense* X = cholmod_solve(CHOLMOD_A, L, &B, c);
  if (X == nullptr) throw SolverError("CHOLMOD solve failed in the adjoint");
  Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(static_cast<double*>(X->x), b.size());
  cholmod_free_dense(&X, c);
  return x;
}

}  // namespace

struct CholmodFactor::Impl {
  Common common;
  cholmod_factor* L = nullptr;
  ~Impl() {
    if (L != nullptr) cholmod_free_factor(&L, &common.c);
  }
};

CholmodFactor::CholmodFactor() : impl_(std::make_unique<Impl>()) {}
CholmodFactor::~CholmodFactor() = default;

std::unique_ptr<CholmodFactor> CholmodFactor::copy_of(const cholmod_factor_struct* L) {
  if (L == nullptr) throw SolverError("no CHOLMOD factor to copy");
  std::unique_ptr<CholmodFactor> f(new CholmodFactor());
  f->impl_->L = cholmod_copy_factor(const_cast<cholmod_factor*>(L), &f->impl_->common.c);
  if (f->impl_->L == nullptr) throw SolverError("CHOLMOD could not copy a factor (out of memory?)");
  return f;
}

void CholmodFactor::assign(const cholmod_factor_struct* L) {
  if (L == nullptr) throw SolverError("no CHOLMOD factor to copy");
  cholmod_factor* mine = impl_->L;
  if (mine != nullptr && same_cholmod_structure(mine, L)) {
    std::memcpy(mine->x, L->x, L->xsize * sizeof(double));
    return;
  }
  if (mine != nullptr) cholmod_free_factor(&impl_->L, &impl_->common.c);
  impl_->L = cholmod_copy_factor(const_cast<cholmod_factor*>(L), &impl_->common.c);
  if (impl_->L == nullptr) throw SolverError("CHOLMOD could not copy a factor (out of memory?)");
}

bool CholmodFactor::take_values_from(LinearSolver& solver) {
  return impl_->L != nullptr && solver.give_factor_values(impl_->L);
}

Eigen::VectorXd CholmodFactor::solve(const Eigen::VectorXd& b) const {
  return cholmod_solve_with(impl_->L, b, &impl_->common.c);
}

int CholmodFactor::rows() const { return static_cast<int>(impl_->L->n); }

std::size_t CholmodFactor::bytes() const { return bytes_of(impl_->L); }

std::size_t CholmodFactor::cholmod_bytes_in_use() const { return impl_->common.c.memory_inuse; }

std::size_t CholmodFactor::bytes_of(const cholmod_factor_struct* L) {
  if (L == nullptr) return 0;
  std::size_t b = L->n * (2 * sizeof(int));  // Perm, ColCount
  if (L->is_super) {
    b += L->xsize * sizeof(double) + L->ssize * sizeof(int) + 3 * (L->nsuper + 1) * sizeof(int);
  } else {
    b += L->nzmax * (sizeof(double) + sizeof(int)) + (L->n + 1) * 4 * sizeof(int);
  }
  return b;
}

struct HessianFactorizer::Impl {
  Common common;
  cholmod_factor* L = nullptr;
  bool use_ldlt = false;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> ldlt;
  ~Impl() {
    if (L != nullptr) cholmod_free_factor(&L, &common.c);
  }
};

HessianFactorizer::HessianFactorizer() : impl_(std::make_unique<Impl>()) {}
HessianFactorizer::~HessianFactorizer() = default;

void HessianFactorizer::factorize(const Eigen::SparseMatrix<double>& A,
                                  std::uint64_t pattern_version) {
  if (!A.isCompressed()) throw SolverError("adjoint: the Hessian is not compressed");
  const auto t0 = std::chrono::steady_clock::now();
  cholmod_sparse view = view_lower(A);
  cholmod_common* c = &impl_->common.c;
  if (!analysed_ || pattern_version != pattern_version_) {
    if (impl_->L != nullptr) cholmod_free_factor(&impl_->L, c);
    impl_->L = cholmod_analyze(&view, c);
    if (impl_->L == nullptr) throw SolverError("adjoint: CHOLMOD symbolic analysis failed");
    analysed_ = true;
    pattern_version_ = pattern_version;
  }
  cholmod_factorize(&view, impl_->L, c);
  ++factorizations_;
  impl_->use_ldlt = c->status == CHOLMOD_NOT_POSDEF;
  if (impl_->use_ldlt) {
    ++fallbacks_;
    impl_->ldlt.compute(A);
    if (impl_->ldlt.info() != Eigen::Success) {
      throw SolverError("adjoint: the exact Hessian is singular (LL^T and LDL^T both failed)");
    }
  } else if (c->status < CHOLMOD_OK) {
    throw SolverError("adjoint: CHOLMOD numeric factorisation failed");
  }
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::size_t HessianFactorizer::cholmod_bytes_in_use() const { return impl_->common.c.memory_inuse; }

Eigen::VectorXd HessianFactorizer::solve(const Eigen::VectorXd& b) const {
  if (factorizations_ == 0) throw SolverError("adjoint: solve before any factorisation");
  if (impl_->use_ldlt) return impl_->ldlt.solve(b);
  return cholmod_solve_with(impl_->L, b, &impl_->common.c);
}

}  // namespace rbaa
