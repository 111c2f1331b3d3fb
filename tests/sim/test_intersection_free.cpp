// The exact intersection check every contact test runs on its trajectories
// (support/intersection_free.hpp) can fail: overlapping bodies, a body pierced by an obstacle
// triangle, a vertex 1e-12 behind a plane, exactly touching (coplanar) faces, a body swallowed
// whole by a closed obstacle or another body are all found, and named; bodies a few ulps apart,
// a vertex 1e-300 in front of a plane and a body folded through itself are not.

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "mesh_fixtures.hpp"
#include "obstacle_fixtures.hpp"
#include "support/intersection_free.hpp"

namespace rbaa {
namespace {

using test::tet;

// Two single-tet bodies stacked into one mesh: body 0 has the face z = 0 on top (the triangle
// (0,0,0), (1,0,0), (0,1,0)), body 1 its apex at `apex` pointing down.
struct TwoTets {
  TetMesh mesh;
  std::vector<Body> bodies;
};
TwoTets two_tets(const Eigen::Vector3d& apex) {
  const TetMesh a = tet({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.25, 0.25, -1});
  const TetMesh b = tet(apex, apex + Eigen::Vector3d(1, 0.2, 1), apex + Eigen::Vector3d(-0.3, 1, 1),
                        apex + Eigen::Vector3d(-0.5, -0.6, 1));
  TwoTets t;
  t.mesh.V.resize(8, 3);
  t.mesh.V << a.V, b.V;
  t.mesh.T.resize(2, 4);
  t.mesh.T << a.T, (b.T.array() + 4).matrix();
  t.bodies.resize(2);
  t.bodies[0].name = "bodies[0] (base)";
  t.bodies[0].vertex_end = 4;
  t.bodies[0].element_end = 1;
  t.bodies[1].name = "bodies[1] (apex)";
  t.bodies[1].vertex_begin = 4;
  t.bodies[1].vertex_end = 8;
  t.bodies[1].element_begin = 1;
  t.bodies[1].element_end = 2;
  return t;
}

std::string check(const TwoTets& t, const std::vector<Plane>& planes = {},
                  const std::vector<ObstacleMesh>& meshes = {}) {
  return test::IntersectionCheck(t.mesh, t.bodies, planes, meshes)
      .first_intersection(test::positions(t.mesh));
}

TEST(IntersectionFree, OverlappingTetsAreFoundAndNamed) {
  const std::string what = check(two_tets({0.2, 0.2, -0.05}));
  EXPECT_NE(what.find("bodies[0] (base) surface triangle"), std::string::npos) << what;
  EXPECT_NE(what.find("intersects bodies[1] (apex) surface triangle"), std::string::npos) << what;
  EXPECT_NE(what.find("intersecting triangle pairs"), std::string::npos) << what;
}

TEST(IntersectionFree, TetsTheSmallestDoubleApartAreNot) {
  const double tiny = std::numeric_limits<double>::denorm_min();  // 4.9e-324
  EXPECT_EQ(check(two_tets({0.2, 0.2, tiny})), "");
  EXPECT_EQ(check(two_tets({0.2, 0.2, 1e-15})), "");
  // Beside the face, level with it: the apex is 1 ulp past the hypotenuse x + y = 1.
  EXPECT_EQ(check(two_tets({0.5, std::nextafter(0.5, 1.0), 0.0})), "");
}

TEST(IntersectionFree, TouchingIsIntersecting) {
  // The apex on the face (closed triangles: touching at a point counts).
  EXPECT_NE(check(two_tets({0.2, 0.2, 0.0})), "");
  // The apex on the face's edge x + y = 1.
  EXPECT_NE(check(two_tets({0.5, 0.5, 0.0})), "");
  // Exactly coplanar faces overlapping in a patch: body 1 stands on body 0's top face, shifted
  // within the plane z = 0.
  TwoTets t;
  const TetMesh a = tet({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.25, 0.25, -1});
  const TetMesh b = tet({0.5, 0.25, 0}, {1.5, 0.25, 0}, {0.5, 1.25, 0}, {0.75, 0.5, 1});
  t.mesh.V.resize(8, 3);
  t.mesh.V << a.V, b.V;
  t.mesh.T.resize(2, 4);
  t.mesh.T << a.T, (b.T.array() + 4).matrix();
  t.bodies = two_tets({0, 0, 1}).bodies;
  EXPECT_NE(check(t), "");
  // The same lifted by the smallest double: apart.
  t.mesh.V.block(4, 2, 3, 1).setConstant(std::numeric_limits<double>::denorm_min());
  EXPECT_EQ(check(t), "");
}

TEST(IntersectionFree, AVertex1em12BehindAPlaneIsFound) {
  const TwoTets t = two_tets({0.2, 0.2, 2.0});
  Plane floor;
  floor.offset = -1.0 + 1e-12;  // the base tet's lowest vertex is at z = -1
  const std::string what = check(t, {floor});
  EXPECT_NE(what.find("bodies[0] (base) surface vertex 3"), std::string::npos) << what;
  EXPECT_NE(what.find("is on or behind plane 0"), std::string::npos) << what;
  EXPECT_NE(what.find("-1.000e-12"), std::string::npos) << what;
  floor.offset = -1.0;  // on the plane: in contact
  EXPECT_NE(check(t, {floor}), "");
  floor.offset = -1.0 - 1e-300;  // rounds to -1.0: still on it
  EXPECT_NE(check(t, {floor}), "");
  floor.offset = std::nextafter(-1.0, -2.0);  // 1 ulp below: free
  EXPECT_EQ(check(t, {floor}), "");
  // A slanted plane through the origin, the base's vertex (0, 0, 0) on it.
  Plane slanted;
  slanted.normal = Eigen::Vector3d(1, 1, 1).normalized();
  slanted.offset = 0;
  EXPECT_NE(check(t, {slanted}), "");
}

// The sign of normal . x - offset agrees with exact rational arithmetic for points within a few
// ulps of slanted planes, where the double sum's sign is often wrong.
TEST(IntersectionFree, PlaneSideIsExactNearThePlane) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int double_sign_wrong = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const Eigen::Vector3d n = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    const Eigen::Vector3d x(u(rng), u(rng), u(rng));
    double offset = n.dot(x);
    for (int k = trial % 5; k > 0; --k) offset = std::nextafter(offset, trial % 2 ? 2.0 : -2.0);
    using Exact = CGAL::Exact_rational;
    const int exact = CGAL::sign(Exact(n.x()) * Exact(x.x()) + Exact(n.y()) * Exact(x.y()) +
                                 Exact(n.z()) * Exact(x.z()) - Exact(offset));
    const double fast = n.dot(x) - offset;
    double_sign_wrong += (fast > 0) - (fast < 0) != exact;
    ASSERT_EQ(test::intersection_detail::plane_side(n, offset, x), exact) << trial;
  }
  std::printf("the plain double sign is wrong in %d of 20000 near-plane cases\n",
              double_sign_wrong);
  EXPECT_GT(double_sign_wrong, 0);  // the exact fallback is exercised
}

TEST(IntersectionFree, ATrianglePiercedByAnObstacleTriangleIsFound) {
  const TwoTets t = two_tets({0.2, 0.2, 5.0});
  // A vertical triangle through the base's top face, its corners all outside the base tet.
  const ObstacleMesh blade =
      test::obstacle_mesh({{0.2, -1.0, 0.5}, {0.2, 1.0, 0.5}, {0.2, 0.0, -3.0}}, {{0, 1, 2}},
                          "obstacles.meshes[0] (blade)");
  const std::string what = check(t, {}, {blade});
  EXPECT_NE(what.find("bodies[0] (base) surface triangle"), std::string::npos) << what;
  EXPECT_NE(what.find("intersects obstacles.meshes[0] (blade) triangle 0 (vertices 0, 1, 2)"),
            std::string::npos)
      << what;
  // Moved beyond the base (x > 1): free.
  ObstacleMesh away = blade;
  away.V.col(0).setConstant(1.0 + 1e-9);
  EXPECT_EQ(check(t, {}, {away}), "");
  // A degenerate obstacle triangle (a segment) through the base's top face is found too.
  const ObstacleMesh needle = test::obstacle_mesh(
      {{0.2, 0.2, 0.5}, {0.2, 0.2, -0.5}, {0.2, 0.2, 0.0}}, {{0, 1, 2}}, "needle");
  EXPECT_NE(check(t, {}, {needle}), "");
}

TEST(IntersectionFree, ABodyInsideAClosedObstacleOrBodyIsFound) {
  const TwoTets t = two_tets({0.2, 0.2, 5.0});
  const ObstacleMesh box =
      test::box_obstacle(Eigen::Vector3d(-2, -2, -2), Eigen::Vector3d(2, 2, 2));
  const std::string what = check(t, {}, {box});
  EXPECT_NE(what.find("bodies[0] (base) is inside box"), std::string::npos) << what;
  // A closed box inside a body.
  const ObstacleMesh pebble =
      test::box_obstacle(Eigen::Vector3d(0.1, 0.1, -0.3), Eigen::Vector3d(0.2, 0.2, -0.2));
  EXPECT_NE(check(two_tets({0.2, 0.2, 5.0}), {}, {pebble}).find("box is inside bodies[0]"),
            std::string::npos);
  // A small tet inside a big one (body 1 is the big one).
  TwoTets nested;
  const TetMesh small =
      tet({0.1, 0.1, -0.2}, {0.2, 0.1, -0.2}, {0.1, 0.2, -0.2}, {0.12, 0.12, -0.3});
  const TetMesh big = tet({-1, -1, 1}, {3, -1, 1}, {-1, 3, 1}, {0.2, 0.2, -3});
  nested.mesh.V.resize(8, 3);
  nested.mesh.V << small.V, big.V;
  nested.mesh.T.resize(2, 4);
  nested.mesh.T << small.T, (big.T.array() + 4).matrix();
  nested.bodies = two_tets({0, 0, 1}).bodies;
  EXPECT_NE(check(nested).find("bodies[0] (base) is inside bodies[1] (apex)"), std::string::npos)
      << check(nested);
  // An open box (its top's two triangles left out) around a body is no container.
  ObstacleMesh open_box = box;
  open_box.F = box.F.topRows(12).eval();
  open_box.F.middleRows(2, 2) = box.F.bottomRows(2);
  open_box.F.conservativeResize(10, 3);
  EXPECT_EQ(check(t, {}, {open_box}), "");
}

// Two fine balls (3072 surface triangles each) side by side along a diagonal and a tilted floor
// under them, so that all their boxes overlap and the broad phase has to sort it out: the check
// stays in milliseconds (a brute-force pass would test 9.4 million triangle pairs between the
// balls) and tells apart a gap of 1e-9 m and an overlap.
TEST(IntersectionFree, ThousandsOfTrianglesStayCheap) {
  const double r = 0.1;
  const Eigen::Vector3d diagonal = Eigen::Vector3d(1, 1, 0).normalized();
  auto pair = [&](double distance) {
    const TetMesh a = test::ball_mesh(r, 16);
    const TetMesh b = test::ball_mesh(r, 16, distance * diagonal);
    TwoTets t;
    t.mesh.V.resize(a.num_vertices() + b.num_vertices(), 3);
    t.mesh.V << a.V, b.V;
    t.mesh.T.resize(a.num_tets() + b.num_tets(), 4);
    t.mesh.T << a.T, (b.T.array() + a.num_vertices()).matrix();
    t.bodies = two_tets({0, 0, 1}).bodies;
    t.bodies[0].vertex_end = a.num_vertices();
    t.bodies[0].element_end = a.num_tets();
    t.bodies[1].vertex_begin = a.num_vertices();
    t.bodies[1].vertex_end = t.mesh.num_vertices();
    t.bodies[1].element_begin = a.num_tets();
    t.bodies[1].element_end = t.mesh.num_tets();
    return t;
  };
  // The balls' vertices lie on their spheres and their faces inside: 2r + 1e-9 apart they are
  // apart, 2r - 2 % apart they overlap (the facets sag by less than 0.5 % of r at n = 16).
  const TwoTets apart = pair(2 * r + 1e-9), overlapping = pair(1.98 * r);
  // A floor tilted by 0.2 rad about y, 1e-6 m below the balls' spheres: its box overlaps theirs.
  ObstacleMesh floor = test::square_obstacle(1.0);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  for (Eigen::Index v = 0; v < floor.V.rows(); ++v) {
    floor.V.row(v) = (R * floor.V.row(v).transpose() - (r + 1e-6) * R.col(2)).transpose();
  }
  const test::IntersectionCheck check(apart.mesh, apart.bodies, {}, {floor});
  const Eigen::VectorXd q = test::positions(apart.mesh);
  const int repeats = 10;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < repeats; ++i) EXPECT_EQ(check.first_intersection(q), "");
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / repeats;
  std::printf(
      "two balls of 3072 surface triangles each, boxes overlapping, and a floor: %.2f ms "
      "per position\n",
      1e3 * seconds);
  EXPECT_NE(check.first_intersection(test::positions(overlapping.mesh)), "");
}

TEST(IntersectionFree, ABodyThroughItselfIsNotChecked) {
  // One body of two cubes side by side, the second folded back through the first.
  TetMesh m = test::box_mesh(2, 1, 1, 1.0);
  Eigen::VectorXd q = test::positions(m);
  for (int v = 0; v < m.num_vertices(); ++v)
    if (m.V(v, 0) > 1.5) q[3 * v] = 0.5;
  EXPECT_EQ(test::IntersectionCheck(m, std::vector<Body>{}, {}, {}).first_intersection(q), "");
}

TEST(IntersectionFree, ATrajectoryNamesItsFirstIntersectingPosition) {
  const TwoTets t = two_tets({0.2, 0.2, 0.1});
  Trajectory traj;
  traj.time_step = 0.01;
  const Eigen::VectorXd q0 = test::positions(t.mesh);
  for (double drop : {0.0, 0.05, 0.12, 0.2}) {
    Eigen::VectorXd q = q0;
    for (int v = 4; v < 8; ++v) q[3 * v + 2] -= drop;
    traj.q.push_back(q);
  }
  traj.steps.resize(3);
  SimulationSettings settings;
  settings.bodies = t.bodies;
  const std::string what = test::first_intersection(t.mesh, settings, traj);
  EXPECT_EQ(what.rfind("q[2] of 4 (t = 0.02 s, after step 1): bodies[0] (base)", 0), 0u) << what;
  traj.q.resize(2);
  EXPECT_EQ(test::first_intersection(t.mesh, settings, traj), "");
}

}  // namespace
}  // namespace rbaa
