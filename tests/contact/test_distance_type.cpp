// Distance-type classification on hand-built cases: every region of a point against an edge and a
// triangle, every feature pair of two edges, parallel edges, and points on region boundaries
// (where either neighbouring type must give the same distance and gradient).

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <vector>

#include "contact_checks.hpp"
#include "rbaa/contact/distance_type.hpp"
#include "rbaa/contact/edge_edge.hpp"
#include "rbaa/contact/point_edge.hpp"
#include "rbaa/contact/point_triangle.hpp"

namespace rbaa::contact {
namespace {

using V = Eigen::Vector3d;

TEST(ContactDistanceType, PointEdgeRegions) {
  const V e0(0, 0, 0), e1(1, 0, 0);
  EXPECT_EQ(point_edge_distance_type(V(-1, 1, 0), e0, e1), PointEdgeDistanceType::P_E0);
  EXPECT_EQ(point_edge_distance_type(V(2, 1, 0), e0, e1), PointEdgeDistanceType::P_E1);
  EXPECT_EQ(point_edge_distance_type(V(0.5, 1, -1), e0, e1), PointEdgeDistanceType::P_E);
  // A zero-length edge is a point.
  EXPECT_EQ(point_edge_distance_type(V(0.5, 1, -1), e0, e0), PointEdgeDistanceType::P_E0);
  EXPECT_DOUBLE_EQ(point_edge_distance(V(0.5, 1, -1), e0, e1), 2.0);
  EXPECT_DOUBLE_EQ(point_edge_distance(V(2, 1, 0), e0, e1), 2.0);
}

struct TriangleCase {
  V p;
  PointTriangleDistanceType type;
  double distance;  // squared
};

TEST(ContactDistanceType, PointTriangleRegions) {
  const V t0(0, 0, 0), t1(1, 0, 0), t2(0, 1, 0);
  using T = PointTriangleDistanceType;
  const TriangleCase cases[] = {
      {V(-1, -1, 0.5), T::P_T0, 2.25},    {V(-0.1, -0.2, 0), T::P_T0, 0.05},
      {V(2, -0.5, 0.3), T::P_T1, 1.34},   {V(-0.5, 2, -0.3), T::P_T2, 1.34},
      {V(0.5, -1, 0.2), T::P_E0, 1.04},   {V(1, 1, 0.1), T::P_E1, 0.51},
      {V(-1, 0.5, 0), T::P_E2, 1.0},      {V(0.25, 0.25, 0.5), T::P_T, 0.25},
      {V(0.2, 0.1, -1e-9), T::P_T, 1e-18}};
  for (const TriangleCase& c : cases) {
    EXPECT_EQ(point_triangle_distance_type(c.p, t0, t1, t2), c.type)
        << c.p.transpose() << ": " << to_string(point_triangle_distance_type(c.p, t0, t1, t2));
    EXPECT_NEAR(point_triangle_distance(c.p, t0, t1, t2), c.distance, 1e-15 * (1 + c.distance))
        << c.p.transpose();
  }
}

// The same regions with the triangle moved, turned and its corners relabelled: the type follows
// the corners (P_T1 is always "closest to t1").
TEST(ContactDistanceType, PointTriangleFollowsTheCorners) {
  std::mt19937 rng(7);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, V(1, 2, 3).normalized()).toRotationMatrix();
  const V shift(0.3, -2, 5);
  const auto move = [&](const V& x) -> V { return R * x + shift; };
  const V t[3] = {move(V(0, 0, 0)), move(V(1, 0, 0)), move(V(0, 1, 0))};
  using T = PointTriangleDistanceType;
  const V near_t1 = move(V(2, -0.5, 0.3)), over_e1 = move(V(1, 1, 0.1));
  // Relabelling (t0, t1, t2) -> (t1, t2, t0): what was t1 is now t0; edge t1t2 is now E0.
  EXPECT_EQ(point_triangle_distance_type(near_t1, t[0], t[1], t[2]), T::P_T1);
  EXPECT_EQ(point_triangle_distance_type(near_t1, t[1], t[2], t[0]), T::P_T0);
  EXPECT_EQ(point_triangle_distance_type(near_t1, t[2], t[0], t[1]), T::P_T2);
  EXPECT_EQ(point_triangle_distance_type(over_e1, t[0], t[1], t[2]), T::P_E1);
  EXPECT_EQ(point_triangle_distance_type(over_e1, t[1], t[2], t[0]), T::P_E0);
  EXPECT_EQ(point_triangle_distance_type(over_e1, t[2], t[0], t[1]), T::P_E2);
  // Reversing the orientation flips the normal but not the distance or the type of a face point.
  const V above = move(V(0.25, 0.25, 0.5));
  EXPECT_EQ(point_triangle_distance_type(above, t[0], t[2], t[1]), T::P_T);
  EXPECT_NEAR(point_triangle_distance(above, t[0], t[2], t[1]), 0.25, 1e-14);
}

// On a region boundary (a vertex exactly over an edge or a corner) the neighbouring types must
// agree in value and gradient: the squared distance to a convex set is C1, so whichever type the
// rounding picks, the barrier's force is the same.
TEST(ContactDistanceType, PointTriangleBoundariesAgree) {
  const V t0(0, 0, 0), t1(1, 0, 0), t2(0, 1, 0);
  using T = PointTriangleDistanceType;
  struct Boundary {
    V p;
    std::vector<T> types;
  };
  const Boundary boundaries[] = {
      {V(0.5, 0, 0.3), {T::P_E0, T::P_T}},                   // over edge t0t1
      {V(0.5, 0.5, 0.3), {T::P_E1, T::P_T}},                 // over edge t1t2
      {V(0, 0, 0.3), {T::P_T0, T::P_E0, T::P_E2, T::P_T}},   // over corner t0
      {V(1, 0, -0.3), {T::P_T1, T::P_E0, T::P_E1, T::P_T}},  // under corner t1
      {V(0.5, -0.5, 0.3), {T::P_E0}},                        // beside edge t0t1, in its region
      {V(-0.5, 0, 0.3), {T::P_T0, T::P_E2}},                 // over t0 seen from edge t2t0
  };
  for (const Boundary& b : boundaries) {
    const T chosen = point_triangle_distance_type(b.p, t0, t1, t2);
    EXPECT_NE(std::find(b.types.begin(), b.types.end(), chosen), b.types.end())
        << b.p.transpose() << " chose " << to_string(chosen);
    const double d = point_triangle_distance(b.p, t0, t1, t2, chosen);
    const Vector12d g = point_triangle_distance_gradient(b.p, t0, t1, t2, chosen);
    for (T other : b.types) {
      EXPECT_NEAR(point_triangle_distance(b.p, t0, t1, t2, other), d, 1e-15) << to_string(other);
      EXPECT_LT((point_triangle_distance_gradient(b.p, t0, t1, t2, other) - g).norm(), 1e-14)
          << b.p.transpose() << ": " << to_string(other) << " vs " << to_string(chosen);
    }
  }
}

TEST(ContactDistanceType, DegenerateTriangleNeverAnswersTheFace) {
  // Collinear corners: no plane. The closest point is on the segment t0..t2.
  const V t0(0, 0, 0), t1(1, 0, 0), t2(2, 0, 0);
  const V p(0.5, 0.4, 0.3);
  const PointTriangleDistanceType type = point_triangle_distance_type(p, t0, t1, t2);
  EXPECT_NE(type, PointTriangleDistanceType::P_T);
  EXPECT_NEAR(point_triangle_distance(p, t0, t1, t2, type), 0.25, 1e-15);
  // A zero-length edge (t1 = t0), with p where the region tests would name that edge: the
  // answer is a corner or the other edge, and the distance is finite.
  for (const V& q : {V(0.5, 0.4, 0.3), V(-0.5, 0.4, 0.3), V(0.5, -0.4, 0.3)}) {
    const PointTriangleDistanceType t = point_triangle_distance_type(q, t0, t0, t2);
    EXPECT_TRUE(std::isfinite(point_triangle_distance(q, t0, t0, t2, t))) << to_string(t);
    EXPECT_NEAR(point_triangle_distance(q, t0, t0, t2), point_edge_distance(q, t0, t2), 1e-15);
  }
}

struct EdgeCase {
  V eb0, eb1;
  EdgeEdgeDistanceType type;
  double distance;  // squared
};

TEST(ContactDistanceType, EdgeEdgeFeaturePairs) {
  const V ea0(0, 0, 0), ea1(1, 0, 0);
  using T = EdgeEdgeDistanceType;
  const EdgeCase cases[] = {
      {V(0.5, -1, 1), V(0.5, 1, 1), T::EA_EB, 1.0},
      {V(-1, -1, 1), V(-1, 1, 1), T::EA0_EB, 2.0},
      {V(2, -1, 1), V(2, 1, 1), T::EA1_EB, 2.0},
      {V(0.5, 1, 1), V(0.5, 2, 1), T::EA_EB0, 2.0},
      {V(0.5, 2, 1), V(0.5, 1, 1), T::EA_EB1, 2.0},
      {V(-1, 1, 1), V(-1, 2, 1), T::EA0_EB0, 3.0},
      {V(-1, 2, 1), V(-1, 1, 1), T::EA0_EB1, 3.0},
      {V(2, 1, 1), V(2, 2, 1), T::EA1_EB0, 3.0},
      {V(2, 2, 1), V(2, 1, 1), T::EA1_EB1, 3.0},
      // Crossing at an angle, eb's interior closest to ea's interior, below it.
      {V(0.2, -0.3, -0.5), V(0.6, 0.9, -0.5), T::EA_EB, 0.25},
  };
  for (const EdgeCase& c : cases) {
    const T type = edge_edge_distance_type(ea0, ea1, c.eb0, c.eb1);
    EXPECT_EQ(type, c.type) << c.eb0.transpose() << " / " << c.eb1.transpose() << ": "
                            << to_string(type);
    EXPECT_NEAR(edge_edge_distance(ea0, ea1, c.eb0, c.eb1), c.distance, 1e-15);
    // Swapping the edges swaps the roles (EA0_EB <-> EA_EB0 ...) and keeps the distance.
    EXPECT_NEAR(edge_edge_distance(c.eb0, c.eb1, ea0, ea1), c.distance, 1e-15);
  }
}

TEST(ContactDistanceType, ParallelEdgesUseEndpoints) {
  const V ea0(0, 0, 0), ea1(1, 0, 0);
  using T = EdgeEdgeDistanceType;
  // Exactly parallel and overlapping: the lines' closest points are not unique.
  const T overlap = edge_edge_distance_type(ea0, ea1, V(0.5, 0, 1), V(1.5, 0, 1));
  EXPECT_NE(overlap, T::EA_EB);
  EXPECT_DOUBLE_EQ(edge_edge_distance(ea0, ea1, V(0.5, 0, 1), V(1.5, 0, 1)), 1.0);
  // Anti-parallel, overlapping.
  EXPECT_NE(edge_edge_distance_type(ea0, ea1, V(0.8, 0.6, 0), V(-0.5, 0.6, 0)), T::EA_EB);
  EXPECT_DOUBLE_EQ(edge_edge_distance(ea0, ea1, V(0.8, 0.6, 0), V(-0.5, 0.6, 0)), 0.36);
  // Parallel, disjoint along the line: endpoint to endpoint.
  EXPECT_EQ(edge_edge_distance_type(ea0, ea1, V(2, 0, 1), V(3, 0, 1)), T::EA1_EB0);
  EXPECT_DOUBLE_EQ(edge_edge_distance(ea0, ea1, V(2, 0, 1), V(3, 0, 1)), 2.0);
  // 1e-11 rad from parallel counts as parallel (sin^2 = 1e-22 < 1e-20); 1e-6 rad does not, and
  // then the lines' closest points lie far outside both edges, so an endpoint case is chosen too.
  for (double angle : {1e-11, 1e-6}) {
    const V eb0(0.5, 0, 1), eb1 = eb0 + V(std::cos(angle), std::sin(angle), 0);
    const T type = edge_edge_distance_type(ea0, ea1, eb0, eb1);
    EXPECT_NE(type, T::EA_EB) << angle;
    EXPECT_NEAR(edge_edge_distance(ea0, ea1, eb0, eb1), 1.0, 1e-12) << angle;
  }
  // 1e-6 rad from parallel with the lines crossing (in projection) inside both edges: the lines'
  // distance is meaningful and is chosen.
  const V eb0 = V(0.5, 0, 1) - 0.5 * V(std::cos(1e-6), std::sin(1e-6), 0);
  const V eb1 = V(0.5, 0, 1) + 0.5 * V(std::cos(1e-6), std::sin(1e-6), 0);
  EXPECT_EQ(edge_edge_distance_type(ea0, ea1, eb0, eb1), T::EA_EB);
  EXPECT_NEAR(edge_edge_distance(ea0, ea1, eb0, eb1), 1.0, 1e-9);
}

}  // namespace
}  // namespace rbaa::contact
