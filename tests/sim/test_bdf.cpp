// The BDF integrator's history and velocity: from the ballistic start (a quadratic in time) BDF-2's
// velocity is exact and BDF-1's lags by h g / 2; variable steps stay exact on a free fall.

#include <gtest/gtest.h>

#include "rbaa/sim/bdf.hpp"

namespace rbaa {
namespace {

TEST(Bdf, VelocityFromTheBallisticStart) {
  const double h = 0.01;
  const Eigen::Vector3d g(0.0, -3.0, -9.8);
  const Eigen::VectorXd q0 = (Eigen::VectorXd(6) << 0.1, 0.2, 0.3, -1.0, 2.0, 3.4).finished();
  const Eigen::VectorXd v0 = (Eigen::VectorXd(6) << 1.0, -2.0, 0.5, 0.0, 4.0, -1.5).finished();
  Eigen::VectorXd half_hg(6);
  half_hg << 0.5 * h * g, 0.5 * h * g;

  BdfIntegrator bdf2(Integrator::kBdf2, h), bdf1(Integrator::kBdf1, h);
  bdf2.initialize(q0, v0, g);
  bdf1.initialize(q0, v0, g);
  // (3 q_0 - 4 q_-1 + q_-2) / 2h is exact for a quadratic; (q_0 - q_-1) / h is the mean velocity
  // over the last step, v_0 - h g / 2.
  EXPECT_LE((bdf2.velocity() - v0).norm(), 1e-12 * v0.norm());
  EXPECT_LE((bdf1.velocity() - (v0 - half_hg)).norm(), 1e-12 * v0.norm());
  // The ballistic past itself.
  for (int k = 1; k <= 2; ++k) {
    Eigen::VectorXd expected = q0 - k * h * v0;
    for (int i = 0; i < 2; ++i) expected.segment<3>(3 * i) += 0.5 * (k * h) * (k * h) * g;
    EXPECT_LE((bdf2.past(k) - expected).norm(), 1e-15 * q0.norm()) << k;
  }
}

// Variable steps: BDF-2 at any step ratio is exact on quadratics, so a free fall stepped with
// sizes h, h/8, h/8, h/4, h/2, h, h/2, ... (ratios 1/8 to 2) must stay on the parabola, with
// the velocity exact too. A wrong coefficient of the eliminated velocities breaks both.
TEST(Bdf, VariableStepsFollowAFreeFallExactly) {
  const double h = 0.01;
  const Eigen::Vector3d g(0.5, -3.0, -9.8);
  const Eigen::VectorXd q0 = (Eigen::VectorXd(3) << 0.1, 0.2, 0.3).finished();
  const Eigen::VectorXd v0 = (Eigen::VectorXd(3) << 1.0, -2.0, 0.5).finished();
  BdfIntegrator bdf(Integrator::kBdf2, h);
  bdf.initialize(q0, v0, g);
  const std::vector<double> sizes = {h, h / 8, h / 8, h / 4, h / 2, h, h / 2, h / 3, h / 3, h / 3, h};
  double t = 0;
  for (double dt : sizes) {
    bdf.set_next_step(dt);
    // The step's equation with no forces but gravity: q = q_hat + w g.
    const Eigen::VectorXd q = bdf.predictor() + bdf.potential_weight() * g;
    bdf.push(q);
    t += dt;
    const Eigen::VectorXd exact = q0 + t * v0 + 0.5 * t * t * g;
    EXPECT_LE((bdf.current() - exact).norm(), 1e-14) << "t " << t;
    EXPECT_LE((bdf.velocity() - (v0 + t * g)).norm(), 1e-11) << "t " << t;
  }
  // Back at a constant step the constant-step coefficients return, bit for bit.
  bdf.set_next_step(h);
  bdf.push(bdf.predictor() + bdf.potential_weight() * g);
  bdf.set_next_step(h);
  bdf.push(bdf.predictor() + bdf.potential_weight() * g);
  bdf.set_next_step(h);
  EXPECT_EQ(bdf.predictor_coefficients(), (std::vector<double>{24.0 / 9.0, -22.0 / 9.0, 8.0 / 9.0, -1.0 / 9.0}));
  EXPECT_EQ(bdf.potential_weight(), 4.0 / 9.0 * h * h);
}

// The coefficients sum to 1 at any ratio (a body at rest stays at rest) and the rule is the
// textbook one at ratio 2: a0 = 9/5, a1 = -4/5, b = 3/5 h.
TEST(Bdf, StepRuleAtRatioTwo) {
  const double h = 0.02;
  const BdfStepRule r = bdf_step_rule(Integrator::kBdf2, h, h / 2);
  EXPECT_NEAR(r.a0, 9.0 / 5.0, 1e-15);
  EXPECT_NEAR(r.a1, -4.0 / 5.0, 1e-15);
  EXPECT_NEAR(r.b, 3.0 / 5.0 * h, 1e-17);
  const BdfStepRule before = bdf_step_rule(Integrator::kBdf2, h / 2, h / 2);
  const BdfPredictor p = bdf_predictor(Integrator::kBdf2, r, before, before, h);
  EXPECT_FALSE(p.constant_step);
  double sum = 0;
  for (double c : p.c) sum += c;
  EXPECT_NEAR(sum, 1.0, 1e-14);
  EXPECT_DOUBLE_EQ(p.weight, r.b * r.b);
}

}  // namespace
}  // namespace rbaa
