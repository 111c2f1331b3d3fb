#pragma once
// Forward-mode (tangent-linear) sensitivities of a recorded trajectory: the directional
// derivative of an objective along a change of the materials and of the initial state, propagated
// step by step through the converged linearisation. With the adjoint's notation (adjoint.hpp),
// step n+1 solves G(q_{n+1}, q_hat, theta) = 0 and its tangent is
//
//   H dq_{n+1} = M dq_hat - [ dM(dm) (q_{n+1} - q_hat - w g) + w dgrad Psi(dtheta) ],
//   dq_hat = sum_j c_j dq_{n-j},   dq_{-j} = dq_0 - j h dv_0 (the ballistic history),
//
// at the free dofs; driven (Dirichlet) dofs are prescribed, so dq_k = 0 there for every k (a
// direction's q0 and v0 entries there are ignored) and H has identity rows there (adjoint.hpp);
// with H the exact Hessian at the converged q_{n+1}, factorised afresh here (never Newton's or the
// adjoint's stored factor). Then dC = sum_k dC/dq_k . dq_k + dC/d(material)_direct . dtheta.
// Because it uses the same linearisation as the adjoint, the two agree to round-off
// (lambda^T b = qbar^T H^-1 b): the "dot-product test" that proves the adjoint is the exact
// transpose of the forward linearisation, on stiff scenes where finite differences drown in
// Newton's tolerance. It does not prove the linearisation itself (finite differences do that on
// soft scenes).

#include <Eigen/Core>

#include <vector>

#include "rbaa/diff/adjoint.hpp"
#include "rbaa/material/design_space.hpp"
#include "rbaa/material/material_field.hpp"
#include "rbaa/sim/simulator.hpp"
#include "rbaa/sim/trajectory.hpp"

namespace rbaa {

/// A direction in the simulation's inputs. Material entries are per element (#T, an empty vector
/// means no change of that field); q0 and v0 are 3 #V (empty: no change).
struct TangentDirection {
  MaterialGradient materials;  ///< dY, dnu, drho, dalpha
  Eigen::VectorXd q0, v0;
};

struct TangentStats {
  int steps = 0;
  int factorizations = 0;   ///< exact Hessians assembled and factorised
  int ldlt_fallbacks = 0;   ///< of those, not positive definite
  double seconds = 0;
};

struct TangentResult {
  std::vector<double> derivatives;        ///< dC along each direction
  /// sum_k |dC/dq_k| |dq_k| + |direct| |dtheta| per direction: the Cauchy-Schwarz bound of the
  /// derivative's terms, the scale its round-off is relative to.
  std::vector<double> bounds;
  std::vector<Eigen::VectorXd> final_dq;  ///< dq_N of each direction (3 #V)
  TangentStats stats;
};

/// dC along each direction for a trajectory that `sim` produced with `materials` (still set in
/// `sim`) and the objective's derivatives `seed` (adjoint.hpp's TrajectorySeed). One exact
/// factorisation per step serves all directions. Throws rbaa::InputError on mismatched sizes.
TangentResult tangent_linear(Simulator& sim, const MaterialField& materials,
                             const Trajectory& trajectory, const TrajectorySeed& seed,
                             const std::vector<TangentDirection>& directions);

}  // namespace rbaa
