// Friction's tangent frames (closest-point weights gamma and tangent basis T) for every distance
// type: r = sum gamma_i x_i has the type's squared distance as |r|^2; T is orthonormal and normal
// to r; T T^T is the projector I - r r^T / |r|^2; and the Jacobians (automatic differentiation)
// match central differences of the frames, in random configurations.

#include <gtest/gtest.h>

#include <random>

#include "contact_checks.hpp"
#include "rbaa/contact/edge_edge.hpp"
#include "rbaa/contact/point_triangle.hpp"
#include "rbaa/contact/tangent_frame.hpp"

namespace rbaa {
namespace {

using contact::EdgeEdgeDistanceType;
using contact::PointTriangleDistanceType;
using contact::TangentFrame;
using test::Points4;
using test::Vector12d;

// gamma and the columns of T stacked (4 + 6 numbers, T column-major as in the Jacobian).
Eigen::Matrix<double, 10, 1> flat(const TangentFrame& f) {
  Eigen::Matrix<double, 10, 1> v;
  v << f.gamma, f.basis.col(0), f.basis.col(1);
  return v;
}

void check_frame(const std::function<TangentFrame(const Points4&)>& frame,
                 const std::function<contact::TangentFrameJacobian(const Points4&)>& jacobian,
                 const std::function<double(const Points4&)>& squared_distance, const Points4& x,
                 const char* type) {
  const TangentFrame f = frame(x);
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  for (int i = 0; i < 4; ++i) r += f.gamma[i] * x[i];
  const double s = squared_distance(x);
  EXPECT_NEAR(r.squaredNorm(), s, 1e-12 * (1 + s)) << type;
  EXPECT_LT((f.basis.transpose() * f.basis - Eigen::Matrix2d::Identity()).norm(), 1e-12) << type;
  EXPECT_LT((f.basis.transpose() * r).norm(), 1e-12 * r.norm()) << type;
  const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - r * r.transpose() / r.squaredNorm();
  EXPECT_LT((f.basis * f.basis.transpose() - P).norm(), 1e-10) << type;
  // Jacobian against central differences, column by column.
  const contact::TangentFrameJacobian J = jacobian(x);
  Eigen::Matrix<double, 10, 12> J_ad, J_fd;
  J_ad << J.gamma, J.basis;
  const Vector12d x0 = test::stack(x);
  const double h = 1e-6;
  for (int k = 0; k < 12; ++k) {
    const Vector12d e = Vector12d::Unit(k);
    J_fd.col(k) =
        (flat(frame(test::unstack(x0 + h * e))) - flat(frame(test::unstack(x0 - h * e)))) / (2 * h);
  }
  EXPECT_LT((J_ad - J_fd).norm(), 1e-7 * J_ad.norm()) << type << "\nAD\n"
                                                      << J_ad << "\nFD\n"
                                                      << J_fd;
}

TEST(TangentFrame, PointTriangleFramesForEveryTypeMatchTheirDistanceAndDifferences) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 20; ++trial) {
    const Points4 x = test::random_points(rng);
    for (int t = 0; t <= static_cast<int>(PointTriangleDistanceType::P_T); ++t) {
      const auto type = static_cast<PointTriangleDistanceType>(t);
      check_frame(
          [&](const Points4& y) {
            return contact::point_triangle_tangent_frame(y[0], y[1], y[2], y[3], type);
          },
          [&](const Points4& y) {
            return contact::point_triangle_tangent_frame_jacobian(y[0], y[1], y[2], y[3], type);
          },
          [&](const Points4& y) {
            return contact::point_triangle_distance(y[0], y[1], y[2], y[3], type);
          },
          x, contact::to_string(type));
    }
  }
}

TEST(TangentFrame, EdgeEdgeFramesForEveryTypeMatchTheirDistanceAndDifferences) {
  std::mt19937 rng(4);
  for (int trial = 0; trial < 20; ++trial) {
    const Points4 x = test::random_points(rng);
    for (int t = 0; t <= static_cast<int>(EdgeEdgeDistanceType::EA_EB); ++t) {
      const auto type = static_cast<EdgeEdgeDistanceType>(t);
      check_frame(
          [&](const Points4& y) {
            return contact::edge_edge_tangent_frame(y[0], y[1], y[2], y[3], type);
          },
          [&](const Points4& y) {
            return contact::edge_edge_tangent_frame_jacobian(y[0], y[1], y[2], y[3], type);
          },
          [&](const Points4& y) {
            return contact::edge_edge_distance(y[0], y[1], y[2], y[3], type);
          },
          x, contact::to_string(type));
    }
  }
}

// Where the type is the actual one, r joins the actual closest points: the weights of the
// features' points are barycentric (in [0, 1]) and sum to 1 on each side.
TEST(TangentFrame, WeightsAreBarycentricForTheActualType) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 200; ++trial) {
    const Points4 x = test::random_points(rng);
    const auto pt = contact::point_triangle_distance_type(x[0], x[1], x[2], x[3]);
    const TangentFrame f = contact::point_triangle_tangent_frame(x[0], x[1], x[2], x[3], pt);
    EXPECT_EQ(f.gamma[0], 1.0);
    EXPECT_NEAR(f.gamma.tail<3>().sum(), -1.0, 1e-12);
    EXPECT_LE(f.gamma.tail<3>().maxCoeff(), 1e-12);
    const auto ee = contact::edge_edge_distance_type(x[0], x[1], x[2], x[3]);
    const TangentFrame g = contact::edge_edge_tangent_frame(x[0], x[1], x[2], x[3], ee);
    EXPECT_NEAR(g.gamma.head<2>().sum(), 1.0, 1e-12);
    EXPECT_NEAR(g.gamma.tail<2>().sum(), -1.0, 1e-12);
    EXPECT_GE(g.gamma.head<2>().minCoeff(), -1e-12);
    EXPECT_LE(g.gamma.tail<2>().maxCoeff(), 1e-12);
  }
}

}  // namespace
}  // namespace rbaa
