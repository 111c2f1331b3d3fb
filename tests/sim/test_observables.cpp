#include <gtest/gtest.h>

#include <cmath>

#include "rbaa/sim/observables.hpp"

namespace rbaa {
namespace {

// A bounce off z = 0 at steps 3-4 whose outgoing velocity settles like BDF-2's parasitic mode
// (deviation x 1/3 per step) towards 4 m/s, under gravity -10 m/s^2 at h = 0.01.
TEST(Observables, BounceReadsTheSettledOutgoingVelocity) {
  const double h = 0.01, g = -10;
  std::vector<std::vector<double>> distances;
  std::vector<Eigen::Vector3d> velocity;
  for (int k = 0; k < 14; ++k) {
    distances.push_back({(k == 3 || k == 4) ? 5e-4 : 0.1});
    double vz = -3.0;
    if (k >= 5) vz = 4.0 - 1.0 * std::pow(1.0 / 3.0, k - 5) + g * h * (k - 5);
    velocity.emplace_back(0, 0, vz);
  }
  const std::vector<Bounce> b = find_bounces(distances, velocity, {Plane{Eigen::Vector3d::UnitZ(), 0.0}}, 1e-3,
                                             Eigen::Vector3d(0, 0, g), h, 5);
  ASSERT_EQ(b.size(), 1u);
  EXPECT_TRUE(b[0].complete);
  // Read 5 steps later: the deviation is 1/3^5 = 0.4 % of its first value; gravity is taken out.
  EXPECT_NEAR(b[0].restitution, 4.0 / 3.0, 1.0 / 243.0 / 3.0 + 1e-12);
  // Reading at the first step after the contact would have given 3/3 = 1.
  const std::vector<Bounce> early = find_bounces(distances, velocity, {Plane{Eigen::Vector3d::UnitZ(), 0.0}}, 1e-3,
                                                 Eigen::Vector3d(0, 0, g), h, 0);
  EXPECT_NEAR(early[0].restitution, 1.0, 1e-12);
}

}  // namespace
}  // namespace rbaa
