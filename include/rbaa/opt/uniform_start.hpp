#pragma once
// The best uniform start (issue 20 item 3, attack.start: best_uniform): before the loop, the
// attacked body A is simulated uniform at a handful of materials within the bounds, each scored by
// the attack's own objective, and the attack starts from the best one. The loop starts from that
// candidate perturbed (attack.seed's N(0, 0.1^2) in theta) and retracted onto the moments, and
// keeps its best iterate: it never ends below its first, perturbed design, which is not the
// candidate itself (README says the same).
//
// Candidates: Y and nu each at the low end, the middle and the high end of their ranges, the ends
// 1e-6 of the range inside (the tanh map reaches a bound only at infinity), 3 x 3 in all. Each
// candidate is the design's unperturbed initial material at that Y0, nu0 (rho alpha the reference
// density everywhere, so the moments are the reference's), mapped through theta as the loop maps
// it; every other body keeps its material.

#include <functional>
#include <string>
#include <vector>

#include "rbaa/opt/attack_problem.hpp"

namespace rbaa {

struct UniformCandidate {
  double Y = 0;  ///< Pa
  double nu = 0;
  double objective = 0;  ///< the objective's trajectory term (the moments are matched)
  double gap = 0;        ///< A's mass-weighted gap to the reference run (m)
};

struct UniformStart {
  std::vector<UniformCandidate> candidates;  ///< Y-major: Y lo, mid, hi, each with nu lo, mid, hi
  int chosen = -1;  ///< the lowest objective (the undirected one: the largest gap); first on ties
  const UniformCandidate& best() const { return candidates.at(chosen); }
};

/// The candidates' Y (or nu) values of a range [lo, hi]: lo + 1e-6 (hi - lo), the middle (as the
/// tanh map's), hi - 1e-6 (hi - lo).
std::vector<double> uniform_candidate_values(double lo, double hi);

/// The unperturbed initial material of A's design (#T_A) at Y0, nu0, through theta as the loop
/// sees it: design.to_material(design.initial_theta(false)) with those initial values.
MaterialField uniform_start_material(const AttackProblem& problem, double Y0, double nu0);

/// Simulates and scores every candidate. `on_candidate` (may be empty) hears of each as it is
/// done. Throws rbaa::SolverError naming the candidate if its simulation fails.
UniformStart find_best_uniform_start(
    const AttackProblem& problem,
    const std::function<void(const UniformCandidate&)>& on_candidate = {});

}  // namespace rbaa
