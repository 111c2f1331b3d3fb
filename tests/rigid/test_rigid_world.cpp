// The rigid twin's world beyond one body among planes: static triangle-mesh obstacles and several
// bodies (friction: test_rigid_friction.cpp).

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <tuple>
#include <vector>

#include "rbaa/error.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/mesh/grid_mesh.hpp"
#include "rbaa/mesh/tetrahedralize.hpp"
#include "rbaa/rigid/rigid_body.hpp"
#include "rbaa/rigid/rigid_simulation.hpp"
#include "rigid/rigid_fixtures.hpp"

namespace rbaa {
namespace {

using test::max_angle;
using test::max_gap;
using test::rectangle;
using test::square_floor;
using test::twin;

// --- Triangle-mesh obstacles -------------------------------------------------------------------

// A box falling onto a floor of two triangles moves as on the plane z = 0 through its first bounce,
// and then comes to rest on the floor's surface. Not closer: Bullet's plane contact collects the
// face's points by perturbing the box's orientation (rigid_simulation.cpp), which holds a resting
// box about one margin (1e-4 m) above the plane (measured 0.025098 m for the 0.025 m half side),
// and lets low-speed bounces start that much early; against triangles the face is clipped
// exactly (measured 0.024998 m at rest). Through the first bounce the paths agree within 3.6e-5 m
// and 5.7e-8 rad (measured); a tumbling landing on a corner does not compare this tightly, the
// two contact generators pick different corner points.
TEST(RigidMeshObstacles, BoxOnATriangleFloorMatchesThePlane) {
  const TetMesh cube = mesh_shape("cube", 1500);  // side 0.05 m
  RigidWorld on_plane;
  on_plane.time_step = 0.005;
  on_plane.bodies = {
      twin(cube, Eigen::Vector3d(-0.3, -0.1, 0.1), 2500, Eigen::Vector3d(0.4, 0.2, -1.0))};
  on_plane.planes = {Plane{Eigen::Vector3d::UnitZ(), 0.0}};
  RigidWorld on_mesh = on_plane;
  on_mesh.planes.clear();
  on_mesh.obstacle_meshes = {square_floor()};
  RigidSettings settings;
  settings.plane_restitution = {0.5};
  settings.mesh_restitution = {0.5};
  const auto a = simulate_rigid(on_plane, settings, 1.0).front();
  const auto b = simulate_rigid(on_mesh, settings, 1.0).front();
  // The second landing is at 0.22 s.
  const std::vector<RigidState> a_first(a.begin(), a.begin() + 41),
      b_first(b.begin(), b.begin() + 41);
  const double gap = max_gap(a_first, b_first), angle = max_angle(a_first, b_first);
  std::printf(
      "box on the triangle floor: through its first bounce %.3g m and %.3g rad from the plane "
      "run; at rest at z = %.7f m (on the plane %.7f m)\n",
      gap, angle, b.back().position.z(), a.back().position.z());
  EXPECT_GT(b_first[20].velocity.z(),
            0.3);  // it bounced (0.5 x 1.4 m/s, less gravity): 0.40 m/s at 0.1 s
  EXPECT_LT(gap, settings.margin);
  EXPECT_LT(angle, 1e-6);
  EXPECT_NEAR(b.back().position.z(), 0.025, 1e-5);
  EXPECT_LT(std::abs(b.back().velocity.z()), 1e-2);
  EXPECT_LT(b.back().orientation.angularDistance(Eigen::Quaterniond::Identity()), 1e-3);
}

// A ball against a backboard of one rectangle (open, in y = 0) bounces as off the plane y = 0,
// from either side, and passes beside its edge as if it were not there.
TEST(RigidMeshObstacles, BallBouncesOffAnOpenBackboardAsOffThePlane) {
  const TetMesh ball = mesh_shape("sphere", 800);
  const ObstacleMesh board =
      rectangle(Eigen::Vector3d(-1, 0, 0), Eigen::Vector3d(2, 0, 0), Eigen::Vector3d(0, 0, 2));
  for (double side : {1.0, -1.0}) {
    RigidWorld on_plane;
    on_plane.bodies = {twin(ball, Eigen::Vector3d(0.3, 0.6 * side, 1.5), 2500,
                            Eigen::Vector3d(0.5, -3 * side, 1))};
    on_plane.planes = {Plane{side * Eigen::Vector3d::UnitY(), 0.0}};
    RigidWorld on_mesh = on_plane;
    on_mesh.planes.clear();
    on_mesh.obstacle_meshes = {board};
    RigidSettings settings;
    settings.plane_restitution = {0.8};
    settings.mesh_restitution = {0.8};
    const auto a = simulate_rigid(on_plane, settings, 0.5).front();
    const auto b = simulate_rigid(on_mesh, settings, 0.5).front();
    const double gap = max_gap(a, b);
    std::printf(
        "ball against the backboard from side %+.0f: largest gap to the plane run %.3g m, "
        "rebound %.6f\n",
        side, gap, -b.back().velocity.y() / 3.0);
    EXPECT_LT(gap, 1e-6);
    EXPECT_NEAR(b.back().velocity.y(), 0.8 * 3 * side, 1e-3 * 3);
    EXPECT_GT(b.back().position.y() * side, 0.6);  // back on its own side
  }
  RigidWorld beside;
  beside.bodies = {twin(ball, Eigen::Vector3d(1.5, 0.6, 1.5), 2500, Eigen::Vector3d(0, -3, 1))};
  beside.obstacle_meshes = {board};
  const auto c = simulate_rigid(beside, RigidSettings{}, 0.5).front();
  EXPECT_NEAR(c.back().velocity.y(), -3.0, 1e-12);
  EXPECT_LT(c.back().position.y(), -0.8);
}

TEST(RigidMeshObstacles, AMeshWithoutTrianglesIsRefusedByName) {
  RigidWorld world;
  world.bodies = {twin(mesh_shape("cube", 300), Eigen::Vector3d(0, 0, 1), 2500)};
  ObstacleMesh empty;
  empty.name = "obstacles.meshes[0] (empty.obj)";
  world.obstacle_meshes = {empty};
  try {
    simulate_rigid(world, RigidSettings{}, 0.1);
    FAIL() << "an empty obstacle mesh was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("obstacles.meshes[0] (empty.obj)"), std::string::npos)
        << e.what();
  }
}

// --- Several bodies ----------------------------------------------------------------------------

// Bullet reads a body of mass 0 as static: a twin with zero (or negative, or NaN) mass or principal
// moment would hang in the air instead of failing, so it is refused by name.
TEST(RigidBodies, ABodyWithoutPositiveMassIsRefusedByName) {
  const TetMesh cube = mesh_shape("cube", 300);
  for (const auto& [label, mass, moment] :
       std::vector<std::tuple<const char*, double, double>>{{"zero mass", 0.0, 1.0},
                                                           {"negative mass", -1.0, 1.0},
                                                           {"NaN mass", std::nan(""), 1.0},
                                                           {"zero moment", 1.0, 0.0}}) {
    RigidWorld world;
    world.bodies = {twin(cube, Eigen::Vector3d(0, 0, 1), 2500)};
    world.bodies[0].name = "cube";
    world.bodies[0].mass.mass = mass;
    if (moment == 0.0) world.bodies[0].mass.principal_moments[1] = 0.0;
    try {
      simulate_rigid(world, RigidSettings{}, 0.01);
      ADD_FAILURE() << label << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("rigid body cube needs positive mass"), std::string::npos)
          << label << ": " << e.what();
    }
  }
}

// Two balls of one mesh stacked into one tet mesh, the second three times as dense: each twin
// gets its own mass, centre and initial velocity, and a head-on elastic collision of the heavy one
// with the light one at rest gives the textbook velocities (m1 - m2) v / (m1 + m2) and
// 2 m1 v / (m1 + m2), momentum kept.
TEST(RigidBodies, StackedBodiesGetTheirOwnMassAndCollideElastically) {
  TetMesh ball = mesh_shape("sphere", 800);
  const double radius = rigid_shape_from_surface(ball).radius;
  TetMesh stacked;
  stacked.V.resize(2 * ball.num_vertices(), 3);
  stacked.T.resize(2 * ball.num_tets(), 4);
  stacked.V << ball.V.rowwise() + Eigen::RowVector3d(0, 0, 1),
      ball.V.rowwise() + Eigen::RowVector3d(0.5, 0, 1);
  stacked.T << ball.T, ball.T.array() + ball.num_vertices();
  std::vector<Body> bodies(2);
  bodies[0].name = "object";
  bodies[0].vertex_end = ball.num_vertices();
  bodies[0].element_end = ball.num_tets();
  bodies[0].velocity = Eigen::Vector3d(0, 0, 0);
  bodies[1].name = "'heavy'";
  bodies[1].vertex_begin = ball.num_vertices();
  bodies[1].vertex_end = 2 * ball.num_vertices();
  bodies[1].element_begin = ball.num_tets();
  bodies[1].element_end = 2 * ball.num_tets();
  bodies[1].velocity = Eigen::Vector3d(-1, 0, 0);
  Eigen::VectorXd rho(stacked.num_tets());
  rho << Eigen::VectorXd::Constant(ball.num_tets(), 1000),
      Eigen::VectorXd::Constant(ball.num_tets(), 3000);

  RigidWorld world;
  world.bodies = rigid_bodies(stacked, bodies, rho);
  world.gravity.setZero();
  ASSERT_EQ(world.bodies.size(), 2u);
  const RigidBody &light = world.bodies[0], &heavy = world.bodies[1];
  const Moments m = compute_moments(ball, 1000.0);
  // Each mass on the twins' grid, 2^-24 of its scale (rigid_mass_properties).
  EXPECT_NEAR(light.mass.mass, m.m0, std::ldexp(m.m0, -24));
  EXPECT_NEAR(heavy.mass.mass, 3 * m.m0, std::ldexp(3 * m.m0, -24));
  EXPECT_LT((heavy.mass.centre - light.mass.centre - Eigen::Vector3d(0.5, 0, 0)).norm(), 1e-12);
  EXPECT_EQ(heavy.name, "'heavy'");
  EXPECT_TRUE(heavy.velocity == Eigen::Vector3d(-1, 0, 0));
  ASSERT_EQ(heavy.shape.kind, RigidShapeKind::kSphere);

  const auto states = simulate_rigid(world, RigidSettings{}, 0.5);
  ASSERT_EQ(states.size(), 2u);
  ASSERT_EQ(states[0].size(), 51u);
  // They touch after (0.5 - 2 r) / 1 m/s = 0.26 s.
  EXPECT_LT((states[0][20].velocity).norm(), 1e-12);
  const Eigen::Vector3d v_light = states[0].back().velocity, v_heavy = states[1].back().velocity;
  std::printf(
      "elastic collision of a 3:1 pair: light %.9f m/s, heavy %.9f m/s (expected -1.5, -0.5)\n",
      v_light.x(), v_heavy.x());
  EXPECT_NEAR(v_light.x(), -1.5, 1e-6);
  EXPECT_NEAR(v_heavy.x(), -0.5, 1e-6);
  EXPECT_LT(v_light.tail<2>().norm() + v_heavy.tail<2>().norm(), 1e-9);
  EXPECT_NEAR(light.mass.mass * v_light.x() + heavy.mass.mass * v_heavy.x(), -heavy.mass.mass,
              1e-9 * heavy.mass.mass);
  EXPECT_GT((states[0].back().position - states[1].back().position).norm(), 2 * radius);
}

// Per-pair restitution: a named pair of bodies gets exactly its own value, and nothing else
// changes: a head-on collision of two equal balls with pair restitution 0.5 leaves them with
// relative speed 0.5 of the approach, while a third ball bouncing off a mesh with restitution 0.7
// still rebounds at 0.7 (the body's own restitution 1 times the mesh's). The touch log names
// both contacts at the samples where they happen. Bullet's impulses meet the restitutions to
// 5.3e-7 (pair) and 2.1e-6 (mesh) m/s (measured), hence 1e-5.
TEST(RigidBodies, APairsRestitutionIsItsOwnAndTheTouchLogNamesEveryContact) {
  const TetMesh ball = mesh_shape("sphere", 800);
  const double radius = rigid_shape_from_surface(ball).radius;
  RigidWorld world;
  world.gravity.setZero();
  world.time_step = 0.01;
  world.bodies = {twin(ball, Eigen::Vector3d(0, 0, 1), 1000, Eigen::Vector3d(1, 0, 0)),
                  twin(ball, Eigen::Vector3d(0.5, 0, 1), 1000, Eigen::Vector3d(-1, 0, 0)),
                  twin(ball, Eigen::Vector3d(0, 3, 0.3), 1000, Eigen::Vector3d(0, 0, -1))};
  world.obstacle_meshes = {square_floor()};
  RigidSettings settings;
  settings.mesh_restitution = {0.7};
  settings.pair_restitution = {{1, 0, 0.5}};  // either order
  std::vector<RigidTouch> touches;
  const auto states = simulate_rigid(world, settings, 0.5, &touches);
  const Eigen::Vector3d w = states[0].back().velocity - states[1].back().velocity;
  std::printf("pair restitution 0.5: relative velocity after (%.9f, %.3g, %.3g); ball on mesh "
              "0.7: %.9f\n",
              w.x(), w.y(), w.z(), states[2].back().velocity.z());
  EXPECT_NEAR(w.x(), -0.5 * 2.0, 1e-5);
  EXPECT_NEAR(states[0].back().velocity.x() + states[1].back().velocity.x(), 0.0, 1e-9);
  EXPECT_NEAR(states[2].back().velocity.z(), 0.7, 1e-5);
  // The pair meets after (0.5 - 2 r) / 2 m/s, the third ball the floor after (0.3 - r) / 1 m/s.
  const int pair_sample = static_cast<int>(std::ceil((0.5 - 2 * radius) / 2.0 / 0.01 - 1e-9));
  const int floor_sample = static_cast<int>(std::ceil((0.3 - radius) / 1.0 / 0.01 - 1e-9));
  int pair_first = -1, floor_first = -1;
  for (const RigidTouch& t : touches) {
    ASSERT_EQ(t.first.kind, RigidContactSide::Kind::kBody);
    if (t.second.kind == RigidContactSide::Kind::kBody) {
      EXPECT_EQ(t.first.index, 0);
      EXPECT_EQ(t.second.index, 1);
      if (pair_first < 0) pair_first = t.sample;
    } else {
      EXPECT_EQ(t.second.kind, RigidContactSide::Kind::kMesh);
      EXPECT_EQ(t.first.index, 2);
      EXPECT_EQ(t.second.index, 0);
      if (floor_first < 0) floor_first = t.sample;
    }
  }
  EXPECT_NEAR(pair_first, pair_sample, 1);
  EXPECT_NEAR(floor_first, floor_sample, 1);

  // Without the entry the pair has the product of the bodies' restitutions (1): elastic.
  const auto elastic = simulate_rigid(world, RigidSettings{}, 0.5);
  EXPECT_NEAR(elastic[0].back().velocity.x() - elastic[1].back().velocity.x(), -2.0, 1e-6);
}

// Per-(body, plane) restitution: two balls dropped side by side onto one floor, the floor's own
// restitution 0.8 and ball 1's against it named 0.3. Gravity off, so each ball's normal velocity
// is constant before and after its one bounce: ball 0 rebounds at 0.8 (its own 1 times the
// floor's), ball 1 at exactly its named 0.3.
TEST(RigidBodies, ABodysRestitutionAgainstAPlaneIsItsOwn) {
  const TetMesh ball = mesh_shape("sphere", 300);
  RigidWorld world;
  world.gravity.setZero();
  world.time_step = 0.01;
  world.bodies = {twin(ball, Eigen::Vector3d(0, 0, 0.3), 1000, Eigen::Vector3d(0, 0, -1)),
                  twin(ball, Eigen::Vector3d(1, 0, 0.3), 1000, Eigen::Vector3d(0, 0, -1))};
  world.planes = {Plane{Eigen::Vector3d::UnitZ(), 0.0}};
  RigidSettings settings;
  settings.plane_restitution = {0.8};
  settings.body_plane_restitution = {{1, 0, 0.3}};
  const auto states = simulate_rigid(world, settings, 0.5);
  std::printf("floor 0.8, ball 1 against it 0.3: rebounds %.9f and %.9f\n",
              states[0].back().velocity.z(), states[1].back().velocity.z());
  EXPECT_NEAR(states[0].back().velocity.z(), 0.8, 1e-5);
  EXPECT_NEAR(states[1].back().velocity.z(), 0.3, 1e-5);
}

TEST(RigidBodies, BadRestitutionsAreRefusedInOneLine) {
  const TetMesh ball = mesh_shape("sphere", 300);
  RigidWorld world;
  world.bodies = {twin(ball, Eigen::Vector3d(0, 0, 1), 1000),
                  twin(ball, Eigen::Vector3d(0.5, 0, 1), 1000)};
  auto error = [&](const RigidSettings& settings) {
    try {
      simulate_rigid(world, settings, 0.01);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  RigidSettings missing;
  missing.pair_restitution = {{0, 2, 0.5}};
  RigidSettings same;
  same.pair_restitution = {{1, 1, 0.5}};
  RigidSettings twice;
  twice.pair_restitution = {{0, 1, 0.5}, {1, 0, 0.6}};
  RigidSettings negative;
  negative.pair_restitution = {{0, 1, -0.1}};
  RigidSettings negative_mesh;
  negative_mesh.mesh_restitution = {-1};
  RigidSettings no_plane;  // the world has no planes
  no_plane.body_plane_restitution = {{0, 0, 0.5}};
  const std::vector<std::pair<RigidSettings, std::string>> cases = {
      {missing, "must name two different bodies of the 2"},
      {same, "bodies (1, 1) must name two different bodies"},
      {twice, "is given twice"},
      {negative, "bodies (0, 1) must be a finite number >= 0, got -0.1"},
      {negative_mesh, "obstacle mesh 0's restitution must be a finite number >= 0"},
      {no_plane, "body 0 against plane 0 must name one of the 2 bodies and one of the 0 planes"}};
  for (const auto& [settings, expected] : cases) {
    const std::string what = error(settings);
    EXPECT_NE(what.find(expected), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

// A box dropped on a box that rests on a triangle-mesh floor: bodies collide with each other and
// with mesh obstacles, and the stack comes to rest at its height, level and centred. A resting box
// loses contact every other internal step (only touching contacts are solved, RigidSettings), so
// its velocity at one sample jitters by up to a step's gravity, g dt = 0.01 m/s, and which sample
// catches which phase is chaotic (one ulp more friction turns a final speed of 6e-5 m/s into
// 2e-3 m/s): the last 0.2 s are judged by their mean drift, mean heights and largest tilt.
// Measured: drift 1.7e-4 and 1.5e-4 m/s, mean heights 7e-6 and 3e-6 m low, tilt 1.1e-3 rad,
// centres 6.7e-5 m apart (Bullet's box-box contact points are not symmetric about the centre, so
// the landing nudges the top box).
TEST(RigidBodies, BoxDroppedOnABoxComesToRestOnTheMeshFloor) {
  const TetMesh cube = mesh_shape("cube", 300);  // side 0.05 m
  RigidWorld world;
  world.bodies = {twin(cube, Eigen::Vector3d(0, 0, 0.1), 2500, Eigen::Vector3d(0, 0, -0.5)),
                  twin(cube, Eigen::Vector3d(0, 0, 0.025), 2500)};
  world.obstacle_meshes = {square_floor()};
  world.obstacle_meshes[0].friction = 0.5;
  world.body_friction = 0.5;
  RigidSettings settings;
  settings.restitution = 0;
  const auto states = simulate_rigid(world, settings, 1.0);
  const size_t from = 80;  // t = 0.8 s
  const double span = states[0].back().time - states[0][from].time;
  double drift[2], height[2] = {0, 0}, tilt = 0;
  for (int b = 0; b < 2; ++b) {
    drift[b] = (states[b].back().position - states[b][from].position).norm() / span;
    for (size_t i = from; i < states[b].size(); ++i) {
      height[b] += states[b][i].position.z() / static_cast<double>(states[b].size() - from);
      tilt =
          std::max(tilt, states[b][i].orientation.angularDistance(Eigen::Quaterniond::Identity()));
    }
  }
  const RigidState &top = states[0].back(), &bottom = states[1].back();
  const double offset = (top.position.head<2>() - bottom.position.head<2>()).norm();
  std::printf(
      "box on a box on the mesh floor, last 0.2 s: mean heights %.7f and %.7f m, drift %.2g and "
      "%.2g m/s, largest tilt %.2g rad; centres %.2g m apart at the end\n",
      height[0], height[1], drift[0], drift[1], tilt, offset);
  // Bullet's margin (1e-4 m) lies inside a box's extents, so the boxes rest exactly stacked.
  EXPECT_NEAR(height[1], 0.025, 2e-5);
  EXPECT_NEAR(height[0], 0.075, 2e-5);
  EXPECT_LT(drift[0] + drift[1], 1e-3);
  EXPECT_LT(tilt, 3e-3);
  EXPECT_LT(offset, 1e-3);
}

}  // namespace
}  // namespace rbaa
