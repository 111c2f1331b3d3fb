#include "rbaa/sim/trajectory.hpp"

namespace rbaa {

Eigen::VectorXd Trajectory::velocity(int k) const {
  if (integrator == Integrator::kBdf2) {
    // 3 q_k - 4 q_{k-1} + q_{k-2} in differences (rounding relative to the motion, not to |q|)
    return (3.0 * (position(k) - position(k - 1)) - (position(k - 1) - position(k - 2))) /
           (2.0 * time_step);
  }
  return (position(k) - position(k - 1)) / time_step;
}

}  // namespace rbaa
