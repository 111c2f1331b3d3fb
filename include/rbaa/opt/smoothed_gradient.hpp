#pragma once
// Applies the gradient smoothing of SPEC section 4 to the theta_alpha block of a design gradient
// (the other fields' blocks are left as they are).

#include <Eigen/Core>

#include "rbaa/geometry/smoothing.hpp"
#include "rbaa/material/design_space.hpp"
#include "rbaa/opt/adam.hpp"

namespace rbaa {

/// Replaces the alpha block g_a (#interior) of `gradient` (design.size()) by
/// gather(N K^-1 N^T scatter(g_a)); nothing happens when alpha is not optimised.
void smooth_alpha_gradient(const DesignSpace& design, const GradientSmoother& smoother,
                           Eigen::VectorXd& gradient);

/// f with its gradient's alpha block smoothed (the value is unchanged). `design` and `smoother`
/// are held by reference and must outlive the returned function.
ValueAndGradient with_smoothed_alpha_gradient(ValueAndGradient f, const DesignSpace& design,
                                              const GradientSmoother& smoother);

}  // namespace rbaa
