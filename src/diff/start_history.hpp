// How the start-up history depends on the initial state (Simulator::reset), for the adjoint and
// the tangent: q_{-k} = q_0 - k h v_0 + (k h)^2 / 2 g for a free body's vertex, and for every
// vertex of a driven body the drive's own past, q_{-k,i} = drive.position(q_{0,i}, -k h), whose
// derivative in q_{0,i} is the drive's rotation R(angle(-k h)) and which does not depend on v_0
// (reset gives those vertices the drive's velocity). Driven vertices are no initial-state
// unknowns at all: the callers zero their dofs.

#pragma once

#include <Eigen/Core>

#include "rbaa/sim/simulator.hpp"

namespace rbaa::diff_detail {

/// Calls f(i, R) for each vertex i of a driven body, R = d q_{-k,i} / d q_{0,i}.
template <class F>
void for_driven_body_vertices(const Simulator& sim, int k, F&& f) {
  const double t = -k * sim.settings().time_step;
  for (const Body& b : sim.settings().bodies) {
    if (!b.is_driven()) continue;
    const Eigen::Matrix3d R = b.drive.rotation(t);
    for (int i = b.vertex_begin; i < b.vertex_end; ++i) f(i, R);
  }
}

/// d q_{-k} along the initial-state direction (dq0, dv0).
inline Eigen::VectorXd start_history_tangent(const Simulator& sim, int k, const Eigen::VectorXd& dq0,
                                             const Eigen::VectorXd& dv0) {
  Eigen::VectorXd d = dq0 - (k * sim.settings().time_step) * dv0;
  for_driven_body_vertices(sim, k, [&](int i, const Eigen::Matrix3d& R) {
    d.segment<3>(3 * i) = R * dq0.segment<3>(3 * i);
  });
  return d;
}

/// Adds the adjoint `adj` of q_{-k} into dq0 and dv0 (the transpose of start_history_tangent).
inline void add_start_history_adjoint(const Simulator& sim, int k, const Eigen::VectorXd& adj,
                                      Eigen::VectorXd& dq0, Eigen::VectorXd& dv0) {
  Eigen::VectorXd to_q0 = adj, to_v0 = -(k * sim.settings().time_step) * adj;
  for_driven_body_vertices(sim, k, [&](int i, const Eigen::Matrix3d& R) {
    to_q0.segment<3>(3 * i) = R.transpose() * adj.segment<3>(3 * i);
    to_v0.segment<3>(3 * i).setZero();
  });
  dq0 += to_q0;
  dv0 += to_v0;
}

}  // namespace rbaa::diff_detail
