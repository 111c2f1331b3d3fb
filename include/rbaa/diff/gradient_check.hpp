#pragma once
// Checks the adjoint gradient of a TrajectoryGradientFunction along random directions, in the
// design vector theta or directly in material space (Y, nu, rho, alpha of the design's fields),
// against
// * central finite differences (SPEC section 3's bar: relative error <= 1e-5 per direction), which
//   prove the linearisation but drown in Newton's tolerance on stiff scenes, where Y and nu move
//   the objective by ~1e-7 relative; a failing direction is re-measured at 4x the step and called
//   noise-dominated when the two estimates disagree with each other by as much as with the
//   adjoint (a wrong adjoint leaves them agreeing with each other);
// * tangent-linear sensitivities (tangent_linear.hpp) through the same converged linearisation,
//   which must agree with the adjoint to round-off on any scene, however stiff. The error is
//   normwise, relative to the Cauchy-Schwarz bounds of the derivative: along a direction nearly
//   orthogonal to g the derivative is a sum of cancelling terms whose round-off is relative to
//   their size, not to the sum.

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "rbaa/diff/trajectory_gradient.hpp"

namespace rbaa {

enum class GradientCheckMethod { kFiniteDifference, kTangent, kBoth };

/// "fd", "tangent", "both"; parse throws rbaa::InputError naming the value.
const char* gradient_check_method_name(GradientCheckMethod method);
GradientCheckMethod parse_gradient_check_method(const std::string& name);

struct GradientCheckOptions {
  GradientCheckMethod method = GradientCheckMethod::kFiniteDifference;
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
  /// Directions move only elements [element_begin, element_end) (-1: to the last), e.g. one
  /// body's of a stacked mesh; the default moves every element.
  int element_begin = 0;
  int element_end = -1;
  /// Finite-difference errors above this are re-measured at 4x the step (noise test).
  double fd_tolerance = 1e-5;
  /// Tangent-vs-adjoint normwise error that passes (or 4x the tangent's measured round-off, if
  /// larger: on long stiff runs the forward recurrence's own round-off reaches ~1e-10).
  double tangent_tolerance = 1e-10;
  /// An error within this many times the tangent's own measured round-off (the largest of the
  /// run's directions: each measures the same recurrence once) passes (0: off).
  double tangent_noise_factor = 4.0;
};

struct DirectionCheck {
  double adjoint = 0;            ///< g . d
  double finite_difference = 0;  ///< (C(x + s d) - C(x - s d)) / (2 s), extrapolated
  double relative_error = 0;     ///< |fd - adjoint| / max(|fd|, |adjoint|)
  /// When the error is above `fd_tolerance`, the estimate is repeated at 4x the step; the two
  /// estimates' difference is the finite differences' error bar, and the error is called
  /// noise-dominated (Newton's tolerance, not a wrong gradient) when the adjoint lies within twice
  /// that bar of the estimate at the step.
  double coarse_finite_difference = 0;
  double coarse_relative_error = 0;  ///< |fd(4 step) - adjoint| / max(...)
  bool noise_dominated = false;
  double tangent = 0;                 ///< dC along d from tangent-linear sensitivities
  /// |tangent - adjoint| / max(|g| |d|, sum_k |dC/dq_k| |dq_k|): the dot-product test's
  /// normwise error (the two Cauchy-Schwarz bounds of the derivative), the pass criterion
  double tangent_relative_error = 0;
  double tangent_pointwise_error = 0;  ///< |tangent - adjoint| / max(|tangent|, |adjoint|)
  /// |T(d) - T(s) - T(d - s)| for a random s, normwise like tangent_relative_error: the tangent's
  /// own round-off (it is linear in d)
  double tangent_noise = 0;
};

struct GradientCheckResult {
  double value = 0;            ///< C at the base point
  double gradient_norm = 0;    ///< |dC/dtheta| or |dC/d(material)| (scaled by the ranges)
  std::vector<DirectionCheck> directions;
  double max_relative_error = 0;          ///< finite differences, over all directions
  double max_tangent_relative_error = 0;  ///< tangent-linear, over all directions
  double max_tangent_noise = 0;           ///< the tangent's own round-off, over all directions
  /// Every direction's tangent error within max(tangent_tolerance, tangent_noise_factor x
  /// max_tangent_noise)
  bool tangent_pass = false;
  bool fd_noise_dominated = false;        ///< every direction above fd_tolerance was noise
  int active_contact_steps = 0;  ///< steps of the base run with contact pairs active
  double tangent_seconds = 0;    ///< wall time of the tangent pass (all directions)
};

/// Runs the check at theta; `on_direction` (optional) is called after every direction.
GradientCheckResult check_gradient(TrajectoryGradientFunction& f, const Eigen::VectorXd& theta,
                                   const GradientCheckOptions& options,
                                   const std::function<void(int, const DirectionCheck&)>& on_direction = {});

}  // namespace rbaa
