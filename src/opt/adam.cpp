#include "rbaa/opt/adam.hpp"

#include <cmath>
#include <sstream>
#include <utility>

#include "rbaa/error.hpp"

namespace rbaa {

Adam::Adam(const AdamOptions& options) : options_(options) {
  const AdamOptions& o = options_;
  if (!(o.learning_rate > 0.0 && std::isfinite(o.learning_rate)) || !(o.beta1 >= 0.0 && o.beta1 < 1.0) ||
      !(o.beta2 >= 0.0 && o.beta2 < 1.0) || !(o.epsilon >= 0.0 && std::isfinite(o.epsilon))) {
    std::ostringstream msg;
    msg << "Adam options out of range: learning_rate = " << o.learning_rate
        << " (> 0), beta1 = " << o.beta1 << ", beta2 = " << o.beta2
        << " (in [0, 1)), epsilon = " << o.epsilon << " (>= 0)";
    throw InputError(msg.str());
  }
}

void Adam::step(Eigen::VectorXd& x, const Eigen::VectorXd& gradient) {
  if (gradient.size() != x.size() || (state_.steps > 0 && state_.m.size() != x.size())) {
    std::ostringstream msg;
    msg << "Adam: gradient of size " << gradient.size() << " for x of size " << x.size()
        << (state_.steps > 0 ? " after steps of size " + std::to_string(state_.m.size()) : "");
    throw InputError(msg.str());
  }
  if (!gradient.allFinite()) {
    throw SolverError("Adam: non-finite gradient at step " + std::to_string(state_.steps + 1));
  }
  if (state_.steps == 0) {
    state_.m = Eigen::VectorXd::Zero(x.size());
    state_.v = Eigen::VectorXd::Zero(x.size());
  }
  const AdamOptions& o = options_;
  ++state_.steps;
  const double t = static_cast<double>(state_.steps);
  const double c1 = 1.0 - std::pow(o.beta1, t);
  const double c2 = 1.0 - std::pow(o.beta2, t);
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const double g = gradient[i];
    state_.m[i] = o.beta1 * state_.m[i] + (1.0 - o.beta1) * g;
    state_.v[i] = o.beta2 * state_.v[i] + (1.0 - o.beta2) * g * g;
    x[i] -= o.learning_rate * (state_.m[i] / c1) / (std::sqrt(state_.v[i] / c2) + o.epsilon);
  }
}

void Adam::restore(const AdamState& state) {
  if (state.steps < 0 || state.m.size() != state.v.size() ||
      (state.steps > 0 && state.m.size() == 0)) {
    throw InputError("Adam: inconsistent saved state (negative step count or moment sizes differ)");
  }
  state_ = state;
}

ValueAndGradient sum_objectives(std::vector<ValueAndGradient> terms) {
  return [terms = std::move(terms)](const Eigen::VectorXd& x, Eigen::VectorXd* gradient) {
    double value = 0.0;
    if (gradient != nullptr) *gradient = Eigen::VectorXd::Zero(x.size());
    Eigen::VectorXd g;
    for (const ValueAndGradient& term : terms) {
      value += term(x, gradient != nullptr ? &g : nullptr);
      if (gradient != nullptr) *gradient += g;
    }
    return value;
  };
}

AdamSummary minimize_adam(const ValueAndGradient& f, Eigen::VectorXd& x, Adam& adam, int steps,
                          const AdamCallback& callback) {
  AdamSummary summary;
  Eigen::VectorXd gradient;
  for (int k = 0; k < steps; ++k) {
    const double value = f(x, &gradient);
    const std::int64_t iteration = adam.state().steps + 1;
    if (!std::isfinite(value) || gradient.size() != x.size() || !gradient.allFinite()) {
      std::ostringstream msg;
      msg << "Adam iteration " << iteration << ": the objective returned "
          << (std::isfinite(value) ? "a non-finite or wrongly sized gradient"
                                   : "a non-finite value");
      throw SolverError(msg.str());
    }
    adam.step(x, gradient);
    ++summary.steps;
    summary.last_value = value;
    if (callback && !callback(AdamIteration{iteration, value, gradient, x, adam})) {
      summary.stopped_by_callback = true;
      break;
    }
  }
  return summary;
}

}  // namespace rbaa
