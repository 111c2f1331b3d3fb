#include "rbaa/sim/linear_solver.hpp"

#include <Eigen/CholmodSupport>

#include <cstring>

#include "rbaa/error.hpp"

namespace rbaa {

namespace {

// Eigen keeps its cholmod_factor protected; this exposes it for copying.
class SupernodalLlt : public Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> {
 public:
  const cholmod_factor* factor() const { return m_cholmodFactor; }
  cholmod_factor* factor() { return m_cholmodFactor; }
};

template <typename T>
bool same_array(const void* a, const void* b, std::size_t n) {
  return n == 0 || (a != nullptr && b != nullptr && std::memcmp(a, b, n * sizeof(T)) == 0);
}

}  // namespace

bool same_cholmod_structure(const cholmod_factor_struct* a, const cholmod_factor_struct* b) {
  if (!a->is_super || !b->is_super || a->xtype != CHOLMOD_REAL || b->xtype != CHOLMOD_REAL) return false;
  if (a->itype != CHOLMOD_INT || b->itype != CHOLMOD_INT || a->dtype != b->dtype) return false;
  if (a->n != b->n || a->nsuper != b->nsuper || a->ssize != b->ssize || a->xsize != b->xsize ||
      a->is_ll != b->is_ll || a->ordering != b->ordering || a->maxcsize != b->maxcsize ||
      a->maxesize != b->maxesize) {
    return false;
  }
  return same_array<int>(a->Perm, b->Perm, a->n) && same_array<int>(a->ColCount, b->ColCount, a->n) &&
         same_array<int>(a->super, b->super, a->nsuper + 1) &&
         same_array<int>(a->pi, b->pi, a->nsuper + 1) && same_array<int>(a->px, b->px, a->nsuper + 1) &&
         same_array<int>(a->s, b->s, a->ssize);
}

struct LinearSolver::Impl {
  SupernodalLlt llt;
};

LinearSolver::LinearSolver() : impl_(std::make_unique<Impl>()) {
  // Not-positive-definite is an expected outcome (the exact Hessian is tried first near
  // convergence); report it through the return value, not through CHOLMOD's printing.
  impl_->llt.cholmod().print = 0;
}

LinearSolver::~LinearSolver() = default;

bool LinearSolver::factorize(const Eigen::SparseMatrix<double>& A, std::uint64_t pattern_version) {
  if (pattern_version != pattern_version_) {
    impl_->llt.analyzePattern(A);
    pattern_version_ = pattern_version;
    ++analyses_;
    if (impl_->llt.info() != Eigen::Success) {
      throw SolverError("CHOLMOD symbolic analysis failed");
    }
  }
  impl_->llt.factorize(A);
  ++factorizations_;
  factored_ = impl_->llt.info() == Eigen::Success;
  return factored_;
}

const cholmod_factor_struct* LinearSolver::cholmod_factor() const {
  return factored_ ? impl_->llt.factor() : nullptr;
}

bool LinearSolver::give_factor_values(cholmod_factor_struct* other) {
  if (!factored_ || other == nullptr) return false;
  ::cholmod_factor* mine = impl_->llt.factor();
  if (mine == nullptr || !same_cholmod_structure(mine, other)) return false;
  std::swap(mine->x, other->x);
  factored_ = false;
  return true;
}

Eigen::VectorXd LinearSolver::solve(const Eigen::VectorXd& b) const {
  if (!factored_) throw SolverError("linear solve without a valid factorisation");
  Eigen::VectorXd x = impl_->llt.solve(b);
  return x;
}

}  // namespace rbaa
