#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <cstdio>

#include "rbaa/error.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/geometry/smoothing.hpp"
#include "rbaa/material/design_space.hpp"
#include "rbaa/mesh/grid_mesh.hpp"
#include "rbaa/opt/adam.hpp"
#include "rbaa/opt/moment_cost.hpp"
#include "rbaa/opt/smoothed_gradient.hpp"

namespace rbaa {
namespace {

TEST(Adam, BiasCorrectionMakesConstantGradientStepsExact) {
  // With a constant gradient the bias-corrected moments equal g and g^2 at every step, so each
  // step moves by lr g / (|g| + eps); without the correction the first steps would be
  // (1 - beta1) / sqrt(1 - beta2) = 1.34 times longer.
  AdamOptions o;
  o.learning_rate = 0.05;
  Adam adam(o);
  Eigen::VectorXd x(3);
  x << 1.0, -2.0, 0.5;
  const Eigen::VectorXd x0 = x;
  Eigen::VectorXd g(3);
  g << 3.0, -0.25, 1e-3;
  for (int k = 1; k <= 5; ++k) {
    adam.step(x, g);
    for (int i = 0; i < 3; ++i) {
      const double expected = x0[i] - k * o.learning_rate * g[i] / (std::abs(g[i]) + o.epsilon);
      EXPECT_NEAR(x[i], expected, 1e-14) << "step " << k << " entry " << i;
    }
  }
  EXPECT_EQ(adam.state().steps, 5);
}

TEST(Adam, SecondStepFollowsTheFormula) {
  AdamOptions o;  // beta1 = 0.7, beta2 = 0.95
  Adam adam(o);
  Eigen::VectorXd x = Eigen::VectorXd::Constant(1, 0.0);
  adam.step(x, Eigen::VectorXd::Constant(1, 2.0));
  adam.step(x, Eigen::VectorXd::Constant(1, -1.0));
  // m2 = 0.7 * 0.6 - 0.3 = 0.12, v2 = 0.95 * 0.2 + 0.05 = 0.24; corrections 0.51 and 0.0975.
  const double step2 = 0.05 * (0.12 / 0.51) / (std::sqrt(0.24 / 0.0975) + 1e-8);
  EXPECT_NEAR(x[0], -0.05 * 2.0 / (2.0 + 1e-8) - step2, 1e-15);
  EXPECT_NEAR(adam.state().m[0], 0.12, 1e-15);
  EXPECT_NEAR(adam.state().v[0], 0.24, 1e-15);
}

double quadratic(const Eigen::VectorXd& x, Eigen::VectorXd* g) {
  // sum_i w_i (x_i - c_i)^2 + 0.1 (x_0 x_1) with very different scales per coordinate.
  Eigen::VectorXd w(4), c(4);
  w << 1.0, 100.0, 0.01, 5.0;
  c << 1.0, -2.0, 3.0, 0.5;
  if (g) {
    *g = 2 * w.cwiseProduct(x - c);
    (*g)[0] += 0.1 * x[1];
    (*g)[1] += 0.1 * x[0];
  }
  return w.dot((x - c).cwiseAbs2()) + 0.1 * x[0] * x[1];
}

TEST(Adam, LoopMinimisesAndResumesBitIdentically) {
  const Eigen::VectorXd start = Eigen::VectorXd::Zero(4);
  // Uninterrupted: 400 steps.
  Eigen::VectorXd x = start;
  Adam adam;
  const AdamSummary s = minimize_adam(quadratic, x, adam, 400);
  EXPECT_EQ(s.steps, 400);
  // The minimiser of the coupled quadratic, from its normal equations.
  Eigen::Matrix4d H = Eigen::Matrix4d::Zero();
  H.diagonal() << 2.0, 200.0, 0.02, 10.0;
  H(0, 1) = H(1, 0) = 0.1;
  Eigen::Vector4d b(2.0, -400.0, 0.06, 5.0);
  const Eigen::Vector4d x_star = H.ldlt().solve(b);
  std::printf("Adam on a badly scaled quadratic: |x - x*|_inf = %.2e after 400 steps\n",
              (x - x_star).cwiseAbs().maxCoeff());
  EXPECT_LT((x - x_star).cwiseAbs().maxCoeff(), 1e-2);

  // Interrupted at step 150 by the callback (a checkpoint), resumed in a fresh optimiser.
  Eigen::VectorXd saved_x;
  AdamState saved_state;
  Eigen::VectorXd y = start;
  Adam first;
  const AdamSummary s1 = minimize_adam(quadratic, y, first, 400, [&](const AdamIteration& it) {
    saved_x = it.x;
    saved_state = it.adam.state();
    return it.iteration < 150;
  });
  EXPECT_TRUE(s1.stopped_by_callback);
  EXPECT_EQ(s1.steps, 150);
  Adam second;
  second.restore(saved_state);
  Eigen::VectorXd z = saved_x;
  minimize_adam(quadratic, z, second, 250);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(z[i], x[i]) << "entry " << i;  // bit-identical
  EXPECT_EQ(second.state().m, adam.state().m);
  EXPECT_EQ(second.state().v, adam.state().v);
  EXPECT_EQ(second.state().steps, 400);
}

TEST(Adam, RejectsBadInput) {
  AdamOptions o;
  o.beta2 = 1.0;
  EXPECT_THROW(Adam{o}, InputError);
  // The ranges are [0, 1) for both betas: 0 (no averaging) is allowed, 1 and negatives are not.
  AdamOptions zero;
  zero.beta1 = 0.0;
  zero.beta2 = 0.0;
  EXPECT_NO_THROW(Adam{zero});
  AdamOptions one;
  one.beta1 = 1.0;
  EXPECT_THROW(Adam{one}, InputError);
  AdamOptions negative;
  negative.beta1 = -0.1;
  EXPECT_THROW(Adam{negative}, InputError);
  AdamOptions no_rate;
  no_rate.learning_rate = 0.0;
  EXPECT_THROW(Adam{no_rate}, InputError);
  Adam adam;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(2);
  EXPECT_THROW(adam.step(x, Eigen::VectorXd::Zero(3)), InputError);
  EXPECT_THROW(adam.step(x, Eigen::VectorXd::Constant(2, std::nan(""))), SolverError);
  const ValueAndGradient nan_value = [](const Eigen::VectorXd& v, Eigen::VectorXd* g) {
    if (g) *g = Eigen::VectorXd::Zero(v.size());
    return std::nan("");
  };
  EXPECT_THROW(minimize_adam(nan_value, x, adam, 3), SolverError);
}

TEST(Adam, MomentPenaltyWithSmoothedAlphaGradientRestoresTheMoments) {
  // The moment term alone, from a strongly perturbed start: Adam on beta |r|^2 (with the alpha
  // block smoothed, as in the attack) brings the normalised residuals back down.
  const TetMesh mesh = box_tet_mesh({-0.2, -0.1, 0.0}, {0.3, 0.2, 0.4}, 4, 4, 5);
  const Moments reference = compute_moments(mesh, 2500.0);
  DesignSpaceOptions o;
  o.perturbation = 0.3;
  const DesignSpace design(mesh, o);
  const MomentCostFunction cost(mesh, design, reference);
  const GradientSmoother smoother(mesh, 1.0);
  const double beta = 1e4;
  const ValueAndGradient moment_term = [&](const Eigen::VectorXd& x, Eigen::VectorXd* g) {
    return cost.penalty(x, beta, g);
  };
  const ValueAndGradient f =
      with_smoothed_alpha_gradient(sum_objectives({moment_term}), design, smoother);

  Eigen::VectorXd theta = design.initial_theta();
  const double r0 = cost.residuals(theta).cwiseAbs().maxCoeff();
  AdamOptions ao;
  ao.learning_rate = 0.01;
  Adam adam(ao);
  minimize_adam(f, theta, adam, 200);
  const double r1 = cost.residuals(theta).cwiseAbs().maxCoeff();
  std::printf("moment term alone: max normalised residual %.3e -> %.3e in 200 Adam steps\n", r0, r1);
  EXPECT_GT(r0, 1e-2);
  EXPECT_LT(r1, 1e-3);

  // The smoothing touched the alpha block only.
  Eigen::VectorXd raw, smoothed;
  moment_term(theta, &raw);
  f(theta, &smoothed);
  const int a = design.offset(DesignField::kAlpha);
  EXPECT_EQ(raw.head(a), smoothed.head(a));
  EXPECT_GT((raw.tail(design.num_interior()) - smoothed.tail(design.num_interior())).norm(),
            1e-6 * raw.tail(design.num_interior()).norm());
}

}  // namespace
}  // namespace rbaa
