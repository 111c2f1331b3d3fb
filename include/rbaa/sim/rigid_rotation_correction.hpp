#pragma once
// A Newton step of a near-rigid body moves its vertices along the tangents of its rotation, which
// stretches the body by theta^2 / 2 for a rotation theta; at Y = 1e13 Pa that stretch costs more
// than the step gains, and Newton creeps through a rotating contact step in tiny increments.
// Splitting the step into its best-fit rigid motion (translation t, infinitesimal rotation w,
// mass-weighted) and the rest, and applying the rotation as the finite rotation exp([w]x), removes
// the spurious stretch:
//
//   dq_i' = t + (exp([w]x) - I) r_i + (dq_i - t - w x r_i),   r_i = x_i - c.
//
// dq' = dq + O(|w|^2 |r|), so it stays a descent direction for the small rotations of one step
// (the Newton solver checks and falls back to dq otherwise).

#include <Eigen/Core>

namespace rbaa {

/// The corrected step dq' for positions x (3 #V), step dq and vertex masses (#V).
Eigen::VectorXd rigid_rotation_correction(const Eigen::VectorXd& x, const Eigen::VectorXd& dq,
                                          const Eigen::VectorXd& vertex_masses);

}  // namespace rbaa
