#pragma once
// Adam (Kingma and Ba) on the design vector, with the paper's beta1 = 0.7, beta2 = 0.95 as
// defaults (SPEC section 4), and a minimisation loop that takes any "value and gradient" callback,
// so the trajectory term (forward simulation + adjoint) plugs in beside the moment term.
//
// Step t (1-based): m = beta1 m + (1 - beta1) g, v = beta2 v + (1 - beta2) g o g,
//   x -= lr (m / (1 - beta1^t)) / (sqrt(v / (1 - beta2^t)) + epsilon).

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <vector>

namespace rbaa {

struct AdamOptions {
  double learning_rate = 0.05;  ///< in theta units
  double beta1 = 0.7;
  double beta2 = 0.95;
  double epsilon = 1e-8;
};

/// Everything that determines Adam's next step besides the gradient: save it with x in a
/// checkpoint and restore it to continue bit-identically.
struct AdamState {
  Eigen::VectorXd m;       ///< first-moment estimate (size of x; empty before the first step)
  Eigen::VectorXd v;       ///< second-moment estimate
  std::int64_t steps = 0;  ///< steps taken (t of the last step)
};

class Adam {
 public:
  /// Throws rbaa::InputError unless learning_rate > 0, beta1, beta2 in [0, 1), epsilon >= 0.
  explicit Adam(const AdamOptions& options = {});

  /// One update of x (in place) with the gradient at x. Throws rbaa::InputError when the gradient's
  /// size differs from earlier steps, rbaa::SolverError on a non-finite gradient.
  void step(Eigen::VectorXd& x, const Eigen::VectorXd& gradient);

  const AdamOptions& options() const { return options_; }
  const AdamState& state() const { return state_; }
  /// Replaces the state (e.g. from a checkpoint); m and v must have equal sizes.
  void restore(const AdamState& state);
  /// Back to no steps taken.
  void reset() { state_ = AdamState{}; }

 private:
  AdamOptions options_;
  AdamState state_;
};

/// An objective: returns C(x) and, when gradient is not null, writes dC/dx (size of x).
using ValueAndGradient = std::function<double(const Eigen::VectorXd& x, Eigen::VectorXd* gradient)>;

/// The sum of several objectives (evaluated in the given order).
ValueAndGradient sum_objectives(std::vector<ValueAndGradient> terms);

/// What the loop reports after every step (progress, checkpoints): `value` and `gradient` were
/// evaluated at the iterate before the step, `x` and `adam` are after it, so saving x and
/// adam.state() here resumes exactly.
struct AdamIteration {
  std::int64_t iteration;          ///< steps taken so far (adam.state().steps)
  double value;                    ///< C before the step
  const Eigen::VectorXd& gradient; ///< dC/dx before the step
  const Eigen::VectorXd& x;        ///< iterate after the step
  const Adam& adam;
};

/// Return false to stop the loop.
using AdamCallback = std::function<bool(const AdamIteration&)>;

struct AdamSummary {
  int steps = 0;             ///< steps taken by this call
  double last_value = 0.0;   ///< C at the last evaluated iterate (before the last step)
  bool stopped_by_callback = false;
};

/// Takes `steps` Adam steps on f from x (in place), continuing from adam's state. Throws
/// rbaa::SolverError naming the iteration when f returns a non-finite value or gradient.
AdamSummary minimize_adam(const ValueAndGradient& f, Eigen::VectorXd& x, Adam& adam, int steps,
                          const AdamCallback& callback = {});

}  // namespace rbaa
