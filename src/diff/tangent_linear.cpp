#include "rbaa/diff/tangent_linear.hpp"

#include <chrono>
#include <sstream>

#include "rbaa/diff/cholmod_factor.hpp"
#include "rbaa/error.hpp"
#include "rbaa/material/lame.hpp"

namespace rbaa {

namespace {

// The entry of a per-element direction field (0 when the field is empty).
double entry(const Eigen::VectorXd& field, int e) { return field.size() == 0 ? 0.0 : field[e]; }

double dot_or_zero(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return a.size() == 0 || b.size() == 0 ? 0.0 : a.dot(b);
}

double norm_product(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return a.size() == 0 || b.size() == 0 ? 0.0 : a.norm() * b.norm();
}

void check_size(const Eigen::VectorXd& v, Eigen::Index n, const char* what) {
  if (v.size() != 0 && v.size() != n) {
    std::ostringstream msg;
    msg << "tangent: " << what << " has " << v.size() << " entries, expected " << n;
    throw InputError(msg.str());
  }
}

// b = dM(dm) u + w dgrad Psi(dtheta): the change of G at fixed positions along a material
// direction, assembled element by element. Psi_e = alpha_e^3 V_e (mu_e Psi_mu + lambda_e Psi_lambda)
// is linear in (mu, lambda) and cubic in alpha; element_gradient_parts returns alpha^3 V grad Psi_mu
// and alpha^3 V grad Psi_lambda. M is linear in m_e = rho_e alpha_e V_e.
Eigen::VectorXd material_forcing(Simulator& sim, const MaterialField& materials,
                                 const MaterialGradient& d, const Eigen::VectorXd& x,
                                 const Eigen::VectorXd& u, double w, bool consistent) {
  const Tets& T = sim.rest_mesh().T;
  const ElasticForm& elastic = sim.elastic_form();
  Eigen::VectorXd b = Eigen::VectorXd::Zero(x.size());
  const bool elastic_change = d.Y.size() != 0 || d.nu.size() != 0 || d.alpha.size() != 0;
  const bool mass_change = d.rho.size() != 0 || d.alpha.size() != 0;
  for (int e = 0; e < T.rows(); ++e) {
    const double dY = entry(d.Y, e), dnu = entry(d.nu, e), drho = entry(d.rho, e),
                 dalpha = entry(d.alpha, e);
    if (dY == 0.0 && dnu == 0.0 && drho == 0.0 && dalpha == 0.0) continue;
    const double alpha = materials.alpha[e], V = elastic.rest_volume(e);
    if (elastic_change) {
      const LameDerivatives l = lame_derivatives(materials.Y[e], materials.nu[e]);
      // d(alpha^3 mu) / alpha^3 = dmu + 3 mu dalpha / alpha, likewise lambda.
      const double dmu = l.dmu_dY * dY + l.dmu_dnu * dnu + 3.0 * elastic.mu(e) * dalpha / alpha;
      const double dlambda =
          l.dlambda_dY * dY + l.dlambda_dnu * dnu + 3.0 * elastic.lambda(e) * dalpha / alpha;
      if (dmu != 0.0 || dlambda != 0.0) {
        Eigen::Matrix<double, 12, 1> g_mu, g_lambda;
        elastic.element_gradient_parts(x, e, g_mu, g_lambda);
        const Eigen::Matrix<double, 12, 1> ge = w * (dmu * g_mu + dlambda * g_lambda);
        for (int a = 0; a < 4; ++a) b.segment<3>(3 * T(e, a)) += ge.segment<3>(3 * a);
      }
    }
    if (mass_change) {
      const double dm = V * (alpha * drho + materials.rho[e] * dalpha);
      if (dm == 0.0) continue;
      // Element mass matrix per unit mass: consistent (1 + delta_ab) / 20 I_3, lumped delta_ab / 4.
      if (consistent) {
        Eigen::Vector3d sum = Eigen::Vector3d::Zero();
        for (int a = 0; a < 4; ++a) sum += u.segment<3>(3 * T(e, a));
        for (int a = 0; a < 4; ++a) {
          b.segment<3>(3 * T(e, a)) += dm / 20.0 * (sum + u.segment<3>(3 * T(e, a)));
        }
      } else {
        for (int a = 0; a < 4; ++a) b.segment<3>(3 * T(e, a)) += dm / 4.0 * u.segment<3>(3 * T(e, a));
      }
    }
  }
  return b;
}

}  // namespace

TangentResult tangent_linear(Simulator& sim, const MaterialField& materials,
                             const Trajectory& traj, const TrajectorySeed& seed,
                             const std::vector<TangentDirection>& directions) {
  const auto t_start = std::chrono::steady_clock::now();
  const int N = traj.num_steps();
  const int ndof = sim.num_dofs();
  const int nt = sim.rest_mesh().num_tets();
  check_linearisation_inputs(sim, materials, traj, seed, "tangent");
  for (const TangentDirection& d : directions) {
    check_size(d.materials.Y, nt, "a direction's Y");
    check_size(d.materials.nu, nt, "a direction's nu");
    check_size(d.materials.rho, nt, "a direction's rho");
    check_size(d.materials.alpha, nt, "a direction's alpha");
    check_size(d.q0, ndof, "a direction's q0");
    check_size(d.v0, ndof, "a direction's v0");
  }
  for (const Eigen::VectorXd& s : seed.dq) check_size(s, ndof, "a seed entry");

  const std::size_t nd = directions.size();
  TangentResult result;
  result.derivatives.assign(nd, 0.0);
  result.bounds.assign(nd, 0.0);

  // dq_k for k = -3 .. N, kept for the last (order + 1) positions only: dq[d][k + 3].
  const BdfIntegrator& bdf = sim.integrator();
  const std::vector<double>& c = bdf.predictor_coefficients();
  const double w = bdf.potential_weight();
  const double h = traj.time_step;
  const Eigen::Vector3d gravity = sim.settings().gravity;
  const bool consistent = sim.settings().mass == MassModel::kConsistent;
  std::vector<std::vector<Eigen::VectorXd>> dq(nd, std::vector<Eigen::VectorXd>(N + 4));
  for (std::size_t i = 0; i < nd; ++i) {
    const TangentDirection& d = directions[i];
    const Eigen::VectorXd dq0 = d.q0.size() ? d.q0 : Eigen::VectorXd::Zero(ndof);
    const Eigen::VectorXd dv0 = d.v0.size() ? d.v0 : Eigen::VectorXd::Zero(ndof);
    dq[i][3] = dq0;
    for (int j = 1; j <= 3; ++j) dq[i][3 - j] = dq0 - (j * h) * dv0;
    // Driven positions are prescribed: no direction moves them.
    for (int j = 0; j <= 3; ++j) {
      for (int dof : sim.driven_dofs()) dq[i][j][dof] = 0.0;
    }
    // The objective's direct dependence on the materials, and on q_0.
    result.derivatives[i] +=
        dot_or_zero(seed.direct.Y, d.materials.Y) + dot_or_zero(seed.direct.nu, d.materials.nu) +
        dot_or_zero(seed.direct.rho, d.materials.rho) +
        dot_or_zero(seed.direct.alpha, d.materials.alpha) + dot_or_zero(seed.dq[0], dq[i][3]);
    result.bounds[i] +=
        norm_product(seed.direct.Y, d.materials.Y) + norm_product(seed.direct.nu, d.materials.nu) +
        norm_product(seed.direct.rho, d.materials.rho) +
        norm_product(seed.direct.alpha, d.materials.alpha) + norm_product(seed.dq[0], dq[i][3]);
  }

  HessianFactorizer factorizer;
  Eigen::VectorXd q_hat(ndof), u(ndof), dq_hat(ndof);
  for (int k = 0; k < N; ++k) {
    ++result.stats.steps;
    const Eigen::VectorXd& x = traj.q[k + 1];
    PlaneFrictionForm* friction = sim.plane_friction_form();
    if (friction != nullptr) friction->lag(traj.position(k), traj.position(k - 1));
    IncrementalPotential& E = sim.potential();
    E.solution_changed(x);
    const int fb0 = factorizer.num_ldlt_fallbacks();
    // Assembled before the pattern version is read: the pattern follows the contact pairs.
    const Eigen::SparseMatrix<double>& H = E.hessian(x, HessianKind::kExact);
    factorizer.factorize(H, sim.hessian_pattern().pattern_version());
    result.stats.ldlt_fallbacks += factorizer.num_ldlt_fallbacks() - fb0;
    ++result.stats.factorizations;

    const Eigen::VectorXd& q_n = traj.position(k);
    q_hat = q_n;
    for (int j = 1; j < static_cast<int>(c.size()); ++j) q_hat += c[j] * (traj.position(k - j) - q_n);
    u = x - q_hat;
    for (int v = 0; v < ndof / 3; ++v) u.segment<3>(3 * v) -= w * gravity;

    for (std::size_t i = 0; i < nd; ++i) {
      dq_hat.setZero();
      for (int j = 0; j < static_cast<int>(c.size()); ++j) dq_hat += c[j] * dq[i][k - j + 3];
      Eigen::VectorXd rhs = sim.inertia_form().multiply(dq_hat) -
                            material_forcing(sim, materials, directions[i].materials, x, u, w,
                                             consistent);
      if (friction != nullptr) rhs -= friction->history_tangent(x, dq[i][k + 3], dq[i][k + 2], w);
      // The step equation holds at the free dofs only; H's identity rows keep dq zero at driven
      // ones.
      for (int dof : sim.driven_dofs()) rhs[dof] = 0.0;
      dq[i][k + 4] = factorizer.solve(rhs);
      result.derivatives[i] += dot_or_zero(seed.dq[k + 1], dq[i][k + 4]);
      result.bounds[i] += norm_product(seed.dq[k + 1], dq[i][k + 4]);
      // Positions older than the predictor's reach are no longer needed.
      const int drop = k + 3 - static_cast<int>(c.size());
      if (drop >= 0) dq[i][drop] = Eigen::VectorXd();
    }
  }
  for (std::size_t i = 0; i < nd; ++i) result.final_dq.push_back(dq[i][N + 3]);
  result.stats.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  return result;
}

}  // namespace rbaa
