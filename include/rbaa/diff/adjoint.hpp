#pragma once
// The adjoint of the forward simulation (SPEC section 3): from a recorded trajectory and the
// objective's derivatives dC/dq_k, the material gradient dC/dY, dC/dnu, dC/drho, dC/dalpha per
// element, backwards in time through BDF-2 or BDF-1.
//
// Step n+1 solves G(q, q_hat, theta) = M (q - q_hat) + w (grad Psi - M g + kappa grad B) = 0 for
// q = q_{n+1}, q_hat = sum_j c_j q_{n-j} (bdf.hpp: w = (4/9) h^2 or h^2). By the implicit function
// theorem dq/dtheta = -H^-1 dG/dtheta and dq/dq_hat = H^-1 M, H = dG/dq the exact (unprojected)
// Hessian at the converged q_{n+1}. With qbar = dC/dq_{n+1} complete (later steps already done):
//
//   lambda          = H^-1 qbar
//   qbar_{n-j}     += c_j M lambda                                  (j = 0 .. order)
//   qbar_n, qbar_{n-1} += -lambda^T dG/dq_n, -lambda^T dG/dq_{n-1}    (lagged friction only)
//   dC/dtheta_e    += -lambda^T [ dM/dtheta_e (q - q_hat - w g) + w d(grad Psi)/dtheta_e ]
//
// The third line: lagged friction (contact.friction) takes each pair's normal force, tangent
// basis and closest-point weights from the lagged state and measures slip from x~ = a0 q_n +
// a1 q_{n-1} (sim/form.hpp), so G depends on those positions besides through q_hat
// (IncrementalPotential::add_history_adjoint). Held fixed within a step, as in the forward pass:
// the set of pairs and each pair's distance type (piecewise constant).
// Psi_e = alpha_e^3 V_e (mu_e Psi_mu + lambda_e Psi_lambda), so d(grad Psi)/dY is
// (dmu/dY) grad Psi_mu + (dlambda/dY) grad Psi_lambda (likewise nu) and d(grad Psi)/dalpha is
// 3/alpha times element e's gradient (the alpha^3 term the paper's supplement omits). M depends on
// m_e = rho_e alpha_e V_e only: dM/drho_e = alpha_e V_e dM/dm_e, dM/dalpha_e = rho_e V_e dM/dm_e.
// The ballistic history q_{-k} = q_0 - k h v_0 + (k h)^2 / 2 g depends on the initial state only;
// its adjoints end up in dC/dq_0 and dC/dv_0. Every vertex of a driven body starts with its
// drive's rigid past instead, q_{-k,i} = drive.position(q_{0,i}, -k h): there dC/dq_0 takes
// R(angle(-k h))^T of the history's adjoint and dC/dv_0 is 0 (src/diff/start_history.hpp). The
// adjoint assumes G = 0: Newton's tolerance must be tight (SPEC section 2).
//
// Driven (Dirichlet) vertices (Body::driven_vertices) follow a prescribed motion: their positions
// depend on nothing the adjoint differentiates, and G = 0 holds at the free dofs only. qbar is
// zeroed at the driven dofs before each solve, and H (the simulator's potential eliminates them:
// identity rows and columns) gives lambda = 0 there, so lambda is the free block's adjoint and the
// terms above sum over the free rows only. dC/dq_0 and dC/dv_0 are zero at driven dofs.
//
// Factor storage: kStore keeps a copy of Newton's last factor of every step during the forward
// run when Newton reports it as the exact Hessian at the returned iterate (StepStats::
// exact_factor); the backward step is then one solve. kRebuild (and kStore's non-exact steps)
// assemble and factorise the exact Hessian in the backward step, counted in AdjointStats.

#include <Eigen/Core>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "rbaa/diff/cholmod_factor.hpp"
#include "rbaa/material/design_space.hpp"
#include "rbaa/material/material_field.hpp"
#include "rbaa/sim/simulator.hpp"
#include "rbaa/sim/trajectory.hpp"

namespace rbaa {

enum class FactorStorage {
  kRebuild,  ///< keep positions only; the backward pass factorises every step's Hessian again
  kStore,    ///< keep Newton's exact factor of every step (memory ~ steps x one factor)
};

/// "store" / "rebuild"; parse throws rbaa::InputError naming the value.
const char* factor_storage_name(FactorStorage storage);
FactorStorage parse_factor_storage(const std::string& name);

/// The objective's derivatives with respect to the trajectory and the materials directly.
struct TrajectorySeed {
  /// dC/dq_k for k = 0 .. N (N + 1 entries; an empty entry means zero).
  std::vector<Eigen::VectorXd> dq;
  /// Explicit dC/d(material) (e.g. an observable weighted by vertex masses); empty: zero.
  MaterialGradient direct;

  /// N + 1 empty entries, no direct term.
  static TrajectorySeed empty(int num_steps);
};

struct AdjointStats {
  int steps = 0;                 ///< backward steps taken
  int solves = 0;                ///< steps with a nonzero adjoint (one solve pair each)
  int stored_factor_solves = 0;  ///< solves with a factor kept from the forward pass
  int rebuilt_factorizations = 0;  ///< exact Hessians assembled and factorised in the backward pass
  int ldlt_fallbacks = 0;        ///< of those, not positive definite (solved by LDL^T)
  double seconds = 0;            ///< wall time of the backward pass
  double factorization_seconds = 0;  ///< of which numeric factorisations (rebuild)
  double solve_seconds = 0;      ///< of which triangular solves
  double parameter_seconds = 0;  ///< of which the per-element parameter derivatives
};

struct AdjointResult {
  MaterialGradient materials;  ///< dC/dY, dC/dnu, dC/drho, dC/dalpha (#T each)
  Eigen::VectorXd dq0;         ///< dC/dq_0 (3 #V), through the steps and the ballistic history
  Eigen::VectorXd dv0;         ///< dC/dv_0 (3 #V), through the ballistic history
  AdjointStats stats;
};

/// Throws rbaa::InputError (messages starting with `who`) unless `trajectory` holds N + 1
/// positions and the 3 history ones, was produced with sim's integrator and h, `seed` has N + 1
/// position entries and `materials` fits the mesh: what the adjoint and the tangent both need.
void check_linearisation_inputs(const Simulator& sim, const MaterialField& materials,
                                const Trajectory& trajectory, const TrajectorySeed& seed,
                                const std::string& who);

/// A simulator whose runs can be differentiated: forward() records what backward() needs.
/// Not thread-safe; the simulator must not be used by others between forward and backward.
class DifferentiableSimulator {
 public:
  /// `sim` (not owned) must outlive this object.
  explicit DifferentiableSimulator(Simulator& sim, FactorStorage storage = FactorStorage::kStore);

  /// Sets the materials and runs the simulation from (q0, v0), keeping per-step factors when
  /// storing. Throws like Simulator::run.
  Trajectory forward(const MaterialField& materials, const Eigen::VectorXd& q0,
                     const Eigen::VectorXd& v0, const Simulator::StepCallback& callback = {});

  /// The adjoint of the last forward() run (`trajectory` is what it returned).
  AdjointResult backward(const Trajectory& trajectory, const TrajectorySeed& seed);

  FactorStorage storage() const { return storage_; }
  void set_storage(FactorStorage storage) { storage_ = storage; }
  /// Bytes held by the factors kept from the last forward run.
  std::size_t stored_factor_bytes() const;
  /// Steps of the last forward run whose factor was kept.
  int num_stored_factors() const;
  Simulator& simulator() { return sim_; }
  const MaterialField& materials() const { return materials_; }

 private:
  Simulator& sim_;
  FactorStorage storage_;
  MaterialField materials_;
  std::vector<std::unique_ptr<CholmodFactor>> factors_;  // per step, null: rebuild
  std::vector<std::unique_ptr<CholmodFactor>> spare_;    // the last run's, refilled in place
  HessianFactorizer factorizer_;
};

/// The adjoint of a trajectory that `sim` produced with `materials` (still set in `sim`),
/// rebuilding every step's factor.
AdjointResult adjoint_gradient(Simulator& sim, const MaterialField& materials,
                               const Trajectory& trajectory, const TrajectorySeed& seed);

}  // namespace rbaa
