#include "rbaa/sim/linear_solver.hpp"

#include <Eigen/CholmodSupport>

#include "rbaa/error.hpp"

namespace rbaa {

namespace {

// Eigen keeps its cholmod_factor protected; this exposes it for copying.
class SupernodalLlt : public Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> {
 public:
  const cholmod_factor* factor() const { return m_cholmodFactor; }
};

}  // namespace

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

Eigen::VectorXd LinearSolver::solve(const Eigen::VectorXd& b) const {
  if (!factored_) throw SolverError("linear solve without a valid factorisation");
  Eigen::VectorXd x = impl_->llt.solve(b);
  return x;
}

}  // namespace rbaa
