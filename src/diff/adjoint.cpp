#include "rbaa/diff/adjoint.hpp"

#include <chrono>
#include <sstream>

#include "rbaa/error.hpp"
#include "start_history.hpp"

namespace rbaa {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Newton's factor of the step just taken (null when the solver cannot hand it out).
const cholmod_factor_struct* newton_factor(Simulator& sim) {
  return sim.newton().linear_solver().cholmod_factor();
}

// dC/dq_hat of step n+1 goes to q_{n-j} with the predictor's coefficients; positions with a
// negative index are the ballistic history. qbar[k + 3] holds dC/dq_k, k = -3 .. N.
struct PositionAdjoints {
  std::vector<Eigen::VectorXd> qbar;
  Eigen::VectorXd& at(int k) { return qbar[k + 3]; }
};

// The backward pass shared by both storage modes. factors[k] (may be empty / null) is the exact
// factor of step k (the step that produced q_{k+1}).
AdjointResult run_adjoint(Simulator& sim, const MaterialField& materials,
                          const Trajectory& traj, const TrajectorySeed& seed,
                          const std::vector<std::unique_ptr<CholmodFactor>>& factors,
                          HessianFactorizer& factorizer) {
  const auto t_start = std::chrono::steady_clock::now();
  const int N = traj.num_steps();
  const int ndof = sim.num_dofs();
  const int nt = sim.rest_mesh().num_tets();
  check_linearisation_inputs(sim, materials, traj, seed, "adjoint");

  PositionAdjoints adj;
  adj.qbar.assign(N + 4, Eigen::VectorXd::Zero(ndof));
  for (int k = 0; k <= N; ++k) {
    if (seed.dq[k].size() == 0) continue;
    if (seed.dq[k].size() != ndof) throw InputError("adjoint: a seed entry has the wrong size");
    adj.at(k) += seed.dq[k];
  }

  AdjointResult result;
  MaterialGradient& g = result.materials;
  g.Y = Eigen::VectorXd::Zero(nt);
  g.nu = Eigen::VectorXd::Zero(nt);
  g.rho = Eigen::VectorXd::Zero(nt);
  g.alpha = Eigen::VectorXd::Zero(nt);
  auto add_direct = [nt](Eigen::VectorXd& to, const Eigen::VectorXd& from) {
    if (from.size() == 0) return;
    if (from.size() != nt) throw InputError("adjoint: a direct material gradient has the wrong size");
    to += from;
  };
  add_direct(g.Y, seed.direct.Y);
  add_direct(g.nu, seed.direct.nu);
  add_direct(g.rho, seed.direct.rho);
  add_direct(g.alpha, seed.direct.alpha);

  IncrementalPotential& E = sim.potential();

  Eigen::VectorXd q_hat(ndof), lambda(ndof);
  for (int k = N - 1; k >= 0; --k) {
    ++result.stats.steps;
    // Driven positions are known functions of time: no adjoint flows into them (the Hessian has
    // identity rows there, so lambda is zero there too and the free dofs' adjoint is that of the
    // step equation with the driven dofs fixed).
    Eigen::VectorXd& qbar = adj.at(k + 1);
    for (int d : sim.driven_dofs()) qbar[d] = 0.0;
    if (qbar.isZero(0.0)) continue;  // nothing later depends on this step
    const Eigen::VectorXd& x = traj.q[k + 1];
    ++result.stats.solves;
    // The step's own rule, predictor and weight (steps may differ in size).
    const BdfPredictor P = traj.predictor(k);
    const std::vector<double>& c = P.c;
    sim.use_step(traj.rule(k), P.weight, traj.step_size(k));
    // The forms' lag of this step (lagged friction's Hessian and history terms need it).
    E.lag(traj.position(k), traj.position(k - 1));

    const auto t_solve = std::chrono::steady_clock::now();
    const CholmodFactor* stored =
        k < static_cast<int>(factors.size()) ? factors[k].get() : nullptr;
    if (stored != nullptr) {
      lambda = stored->solve(qbar);
      ++result.stats.stored_factor_solves;
    } else {
      E.solution_changed(x);
      const double f0 = factorizer.factorization_seconds();
      const int fb0 = factorizer.num_ldlt_fallbacks();
      // Assembled before the pattern version is read: the pattern follows the contact pairs.
      const Eigen::SparseMatrix<double>& H = E.hessian(x, HessianKind::kExact);
      factorizer.factorize(H, sim.hessian_pattern().pattern_version());
      result.stats.factorization_seconds += factorizer.factorization_seconds() - f0;
      result.stats.ldlt_fallbacks += factorizer.num_ldlt_fallbacks() - fb0;
      ++result.stats.rebuilt_factorizations;
      lambda = factorizer.solve(qbar);
    }
    result.stats.solve_seconds += seconds_since(t_solve);

    // q_hat in the simulator's difference form (sum c_j = 1): q_n + sum_j c_j (q_{n-j} - q_n).
    const Eigen::VectorXd& q_n = traj.position(k);
    q_hat = q_n;
    for (int j = 1; j < static_cast<int>(c.size()); ++j) q_hat += c[j] * (traj.position(k - j) - q_n);
    sim.inertia_form().set_predictor(q_hat);

    // dC/dq_hat = M lambda, spread over the predictor's positions.
    const Eigen::VectorXd Mlambda = sim.inertia_form().multiply(lambda);
    for (int j = 0; j < static_cast<int>(c.size()); ++j) adj.at(k - j) += c[j] * Mlambda;
    // Forms that depend on q_n and q_{n-1} besides through q_hat (lagged friction's normal forces
    // and x~).
    E.add_history_adjoint(x, lambda, adj.at(k), adj.at(k - 1));

    // dC/dtheta -= lambda^T dG/dtheta, summed over the forms (inertia and gravity through the
    // element masses, elasticity through the moduli and alpha^3).
    const auto t_parameters = std::chrono::steady_clock::now();
    E.add_material_adjoint(x, lambda, materials, g);
    result.stats.parameter_seconds += seconds_since(t_parameters);
  }

  sim.set_next_step(sim.units_per_step());  // back to the scene's h
  // The start-up history: ballistic for free bodies, the drive's past for driven ones.
  result.dq0 = adj.at(0);
  result.dv0 = Eigen::VectorXd::Zero(ndof);
  for (int j = 1; j <= 3; ++j) {
    diff_detail::add_start_history_adjoint(sim, j, adj.at(-j), result.dq0, result.dv0);
  }
  // Driven vertices start where their drive says, at its velocity: not initial-state unknowns.
  for (int d : sim.driven_dofs()) result.dq0[d] = result.dv0[d] = 0.0;
  result.stats.seconds = seconds_since(t_start);
  return result;
}

}  // namespace

void check_linearisation_inputs(const Simulator& sim, const MaterialField& materials,
                                const Trajectory& traj, const TrajectorySeed& seed,
                                const std::string& who) {
  const int N = traj.num_steps();
  if (static_cast<int>(traj.q.size()) != N + 1 || traj.history.size() != 3) {
    throw InputError(who + ": the trajectory does not hold N + 1 positions and 3 history ones");
  }
  if (!traj.step_sizes.empty() && static_cast<int>(traj.step_sizes.size()) != N) {
    throw InputError(who + ": the trajectory's step sizes do not match its steps");
  }
  if (sim.settings().friction_iterations > 1) {
    throw InputError(who + ": friction is re-lagged within each step (friction iterations " +
                     std::to_string(sim.settings().friction_iterations) +
                     "), which only forward runs do: the derivatives take the lag at q_n (set 1)");
  }
  if (traj.integrator != sim.settings().integrator || traj.time_step != sim.settings().time_step) {
    throw InputError(who + ": the trajectory was not produced with the simulator's integrator and h");
  }
  if (static_cast<int>(seed.dq.size()) != N + 1) {
    std::ostringstream msg;
    msg << who << ": the seed has " << seed.dq.size() << " position entries, the trajectory " << N + 1;
    throw InputError(msg.str());
  }
  validate_material_field(materials, sim.rest_mesh().num_tets(), who + " materials");
}

const char* factor_storage_name(FactorStorage storage) {
  return storage == FactorStorage::kStore ? "store" : "rebuild";
}

FactorStorage parse_factor_storage(const std::string& name) {
  if (name == "store") return FactorStorage::kStore;
  if (name == "rebuild") return FactorStorage::kRebuild;
  throw InputError("factor storage '" + name + "' is not one of store, rebuild");
}

TrajectorySeed TrajectorySeed::empty(int num_steps) {
  TrajectorySeed s;
  s.dq.assign(num_steps + 1, Eigen::VectorXd());
  return s;
}

DifferentiableSimulator::DifferentiableSimulator(Simulator& sim, FactorStorage storage)
    : sim_(sim), storage_(storage) {}

Trajectory DifferentiableSimulator::forward(const MaterialField& materials,
                                            const Eigen::VectorXd& q0, const Eigen::VectorXd& v0,
                                            const Simulator::StepCallback& callback) {
  // Keep the last run's factor buffers for this run (same pattern: values copied in place).
  for (auto& f : factors_) {
    if (f) spare_.push_back(std::move(f));
  }
  factors_.clear();
  sim_.set_materials(materials, "materials");
  materials_ = materials;
  const bool store = storage_ == FactorStorage::kStore;
  if (!store) spare_.clear();
  // Newton's chord start (NewtonSettings::chord_first_step) finds the previous step's factor
  // here once it has been taken from Newton's solver.
  // sim_ may outlive this object: the hook is removed however the run ends.
  struct ChordHook {
    NewtonSolver& newton;
    ~ChordHook() { newton.set_chord_solve(nullptr); }
  } hook{sim_.newton()};
  if (store) {
    sim_.newton().set_chord_solve([this](const Eigen::VectorXd& b) {
      return factors_.empty() || !factors_.back() ? Eigen::VectorXd() : factors_.back()->solve(b);
    });
  }
  Trajectory trajectory = sim_.run(q0, v0, [&](int step, const Eigen::VectorXd& q, const StepStats& s) {
    if (store) {
      // Newton's last factor is of the Hessian at the returned iterate; only an exact one is H.
      const cholmod_factor_struct* L = s.exact_factor ? newton_factor(sim_) : nullptr;
      if (L == nullptr) {
        factors_.push_back(nullptr);
      } else if (!spare_.empty()) {
        // Refill an earlier run's factor: exchange value arrays with Newton's (no copy; Newton
        // refactorises into the old array next step), else copy the values in place.
        factors_.push_back(std::move(spare_.back()));
        spare_.pop_back();
        if (!factors_.back()->take_values_from(sim_.newton().linear_solver())) factors_.back()->assign(L);
      } else {
        factors_.push_back(CholmodFactor::copy_of(L));
      }
    }
    if (callback) callback(step, q, s);
  });
  spare_.clear();  // hold no more factors than this run's
  return trajectory;
}

AdjointResult DifferentiableSimulator::backward(const Trajectory& trajectory,
                                                const TrajectorySeed& seed) {
  if (materials_.size() != sim_.rest_mesh().num_tets()) {
    throw InputError("adjoint: backward() without a forward() run");
  }
  return run_adjoint(sim_, materials_, trajectory, seed, factors_, factorizer_);
}

std::size_t DifferentiableSimulator::stored_factor_bytes() const {
  std::size_t b = 0;
  for (const auto& f : factors_) {
    if (f) b += f->bytes();
  }
  return b;
}

int DifferentiableSimulator::num_stored_factors() const {
  int n = 0;
  for (const auto& f : factors_) n += f != nullptr;
  return n;
}

AdjointResult adjoint_gradient(Simulator& sim, const MaterialField& materials,
                               const Trajectory& trajectory, const TrajectorySeed& seed) {
  HessianFactorizer factorizer;
  return run_adjoint(sim, materials, trajectory, seed, {}, factorizer);
}

}  // namespace rbaa
