#include "rbaa/sim/bdf.hpp"

namespace rbaa {

BdfIntegrator::BdfIntegrator(Integrator kind, double time_step) : kind_(kind), h_(time_step) {
  if (kind == Integrator::kBdf2) {
    coefficients_ = {24.0 / 9.0, -22.0 / 9.0, 8.0 / 9.0, -1.0 / 9.0};
    weight_ = 4.0 / 9.0 * h_ * h_;
  } else {
    coefficients_ = {2.0, -1.0};
    weight_ = h_ * h_;
  }
}

void BdfIntegrator::initialize(const Eigen::VectorXd& q0, const Eigen::VectorXd& v0,
                               const Eigen::Vector3d& g) {
  history_.clear();
  const int n = static_cast<int>(q0.size()) / 3;
  Eigen::VectorXd g_stacked(q0.size());
  for (int v = 0; v < n; ++v) g_stacked.segment<3>(3 * v) = g;
  // Keep 4 positions whatever the scheme, so that the BDF-2 velocity is defined from step 0.
  for (int k = 0; k < 4; ++k) {
    const double t = k * h_;
    history_.push_back(q0 - t * v0 + 0.5 * t * t * g_stacked);
  }
}

Eigen::VectorXd BdfIntegrator::predictor() const {
  // Written in differences of consecutive positions, whose rounding scales with the motion per
  // step rather than with |q|: the coefficients 24/9, -22/9, ... are not exact in binary, and
  // their rounding would bias every step the same way (a momentum drift of ~1e-13 per step).
  const Eigen::VectorXd d1 = history_[0] - history_[1];
  if (kind_ == Integrator::kBdf2) {
    // q_hat - q_n = (15 (q_n - q_{n-1}) - 7 (q_{n-1} - q_{n-2}) + (q_{n-2} - q_{n-3})) / 9
    return history_[0] + (15.0 * d1 - 7.0 * (history_[1] - history_[2]) +
                          (history_[2] - history_[3])) / 9.0;
  }
  return history_[0] + d1;
}

void BdfIntegrator::push(const Eigen::VectorXd& q_next) {
  history_.push_front(q_next);
  history_.pop_back();
}

Eigen::VectorXd BdfIntegrator::velocity() const {
  if (kind_ == Integrator::kBdf2) {
    return (3.0 * (history_[0] - history_[1]) - (history_[1] - history_[2])) / (2.0 * h_);
  }
  return (history_[0] - history_[1]) / h_;
}

}  // namespace rbaa
