#include "rbaa/opt/moment_cost.hpp"

#include <cmath>
#include <sstream>

#include "rbaa/error.hpp"

namespace rbaa {

MomentCostFunction::MomentCostFunction(const TetMesh& mesh, const DesignSpace& design,
                                       const Moments& reference)
    : design_(design),
      S_(moment_operator(mesh)),
      reference_(reference.as_vector()),
      scale_(moment_normalisation(reference)) {
  if (mesh.num_tets() != design.num_tets()) {
    std::ostringstream msg;
    msg << "moment cost: the mesh has " << mesh.num_tets() << " elements, the design space "
        << design.num_tets();
    throw InputError(msg.str());
  }
  // Only the designed elements' moments: with an element mask (several bodies in one mesh) the
  // other bodies are not the attacked object, and their mass must not enter its moments.
  for (int e = 0; e < design_.num_tets(); ++e) {
    if (!design_.is_designed(e)) S_.col(e).setZero();
  }
  AddParameterBlock(design_.size());
  SetNumResiduals(10);
}

MomentCostFunction::~MomentCostFunction() = default;

bool MomentCostFunction::Evaluate(double const* const* parameters, double* residuals,
                                  double** jacobians) const {
  const int n = design_.size();
  const Eigen::Map<const Eigen::VectorXd> theta(parameters[0], n);
  const MaterialField m = design_.to_material(theta);

  // Per-element density rho alpha; the product with S sums in element order.
  const MomentVector r = (S_ * m.effective_density() - reference_).cwiseQuotient(scale_);
  Eigen::Map<MomentVector> out(residuals);
    out = r;
  if (!r.allFinite()) return false;

  if (jacobians != nullptr && jacobians[0] != nullptr) {
    Eigen::Map<Eigen::Matrix<double, 10, Eigen::Dynamic, Eigen::RowMajor>> J(jacobians[0], 10, n);
    J.setZero();
    const Eigen::Matrix<double, 10, 1> inv_scale = scale_.cwiseInverse();
    if (design_.optimises(DesignField::kRho)) {
      const int o = design_.offset(DesignField::kRho);
      const TanhBoxMap& map = design_.map(DesignField::kRho);
      for (int i = 0; i < design_.num_designed(); ++i) {
        const int e = design_.designed()[i];
        J.col(o + i) =
            S_.col(e).cwiseProduct(inv_scale) * (m.alpha[e] * map.derivative(theta[o + i]));
      }
    }
    if (design_.optimises(DesignField::kAlpha)) {
      const int o = design_.offset(DesignField::kAlpha);
      const TanhBoxMap& map = design_.map(DesignField::kAlpha);
      for (int i = 0; i < design_.num_interior(); ++i) {
        const int e = design_.interior()[i];
        J.col(o + i) = S_.col(e).cwiseProduct(inv_scale) * (m.rho[e] * map.derivative(theta[o + i]));
      }
    }
  }
  return true;
}

MomentVector MomentCostFunction::residuals(const Eigen::VectorXd& theta) const {
  if (theta.size() != design_.size()) throw InputError("moment cost: design vector of wrong size");
  MomentVector r;
  const double* p[1] = {theta.data()};
  Evaluate(p, r.data(), nullptr);
  return r;
}

Eigen::Matrix<double, 10, Eigen::Dynamic> MomentCostFunction::jacobian(
    const Eigen::VectorXd& theta) const {
  if (theta.size() != design_.size()) throw InputError("moment cost: design vector of wrong size");
  MomentVector r;
  Eigen::Matrix<double, 10, Eigen::Dynamic, Eigen::RowMajor> J(10, design_.size());
  const double* p[1] = {theta.data()};
  double* jac[1] = {J.data()};
  Evaluate(p, r.data(), jac);
  return J;
}

double MomentCostFunction::penalty(const Eigen::VectorXd& theta, double beta,
                                   Eigen::VectorXd* gradient) const {
  const MomentVector r = residuals(theta);
  if (gradient) *gradient = 2.0 * beta * (jacobian(theta).transpose() * r);
  return beta * r.squaredNorm();
}

}  // namespace rbaa
