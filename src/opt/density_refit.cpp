#include "rbaa/opt/density_refit.hpp"

#include <ceres/ceres.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>
#include <utility>

#include "rbaa/error.hpp"

namespace rbaa {
namespace {

using Basis = Eigen::Matrix<double, Eigen::Dynamic, 10>;  // #T by 10: phi_k(e)

// Residuals and Jacobian in c. r = (S d - m_ref) ./ scale with d_e = alpha_e rho(theta0_e + Phi_e c);
// dr/dc = diag(1/scale) S diag(alpha o rho'(theta)) Phi.
class RefitCost : public ceres::SizedCostFunction<10, 10> {
 public:
  RefitCost(const Eigen::Matrix<double, 10, Eigen::Dynamic>& S, const Eigen::VectorXd& alpha,
            const Eigen::VectorXd& theta0, const Basis& phi, const MomentVector& reference,
            const MomentVector& scale, const TanhBoxMap& map)
      : S_(S), alpha_(alpha), theta0_(theta0), phi_(phi), reference_(reference), scale_(scale),
        map_(map) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const Eigen::Map<const Eigen::Matrix<double, 10, 1>> c(parameters[0]);
    const Eigen::VectorXd theta = theta0_ + phi_ * c;
    const Eigen::Index nt = theta.size();
    Eigen::VectorXd density(nt);
    for (Eigen::Index e = 0; e < nt; ++e) density[e] = alpha_[e] * map_.value(theta[e]);
    const MomentVector r = (S_ * density - reference_).cwiseQuotient(scale_);
    Eigen::Map<MomentVector> out(residuals);
    out = r;
    if (!r.allFinite()) return false;
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      Eigen::VectorXd w(nt);
      for (Eigen::Index e = 0; e < nt; ++e) w[e] = alpha_[e] * map_.derivative(theta[e]);
      Eigen::Map<Eigen::Matrix<double, 10, 10, Eigen::RowMajor>> J(jacobians[0]);
      J = scale_.cwiseInverse().asDiagonal() * (S_ * w.asDiagonal() * phi_);
    }
    return true;
  }

 private:
  const Eigen::Matrix<double, 10, Eigen::Dynamic>& S_;
  const Eigen::VectorXd& alpha_;
  const Eigen::VectorXd& theta0_;
  const Basis& phi_;
  const MomentVector& reference_;
  const MomentVector& scale_;
  const TanhBoxMap& map_;
};

// Stops Ceres once the max normalised residual about the origin (the quantity the bar is on,
// evaluated at the current iterate) is well below the bar.
class StopWhenFitted : public ceres::IterationCallback {
 public:
  StopWhenFitted(std::function<double()> max_residual, double threshold)
      : max_residual_(std::move(max_residual)), threshold_(threshold) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary&) override {
    return max_residual_() <= threshold_ ? ceres::SOLVER_TERMINATE_SUCCESSFULLY
                                         : ceres::SOLVER_CONTINUE;
  }

 private:
  std::function<double()> max_residual_;
  double threshold_;
};

// The moments of a Moments value about the point c (the parallel-axis shift), as a vector.
MomentVector moments_about(const Moments& m, const Eigen::Vector3d& c) {
  Moments out;
  out.m0 = m.m0;
  out.m1 = m.m1 - m.m0 * c;
  const Eigen::Matrix3d I =
      m.inertia_about_origin() - m.m0 * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose()) -
      (2.0 * c.dot(out.m1) * Eigen::Matrix3d::Identity() - c * out.m1.transpose() - out.m1 * c.transpose());
  out.m2 << I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2);
  return out.as_vector();
}

}  // namespace

DensityRefitResult refit_density(const TetMesh& mesh, const Eigen::VectorXd& alpha,
                                 const Eigen::VectorXd& rho, const Moments& reference,
                                 const TanhBoxMap& rho_map, const DensityRefitOptions& options) {
  const int nt = mesh.num_tets();
  if (alpha.size() != nt || rho.size() != nt) {
    std::ostringstream msg;
    msg << "density re-fit: alpha has " << alpha.size() << " and rho " << rho.size()
        << " entries, the mesh " << nt << " elements";
    throw InputError(msg.str());
  }
  if (!(options.tolerance > 0.0) || options.max_iterations < 1) {
    throw InputError("density re-fit: tolerance must be positive and max_iterations >= 1");
  }
  const Eigen::Matrix<double, 10, Eigen::Dynamic> S = moment_operator(mesh);
  const MomentVector m_ref = reference.as_vector();
  const MomentVector scale = moment_normalisation(reference);

  // Feasibility of m0: the tanh map keeps every density strictly inside (rho_min, rho_max).
  double occupied_volume = 0.0, total_volume = 0.0;
  for (int e = 0; e < nt; ++e) {
    occupied_volume += alpha[e] * S(0, e);
    total_volume += S(0, e);
  }
  if (!(occupied_volume * rho_map.lo() < m_ref[0] && m_ref[0] < occupied_volume * rho_map.hi())) {
    std::ostringstream msg;
    msg << "density re-fit: the occupied volume " << occupied_volume << " m^3 (void fraction "
        << 100.0 * (1.0 - occupied_volume / total_volume) << " %) would need a mean density of "
        << m_ref[0] / occupied_volume << " kg/m^3 to match m0 = " << m_ref[0]
        << " kg, outside the density bounds (" << rho_map.lo() << ", " << rho_map.hi()
        << ") kg/m^3; lower the void fraction (rounding threshold, occupancy) or widen the bounds";
    throw InputError(msg.str());
  }

  // theta0, with values on a bound moved just inside so that the inverse map is finite.
  const double margin = 1e-12 * (rho_map.hi() - rho_map.lo());
  Eigen::VectorXd theta0(nt);
  for (int e = 0; e < nt; ++e) {
    if (!std::isfinite(rho[e])) {
      throw InputError("density re-fit: rho of element " + std::to_string(e) + " is not finite");
    }
    const double r = std::clamp(rho[e], rho_map.lo() + margin, rho_map.hi() - margin);
    theta0[e] = rho_map.inverse(r, "rho of element " + std::to_string(e));
  }

  // phi_k(e): element averages of the moment integrands in centred, scaled coordinates; zero on
  // void elements so that they keep their density.
  const Eigen::Vector3d centre = reference.centre_of_mass();
  const double L = radius_of_gyration(reference);
  TetMesh local = mesh;
  local.V = (mesh.V.rowwise() - centre.transpose()) / L;
  const Eigen::Matrix<double, 10, Eigen::Dynamic> S_local = moment_operator(local);
  Basis phi(nt, 10);
  for (int e = 0; e < nt; ++e) {
    if (alpha[e] > 0.0) {
      phi.row(e) = (S_local.col(e) / S_local(0, e)).transpose();
    } else {
      phi.row(e).setZero();
    }
  }

  // Ceres works on the moments about the reference's centre of mass, normalised the same way: an
  // invertible linear map of the residuals about the origin, with the same zero, but without the
  // (|c| / L)^2 amplification that makes the origin residuals of an object far from the origin
  // (the ball at 3.4 m, L = 7.7 cm: a factor 2000) badly conditioned for Levenberg-Marquardt.
  TetMesh shifted = mesh;
  shifted.V = mesh.V.rowwise() - centre.transpose();
  const Eigen::Matrix<double, 10, Eigen::Dynamic> S_centred = moment_operator(shifted);
  const MomentVector m_ref_centred = moments_about(reference, centre);

  DensityRefitResult result;
  result.c.setZero();
  auto origin_residual = [&](const Eigen::Matrix<double, 10, 1>& c) {
    const Eigen::VectorXd theta = theta0 + phi * c;
    Eigen::VectorXd density = Eigen::VectorXd::Zero(nt);
    for (int e = 0; e < nt; ++e) {
      if (alpha[e] > 0.0) density[e] = alpha[e] * rho_map.value(theta[e]);
    }
    return MomentVector((S * density - m_ref).cwiseQuotient(scale));
  };
  result.initial_max_residual = origin_residual(result.c).cwiseAbs().maxCoeff();

  auto* cost = new RefitCost(S_centred, alpha, theta0, phi, m_ref_centred, scale, rho_map);
  {
    // Precondition: replace the basis by phi J0^-1 (same span), so that the Jacobian at the start
    // is the identity and Levenberg-Marquardt's damping (relative to the scaled Jacobian) stays
    // negligible: the iteration is then Gauss-Newton on a nearly linear problem. (The cost holds
    // phi by reference and sees the new basis.)
    const double* p[1] = {result.c.data()};
    MomentVector r0;
    Eigen::Matrix<double, 10, 10, Eigen::RowMajor> J0;
    double* jac[1] = {J0.data()};
    cost->Evaluate(p, r0.data(), jac);
    const Eigen::FullPivLU<Eigen::Matrix<double, 10, 10>> lu(J0);
    if (lu.isInvertible()) phi = phi * lu.inverse();
  }

  if (options.check_jacobian) {
    // The analytic Jacobian against central differences of the residuals, normwise, at c = 0
    // and at a c whose density change is about the range's (where the tanh map bends).
    auto evaluate = [&](const Eigen::Matrix<double, 10, 1>& c, MomentVector* r,
                        Eigen::Matrix<double, 10, 10, Eigen::RowMajor>* J) {
      const double* p[1] = {c.data()};
      double* jac[1] = {J != nullptr ? J->data() : nullptr};
      cost->Evaluate(p, r->data(), J != nullptr ? jac : nullptr);
    };
    Eigen::Matrix<double, 10, 1> c_probe;
    for (int k = 0; k < 10; ++k) c_probe[k] = 0.05 * std::cos(1.0 + 2.3 * k);
    for (const Eigen::Matrix<double, 10, 1>& c : {Eigen::Matrix<double, 10, 1>::Zero().eval(), c_probe}) {
      MomentVector r, rp, rm;
      Eigen::Matrix<double, 10, 10, Eigen::RowMajor> J, J_fd;
      evaluate(c, &r, &J);
      const double step = 1e-6;
      for (int k = 0; k < 10; ++k) {
        Eigen::Matrix<double, 10, 1> cp = c, cm = c;
        cp[k] += step;
        cm[k] -= step;
        evaluate(cp, &rp, nullptr);
        evaluate(cm, &rm, nullptr);
        J_fd.col(k) = (rp - rm) / (2 * step);
      }
      result.jacobian_check_error =
          std::max(result.jacobian_check_error, (J - J_fd).norm() / J.norm());
    }
  }

  ceres::Problem::Options problem_options;
  ceres::Problem problem(problem_options);  // owns `cost`
  problem.AddResidualBlock(cost, nullptr, result.c.data());

  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = options.max_iterations;
  // The callback decides convergence on the residuals the bar is about; Ceres' relative tests
  // would stop too early for 1e-10, so they are off.
  solver_options.function_tolerance = 0.0;
  solver_options.gradient_tolerance = 0.0;
  solver_options.parameter_tolerance = 0.0;
  solver_options.num_threads = 1;
  solver_options.logging_type = ceres::SILENT;
  solver_options.minimizer_progress_to_stdout = false;
  solver_options.update_state_every_iteration = true;  // the callback reads result.c
  // Stop at 1 % of the tolerance, or once the residual is within a few round-off units of zero
  // if that is coarser: the residuals about the origin cannot be evaluated more finely than
  // eps sum_e |S_ke| d_e / scale_k (for the ball at 3.4 m, |c| / L ~ 45, that unit is ~4e-13, and
  // its ulp steps of 1.8e-13 are what Ceres sees below it). A fixed 1e-12 sat five such steps
  // above zero, so whether and when it was reached depended on the last bits of the input (6 to
  // 22 iterations on the same sphere).
  double roundoff_unit = 0.0;
  {
    Eigen::VectorXd density = Eigen::VectorXd::Zero(nt);
    for (int e = 0; e < nt; ++e) density[e] = alpha[e] * rho[e];
    const MomentVector magnitude = S.cwiseAbs() * density.cwiseAbs() + m_ref.cwiseAbs();
    roundoff_unit = std::numeric_limits<double>::epsilon() *
                    magnitude.cwiseQuotient(scale).maxCoeff();
  }
  StopWhenFitted stop([&] { return origin_residual(result.c).cwiseAbs().maxCoeff(); },
                      std::max(0.01 * options.tolerance, 16.0 * roundoff_unit));
  solver_options.callbacks.push_back(&stop);

  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  result.iterations = summary.num_successful_steps + summary.num_unsuccessful_steps;
  result.ceres_report = summary.BriefReport();

  const Eigen::VectorXd theta = theta0 + phi * result.c;
  result.rho = rho;
  for (int e = 0; e < nt; ++e) {
    if (alpha[e] > 0.0) result.rho[e] = rho_map.value(theta[e]);
  }
  result.residual = (S * result.rho.cwiseProduct(alpha) - m_ref).cwiseQuotient(scale);
  result.max_residual = result.residual.cwiseAbs().maxCoeff();
  if (!(result.max_residual <= options.tolerance)) {
    std::ostringstream msg;
    msg << "density re-fit: max normalised moment residual " << result.max_residual
        << " after " << result.iterations << " iterations is above the tolerance "
        << options.tolerance << " (" << result.ceres_report << ")";
    throw SolverError(msg.str());
  }
  return result;
}

}  // namespace rbaa
