#include "rbaa/opt/smoothed_gradient.hpp"

#include <utility>

#include "rbaa/error.hpp"

namespace rbaa {

void smooth_alpha_gradient(const DesignSpace& design, const GradientSmoother& smoother,
                           Eigen::VectorXd& gradient) {
  if (gradient.size() != design.size()) {
    throw InputError("smooth_alpha_gradient: gradient of size " + std::to_string(gradient.size()) +
                     " for a design space of size " + std::to_string(design.size()));
  }
  if (!design.optimises(DesignField::kAlpha)) return;
  const int o = design.offset(DesignField::kAlpha), n = design.num_interior();
  gradient.segment(o, n) = smoother.apply_interior(design.interior(), gradient.segment(o, n));
}

ValueAndGradient with_smoothed_alpha_gradient(ValueAndGradient f, const DesignSpace& design,
                                              const GradientSmoother& smoother) {
  return [f = std::move(f), &design, &smoother](const Eigen::VectorXd& x, Eigen::VectorXd* gradient) {
    const double value = f(x, gradient);
    if (gradient != nullptr) smooth_alpha_gradient(design, smoother, *gradient);
    return value;
  };
}

}  // namespace rbaa
