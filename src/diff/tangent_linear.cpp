#include "rbaa/diff/tangent_linear.hpp"

#include <chrono>
#include <sstream>

#include "rbaa/diff/cholmod_factor.hpp"
#include "rbaa/error.hpp"
#include "start_history.hpp"

namespace rbaa {

namespace {

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
  std::vector<std::vector<Eigen::VectorXd>> dq(nd, std::vector<Eigen::VectorXd>(N + 4));
  for (std::size_t i = 0; i < nd; ++i) {
    const TangentDirection& d = directions[i];
    const Eigen::VectorXd dq0 = d.q0.size() ? d.q0 : Eigen::VectorXd::Zero(ndof);
    const Eigen::VectorXd dv0 = d.v0.size() ? d.v0 : Eigen::VectorXd::Zero(ndof);
    dq[i][3] = dq0;
    for (int j = 1; j <= 3; ++j) dq[i][3 - j] = diff_detail::start_history_tangent(sim, j, dq0, dv0);
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
  Eigen::VectorXd q_hat(ndof), dq_hat(ndof);
  for (int k = 0; k < N; ++k) {
    ++result.stats.steps;
    const Eigen::VectorXd& x = traj.q[k + 1];
    // The step's own rule, predictor and weight (steps may differ in size).
    const BdfPredictor P = traj.predictor(k);
    const std::vector<double>& c = P.c;
    sim.use_step(traj.rule(k), P.weight, traj.step_size(k));
    IncrementalPotential& E = sim.potential();
    E.lag(traj.position(k), traj.position(k - 1));
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
    sim.inertia_form().set_predictor(q_hat);

    for (std::size_t i = 0; i < nd; ++i) {
      dq_hat.setZero();
      for (int j = 0; j < static_cast<int>(c.size()); ++j) dq_hat += c[j] * dq[i][k - j + 3];
      // The change of G at fixed x: through the materials and the history, summed over forms.
      Eigen::VectorXd change = Eigen::VectorXd::Zero(ndof);
      E.add_material_tangent(x, directions[i].materials, materials, change);
      E.add_history_tangent(x, dq[i][k + 3], dq[i][k + 2], change);
      Eigen::VectorXd rhs = sim.inertia_form().multiply(dq_hat) - change;
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
  sim.set_next_step(sim.units_per_step());  // back to the scene's h
  for (std::size_t i = 0; i < nd; ++i) result.final_dq.push_back(dq[i][N + 3]);
  result.stats.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  return result;
}

}  // namespace rbaa
