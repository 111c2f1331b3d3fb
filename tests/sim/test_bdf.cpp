// The BDF integrator's history and velocity: from the ballistic start (a quadratic in time) BDF-2's
// velocity is exact and BDF-1's lags by h g / 2.

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

}  // namespace
}  // namespace rbaa
