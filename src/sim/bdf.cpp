#include "rbaa/sim/bdf.hpp"

#include <cassert>

namespace rbaa {

BdfStepRule bdf_step_rule(Integrator kind, double h, double h_previous) {
  if (kind == Integrator::kBdf1) return {1.0, 0.0, h};
  if (h == h_previous) return {4.0 / 3.0, -1.0 / 3.0, 2.0 * h / 3.0};
  const double r = h / h_previous;
  const double d = 1.0 + 2.0 * r;
  return {(1.0 + r) * (1.0 + r) / d, -r * r / d, h * (1.0 + r) / d};
}

BdfPredictor bdf_predictor(Integrator kind, const BdfStepRule& now, const BdfStepRule& previous,
                           const BdfStepRule& before, double h) {
  BdfPredictor p;
  p.constant_step = now == previous && previous == before;
  if (p.constant_step) {
    if (kind == Integrator::kBdf2) {
      p.c = {24.0 / 9.0, -22.0 / 9.0, 8.0 / 9.0, -1.0 / 9.0};
      p.weight = 4.0 / 9.0 * h * h;
    } else {
      p.c = {2.0, -1.0};
      p.weight = h * h;
    }
    return p;
  }
  p.weight = now.b * now.b;
  if (kind == Integrator::kBdf1) {
    // q_hat = q_n + b v_n, v_n = (q_n - q_{n-1}) / b'.
    const double s = now.b / previous.b;
    p.c = {1.0 + s, -s};
    return p;
  }
  // q_hat = a0 q_n + a1 q_{n-1} + b (a0 v_n + a1 v_{n-1}), with
  // v_n = (q_n - a0' q_{n-1} - a1' q_{n-2}) / b' and v_{n-1} = (q_{n-1} - a0'' q_{n-2} - a1'' q_{n-3}) / b''.
  const double s1 = now.b * now.a0 / previous.b, s2 = now.b * now.a1 / before.b;
  p.c = {now.a0 + s1, now.a1 - s1 * previous.a0 + s2, -s1 * previous.a1 - s2 * before.a0,
         -s2 * before.a1};
  return p;
}

Eigen::VectorXd bdf_predict(Integrator kind, const BdfPredictor& p,
                            const std::vector<const Eigen::VectorXd*>& past) {
  // Written in differences of consecutive positions, whose rounding scales with the motion per
  // step rather than with |q|: the coefficients 24/9, -22/9, ... are not exact in binary, and
  // their rounding would bias every step the same way (a momentum drift of ~1e-13 per step).
  const Eigen::VectorXd& q0 = *past[0];
  const Eigen::VectorXd d1 = q0 - *past[1];
  if (kind == Integrator::kBdf1) {
    if (p.constant_step) return q0 + d1;
    return q0 + (-p.c[1]) * d1;
  }
  if (p.constant_step) {
    // q_hat - q_n = (15 (q_n - q_{n-1}) - 7 (q_{n-1} - q_{n-2}) + (q_{n-2} - q_{n-3})) / 9
    return q0 + (15.0 * d1 - 7.0 * (*past[1] - *past[2]) + (*past[2] - *past[3])) / 9.0;
  }
  // q_hat - q_n = e1 d1 + e2 d2 + e3 d3 with d_j = q_{n-j+1} - q_{n-j} (sum c_j = 1).
  const double e1 = -(p.c[1] + p.c[2] + p.c[3]), e2 = -(p.c[2] + p.c[3]), e3 = -p.c[3];
  return q0 + e1 * d1 + e2 * (*past[1] - *past[2]) + e3 * (*past[2] - *past[3]);
}

Eigen::VectorXd bdf_velocity(Integrator kind, const BdfStepRule& rule, double h,
                             const Eigen::VectorXd& q_n, const Eigen::VectorXd& q_n1,
                             const Eigen::VectorXd& q_n2) {
  if (kind == Integrator::kBdf1) return (q_n - q_n1) / rule.b;  // b = h
  if (rule == bdf_step_rule(kind, h, h)) {
    // 3 q_n - 4 q_{n-1} + q_{n-2} in differences (rounding relative to the motion, not to |q|)
    return (3.0 * (q_n - q_n1) - (q_n1 - q_n2)) / (2.0 * h);
  }
  // q_n - a0 q_{n-1} - a1 q_{n-2} = (q_n - q_{n-1}) + a1 (q_{n-1} - q_{n-2}) since a0 + a1 = 1.
  return ((q_n - q_n1) + rule.a1 * (q_n1 - q_n2)) / rule.b;
}

BdfIntegrator::BdfIntegrator(Integrator kind, double time_step)
    : kind_(kind), h_(time_step), next_h_(time_step) {
  const BdfStepRule rule = bdf_step_rule(kind_, h_, h_);
  rules_ = {rule, rule};
  sizes_ = {h_, h_};
  set_next_step(h_);
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
  const BdfStepRule rule = bdf_step_rule(kind_, h_, h_);
  rules_ = {rule, rule};
  sizes_ = {h_, h_};
  set_next_step(h_);
}

void BdfIntegrator::set_next_step(double h) {
  next_h_ = h;
  next_rule_ = bdf_step_rule(kind_, h, sizes_[0]);
  predictor_ = bdf_predictor(kind_, next_rule_, rules_[0], rules_[1], h);
}

Eigen::VectorXd BdfIntegrator::predictor() const {
  return bdf_predict(kind_, predictor_, {&history_[0], &history_[1], &history_[2], &history_[3]});
}

void BdfIntegrator::push(const Eigen::VectorXd& q_next) {
  history_.push_front(q_next);
  history_.pop_back();
  rules_.push_front(next_rule_);
  rules_.pop_back();
  sizes_.push_front(next_h_);
  sizes_.pop_back();
  set_next_step(next_h_);
}

Eigen::VectorXd BdfIntegrator::velocity() const {
  return bdf_velocity(kind_, rules_[0], sizes_[0], history_[0], history_[1], history_[2]);
}

}  // namespace rbaa
