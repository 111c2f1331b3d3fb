#pragma once
// The occupancy penalty (issue 20 item 6, "keep the gap through rounding"): a term that drives
// interior alpha towards alpha_min or 1 during the Adam loop, as topology optimisation does, so
// that the continuous design does not lean on grey elements that rounding (post_process.hpp)
// throws away. Over the #interior designed elements i with volumes V_i,
//
//   P(alpha) = sum_i V_i p(alpha_i) / sum_i V_i,   p = 4 s (1 - s),
//   s(alpha) = (alpha - alpha_min) / (2 (t - alpha_min))   for alpha <= t,
//              1 - (1 - alpha) / (2 (1 - t))                for alpha >  t,
//
// with t the rounding threshold: p is 0 at alpha_min and at 1, peaks (1) at t, is C^1 there, and
// its gradient points towards the side that rounding keeps. With t = 0.5 and alpha_min -> 0 it is
// the usual 4 alpha (1 - alpha). P lies in [0, 1] and reads as the design's greyness.
//
// Rounding is followed by the connectivity repair (occupancy.hpp), which fills void paths until
// the occupied elements are one face-connected body with the boundary shell. The ball's
// 50-iteration design is nearly binary (2.1 % of its interior volume grey, P = 0.014) but its
// rounded occupancy falls into 84 face-connected components: it carves the void right under the
// shell, whose elements then hang together by edges and vertices only, hinges that cost no
// energy in the simulation. The repair fills 87 void elements to join the 83 pieces to the rest,
// and the gap falls from 0.138 m to 0.022 m. The repair term
//
//   R(alpha) = sum_{i in F} V_i (1 - alpha_i) / (1 - alpha_min) / sum_i V_i,
//
// with F the elements the repair would fill in the rounded design, fills them during the loop,
// so that the loop optimises the object the repair will make. F is fixed between roundings, so
// dR/dtheta is that of a sum over a fixed set (exact wherever no alpha crosses t). Measured on
// the ball (connectivity_weight 100), R stayed at 0.004 and the components grew to 115 all the
// same: the trajectory term carves faster than the term fills. `repair_in_loop` projects instead:
// after every step it sets F to alpha = (1 + t) / 2 and retracts onto the moments. On the ball
// the rounded, repaired, re-fitted object then keeps 93 % of the continuous gap (16 % without).
//
// The loop (attack_loop.hpp) adds w_k (weight P + connectivity_weight R) to the objective at
// iteration k, with
//
//   w_k = ramp(k / n) * max_{j <= k} |C_traj(theta_j)|,
//
// ramp 0 up to a fraction `ramp_start` of the n iterations, linear up to 1 at `ramp_end`, 1
// after (a continuation, as topology optimisation does). The scale: C_traj is normalised by
// m0_ref L^2 (SPEC section 4), but the attack grows it by orders of magnitude during a run (the
// ball's from -3e-6 to -2) and each scene to its own size (ball 2, ball_accurate 0.2), so a fixed
// weight would either swamp the trajectory's occupancy gradient early or vanish beside it late.
// Scaled by the largest trajectory term seen so far, `weight` = 1 means a fully grey design costs
// as much as the attack has gained; the running maximum (not the current value) keeps the scale
// of a directed objective, whose term shrinks towards its target, and is recomputed exactly from
// the progress rows on a resume.

#include <Eigen/Core>

#include "rbaa/material/design_space.hpp"
#include "rbaa/mesh/tet_mesh.hpp"

namespace rbaa {

struct OccupancyPenaltyOptions {
  double weight = 0;               ///< of the greyness P at full strength (0: off)
  double connectivity_weight = 0;  ///< of the repair term R at full strength (0: off)
  double ramp_start = 0.2;  ///< fraction of the iterations before which both weights act as 0
  double ramp_end = 0.8;    ///< fraction of the iterations from which both are at full strength
  /// After every Adam step, set the elements the repair would fill to alpha = (1 + t) / 2
  /// (fill_repair_paths), then retract onto the moments: the loop then only ever simulates
  /// designs whose rounding is one face-connected body. From the first step: the unpenalised
  /// ball has 24 components after 3 iterations.
  bool repair_in_loop = false;
};

/// ramp(k / n) for iteration k (0-based) of n: 0 while k / n <= ramp_start, 1 once
/// k / n >= ramp_end, linear between (a step at ramp_start when the two are equal).
double occupancy_penalty_ramp(const OccupancyPenaltyOptions& options, int iteration,
                              int iterations);

class OccupancyPenalty {
 public:
  /// `mesh` is the design's, one face-connected body (what post_process rounds and repairs);
  /// `design` is held by reference and must outlive the penalty; `threshold` is the rounding
  /// threshold t. Throws
  /// rbaa::InputError unless alpha_min < t < 1 and the sizes match. Without alpha in the design
  /// P = 0 and the gradient is zero.
  OccupancyPenalty(const TetMesh& mesh, const DesignSpace& design, double threshold,
                   const OccupancyPenaltyOptions& options = {});

  const OccupancyPenaltyOptions& options() const { return options_; }
  double threshold() const { return threshold_; }

  /// p(alpha) and dp/dalpha of one element (see the file's comment).
  double greyness(double alpha, double* derivative = nullptr) const;
  /// P(theta) and, if gradient is given, dP/dtheta (design.size(); zero outside the alpha block).
  double value(const Eigen::VectorXd& theta, Eigen::VectorXd* gradient = nullptr) const;
  /// R(theta) and, if gradient is given, dR/dtheta with the repair's set held (design.size()).
  /// `components`, if given, receives the number of face-connected components of the rounded
  /// occupancy (1: the repair has nothing to do).
  double repair_share(const Eigen::VectorXd& theta, Eigen::VectorXd* gradient = nullptr,
                      int* components = nullptr) const;
  /// The number of face-connected components of the rounded occupancy (held elements solid),
  /// without the repair's search: cheap, and it never throws on a mesh that is not itself
  /// face-connected.
  int components(const Eigen::VectorXd& theta) const;
  /// Sets theta of the elements the repair would fill in the rounded design to alpha =
  /// (1 + t) / 2, halfway between the threshold and solid; returns how many it set. Moments are
  /// the caller's (retract_onto_moments).
  int fill_repair_paths(Eigen::VectorXd& theta) const;
  /// The share of interior volume with 0.05 < alpha < 0.95.
  double grey_fraction(const Eigen::VectorXd& theta) const;

 private:
  const DesignSpace& design_;
  OccupancyPenaltyOptions options_;
  double threshold_ = 0.5;
  Eigen::VectorXd weights_;  ///< #interior: V_i / sum V (empty without alpha)
  TetMesh mesh_;
  Tets adjacency_;  ///< face neighbours (topology.hpp)
};

}  // namespace rbaa
