// The simulator with static triangle-mesh obstacles: a ball on a two-triangle square follows the
// same path as on the analytic plane; a ball striking a box's edge and corner never intersects it;
// an obstacle out of reach leaves a run bit for bit unchanged; a body starting inside is refused.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "mesh_fixtures.hpp"
#include "obstacle_fixtures.hpp"
#include "rbaa/error.hpp"
#include "rbaa/sim/simulator.hpp"
#include "support/intersection_free.hpp"

namespace rbaa {
namespace {

struct Ball {
  TetMesh mesh;
  SimulationSettings settings;
  Eigen::VectorXd q0, v0;
};

// A coarse ball (r = 0.1 m, 2500 kg/m^3) `gap` above z = 0 at (x, y), thrown at 2 m/s: the
// adjoint tests' ball (diff_fixtures.hpp) without its plane.
Ball ball(double x, double y, double z_gap, const Eigen::Vector3d& velocity, int steps) {
  Ball b;
  b.mesh = test::lifted(test::ball_mesh(0.1, 3, Eigen::Vector3d(x, y, 0.0)), z_gap);
  b.settings.time_step = 2e-3;
  b.settings.num_steps = steps;
  b.settings.d_hat = 3e-3;
  b.settings.kappa = 2e2;
  b.settings.newton_tolerance = 1e-10;
  b.q0 = test::positions(b.mesh);
  const Eigen::Vector3d c = b.mesh.V.colwise().mean().transpose();
  b.v0 = rigid_velocities(b.q0, c, velocity, Eigen::Vector3d(3.0, -2.0, 1.0));
  return b;
}

MaterialField stiff(const TetMesh& mesh) {
  return MaterialField::uniform(mesh.num_tets(), 5e9, 0.28, 2500);
}

Eigen::Vector3d centre(const Eigen::VectorXd& q) {
  return Eigen::Map<const Eigen::Matrix<double, 3, Eigen::Dynamic>>(q.data(), 3, q.size() / 3)
      .rowwise()
      .mean();
}

// The same bounce on z = 0 as a plane and as a square of two triangles (the contact patch stays
// 0.4 m from the square's diagonal and 0.6 m from its rim, so every active pair is a vertex over a
// triangle's interior, whose squared distance is that to the plane). The paths differ only by
// round-off: sqrt of the squared point-plane distance against n . x - c, and the barrier's
// Hessian assembled as f' grad^2 s + f'' grad s grad s^T instead of b'' n n^T, which Newton's
// tolerance (1e-10 x diagonal per second) then carries along.
TEST(MeshObstacles, BallOnTwoTrianglesFollowsTheAnalyticPlane) {
  Ball on_plane = ball(0.3, -0.3, 0.004, Eigen::Vector3d(0.4, 0.1, -2.0), 60);
  Ball on_mesh = on_plane;
  on_plane.settings.planes = {Plane{Eigen::Vector3d::UnitZ(), 0.0}};
  on_mesh.settings.obstacle_meshes = {test::square_obstacle(1.0)};
  Simulator a(on_plane.mesh, stiff(on_plane.mesh), on_plane.settings);
  Simulator b(on_mesh.mesh, stiff(on_mesh.mesh), on_mesh.settings);
  const Trajectory ta = a.run(on_plane.q0, on_plane.v0);
  const Trajectory tb = b.run(on_mesh.q0, on_mesh.v0);
  EXPECT_EQ(test::first_intersection(on_plane.mesh, on_plane.settings, ta), "");
  EXPECT_EQ(test::first_intersection(on_mesh.mesh, on_mesh.settings, tb), "");
  double gap = 0, extent = 0, gap_all = 0;
  int contact_steps = 0;
  for (std::size_t k = 0; k < ta.q.size(); ++k) {
    gap = std::max(gap, (centre(ta.q[k]) - centre(tb.q[k])).norm());
    extent = std::max(extent, (centre(ta.q[k]) - centre(ta.q[0])).norm());
    gap_all = std::max(gap_all, (ta.q[k] - tb.q[k]).cwiseAbs().maxCoeff());
    if (k > 0) {
      contact_steps += ta.steps[k - 1].active_pairs > 0;
      EXPECT_EQ(ta.steps[k - 1].active_pairs, tb.steps[k - 1].active_pairs) << k;
    }
  }
  const double vz_out = (centre(ta.q.back()) - centre(ta.q[ta.q.size() - 2])).z();
  std::printf(
      "plane vs two triangles: %d contact steps, centre-of-mass gap %.2e m over a %.3f m path "
      "(%.1e relative), largest vertex gap %.2e m, final vz %.3f m/step\n",
      contact_steps, gap, extent, gap / extent, gap_all, vz_out);
  EXPECT_GE(contact_steps, 3);
  EXPECT_GT(vz_out, 0.0);         // it bounced
  EXPECT_LE(gap, 1e-6 * extent);  // issue 19's bar
}

// A ball thrown against a box's top edge and against its corner: at every stored step every body
// surface vertex / obstacle triangle, obstacle vertex / body triangle and edge-edge pair is at a
// positive distance and no edge of one crosses a triangle of the other.
TEST(MeshObstacles, BallStrikingABoxEdgeAndCornerNeverIntersects) {
  struct Case {
    const char* name;
    Eigen::Vector3d lo, hi, centre, velocity, spin;
  };
  // The corner (the origin) is struck by the inside of a face of the ball, head-on. Struck by a
  // vertex of the ball instead (its centre on the box's diagonal), the point-point pair's barrier
  // has a tangential curvature b'(d) / d (here ~ -1e9 kappa): the vertex wants to slide off the
  // corner, which projected Newton resolves only linearly (a 0.5 % growth per iteration, beyond
  // 100 iterations at this Newton tolerance); see the report of issue 19's mesh-obstacle step.
  const Eigen::Vector3d towards = Eigen::Vector3d(0.15, -0.1, -1.0).normalized();
  const std::vector<Case> cases = {{"edge",
                                    {-0.5, -0.5, -0.5},
                                    {0.0, 0.5, 0.0},
                                    {0.06, 0.0, 0.085},
                                    {-1.5, 0.0, -1.0},
                                    {3.0, -2.0, 1.0}},
                                   {"corner",
                                    {-0.5, -0.5, -0.5},
                                    {0.0, 0.0, 0.0},
                                    -0.104 * towards,
                                    1.5 * towards,
                                    Eigen::Vector3d::Zero()}};
  for (const Case& c : cases) {
    Ball b = ball(0.0, 0.0, 0.0, c.velocity, 50);
    b.mesh = test::ball_mesh(0.1, 3, c.centre);
    b.q0 = test::positions(b.mesh);
    b.v0 = rigid_velocities(b.q0, c.centre, c.velocity, c.spin);
    b.settings.obstacle_meshes = {test::box_obstacle(c.lo, c.hi)};
    Simulator sim(b.mesh, stiff(b.mesh), b.settings);
    const Trajectory t = sim.run(b.q0, b.v0);
    EXPECT_EQ(test::first_intersection(b.mesh, b.settings, t), "") << c.name;
    const MeshObstacleForm& form = *sim.mesh_obstacle_form();
    double closest = std::numeric_limits<double>::infinity();
    int contact_steps = 0;
    for (std::size_t k = 0; k < t.q.size(); ++k) {
      const ObstacleClearance cl = form.clearance(t.q[k], 0.05);
      EXPECT_FALSE(cl.intersecting) << c.name << " step " << k << ": " << cl.pair;
      EXPECT_GT(cl.distance, 0.0) << c.name << " step " << k;
      closest = std::min(closest, cl.distance);
      contact_steps += cl.distance < b.settings.d_hat;
      // Independently: no vertex of the ball inside the box.
      for (Eigen::Index v = 0; v < t.q[k].size() / 3; ++v) {
        const Eigen::Vector3d x = t.q[k].segment<3>(3 * v);
        EXPECT_FALSE((x.array() > c.lo.array()).all() && (x.array() < c.hi.array()).all())
            << c.name << " " << k;
      }
    }
    const Eigen::Vector3d v_out =
        (centre(t.q.back()) - centre(t.q[t.q.size() - 2])) / b.settings.time_step;
    std::printf(
        "box %s: %d steps within d_hat, closest %.3e m, outgoing velocity (%.3f, %.3f, %.3f) m/s\n",
        c.name, contact_steps, closest, v_out.x(), v_out.y(), v_out.z());
    EXPECT_GE(contact_steps, 2) << c.name;
    EXPECT_GT(v_out.z(), 0.0) << c.name;  // thrown down, deflected up
  }
}

// An obstacle mesh beyond the body's reach: the broad phase's first box test rejects it, no pair
// is ever evaluated, and the run is the planes-only run bit for bit.
TEST(MeshObstacles, AnObstacleOutOfReachChangesNothing) {
  Ball b = ball(0.05, -0.02, 0.004, Eigen::Vector3d(0.4, 0.1, -2.0), 12);
  b.settings.planes = {Plane{Eigen::Vector3d::UnitZ(), 0.0}};
  Ball far = b;
  far.settings.obstacle_meshes = {test::square_obstacle(1.0, -10.0)};
  const Trajectory ta = Simulator(b.mesh, stiff(b.mesh), b.settings).run(b.q0, b.v0);
  const Trajectory tb = Simulator(far.mesh, stiff(far.mesh), far.settings).run(far.q0, far.v0);
  ASSERT_EQ(ta.q.size(), tb.q.size());
  for (std::size_t k = 0; k < ta.q.size(); ++k)
    EXPECT_TRUE((ta.q[k].array() == tb.q[k].array()).all()) << k;
  EXPECT_EQ(test::first_intersection(far.mesh, far.settings, tb), "");  // ta is the same
}

TEST(MeshObstacles, AStartInsideOrOnAnObstacleIsRefused) {
  Ball b = ball(0.0, 0.0, 0.0, Eigen::Vector3d(0, 0, -1), 1);
  b.mesh = test::ball_mesh(0.1, 3, Eigen::Vector3d(0, 0, 0.05));  // its lower half below z = 0
  b.q0 = test::positions(b.mesh);
  b.v0 = Eigen::VectorXd::Zero(b.q0.size());
  b.settings.obstacle_meshes = {
      test::box_obstacle(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 0))};
  b.settings.obstacle_meshes[0].name = "obstacles.meshes[0] (box.obj)";
  EXPECT_NE(test::first_intersection(b.mesh, b.settings, b.q0), "");  // the exact check agrees
  Simulator sim(b.mesh, stiff(b.mesh), b.settings);
  try {
    sim.reset(b.q0, b.v0);
    FAIL() << "a ball half inside a box was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("intersecting"), std::string::npos) << what;
    EXPECT_NE(what.find("obstacles.meshes[0] (box.obj)"), std::string::npos) << what;
  }
  // No kappa with obstacle meshes is a settings error.
  b.settings.kappa = 0;
  EXPECT_THROW(Simulator(b.mesh, stiff(b.mesh), b.settings), InputError);
}

}  // namespace
}  // namespace rbaa
