#pragma once
// Checks the adjoint gradient of a TrajectoryGradientFunction against central finite differences
// along random directions (SPEC section 3's bar: relative error <= 1e-5 per direction), in the
// design vector theta or directly in material space (Y, nu, rho, alpha of the design's fields).

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <vector>

#include "rbaa/diff/trajectory_gradient.hpp"

namespace rbaa {

struct GradientCheckOptions {
  int directions = 4;
  /// Central-difference step along a unit direction: in theta units, or in material space as a
  /// fraction of each field's range (x_max - x_min). See gradient_check.cpp for the choice.
  double step = 1e-4;
  /// Also evaluate at step / 2 and combine both by Richardson extrapolation (error O(step^4)).
  bool richardson = true;
  std::uint64_t seed = 1;
  /// false: directions in theta; true: in material space (the design's fields, every element;
  /// alpha only on interior elements).
  bool material_space = false;
};

struct DirectionCheck {
  double adjoint = 0;            ///< g . d
  double finite_difference = 0;  ///< (C(x + s d) - C(x - s d)) / (2 s), extrapolated
  double relative_error = 0;     ///< |fd - adjoint| / max(|fd|, |adjoint|)
};

struct GradientCheckResult {
  double value = 0;            ///< C at the base point
  double gradient_norm = 0;    ///< |dC/dtheta| or |dC/d(material)| (scaled by the ranges)
  std::vector<DirectionCheck> directions;
  double max_relative_error = 0;
  int active_contact_steps = 0;  ///< steps of the base run with contact pairs active
};

/// Runs the check at theta; `on_direction` (optional) is called after every direction.
GradientCheckResult check_gradient(TrajectoryGradientFunction& f, const Eigen::VectorXd& theta,
                                   const GradientCheckOptions& options,
                                   const std::function<void(int, const DirectionCheck&)>& on_direction = {});

}  // namespace rbaa
