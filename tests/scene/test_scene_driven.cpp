// driven: a body's kinematic (Dirichlet) vertices in a config (DriveSpec, scene.hpp): a listed or
// selected set (the N farthest along a direction of the body's own frame, the end slab within a
// depth, or the slab's N nearest the body's axis), the drive's motion, the body starting with it;
// bad input a one-line error naming the key and the value; the fingerprint sees the drive; a
// driven scene simulates with its vertices on their prescribed path.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <string>

#include "rbaa/error.hpp"
#include "rbaa/scene/scene.hpp"
#include "rbaa/scene/scene_fingerprint.hpp"
#include "rbaa/scene/scene_mesh.hpp"
#include "rbaa/scene/scene_world.hpp"
#include "rbaa/scene/simulate.hpp"
#include "scene/scene_errors.hpp"

namespace rbaa {
namespace {

// A 0.1 m cube turned 90 degrees about x (its own -z end faces world +y), driven about the world
// z axis through (0, -0.2, 0) at 2 rad/s while that axis moves at 0.5 m/s along x; no gravity.
std::string driven_cube(const std::string& vertices, const std::string& extra = "") {
  return "mesh: {shape: cube, side: 0.1, target_tets: 300}\n"
         "object:\n"
         "  position: [0, 0, 0.3]\n"
         "  rotation: {axis: [1, 0, 0], angle_deg: 90}\n"
         "  driven:\n"
         "    vertices: " +
         vertices +
         "\n"
         "    axis: [0, 0, 2]\n"
         "    centre: [0, -0.2, 0]\n"
         "    angular_velocity: 2.0\n"
         "    velocity: [0.5, 0, 0]\n" +
         extra +
         "gravity: off\n"
         "contact: {kappa: 1000}\n"
         "time: {step: 0.01, duration: 0.05}\n"
         "reference_material: {Y: 1.0e8, nu: 0.3, rho: 1000}\n";
}

struct World {
  Scene scene;
  SceneWorld world;
};

World world_of(const std::string& yaml) {
  World w;
  w.scene = parse_scene(yaml, "test.yaml", "");
  w.world = make_world(w.scene, make_scene_mesh(w.scene));
  return w;
}


// World y of the object's vertices (its own -z direction after the rotation).
Eigen::VectorXd world_y(const SceneWorld& w) { return w.mesh.V.col(1); }

TEST(SceneDriven, AListNamesBodyLocalVerticesAndTheBodyStartsWithTheDrivesMotion) {
  const World w = world_of(driven_cube("[7, 0, 3]"));
  const Body& b = w.world.bodies.front();
  EXPECT_EQ(b.driven_vertices, (std::vector<int>{0, 3, 7}));
  EXPECT_EQ(b.drive.axis, Eigen::Vector3d(0, 0, 1));
  EXPECT_EQ(b.drive.centre, Eigen::Vector3d(0, -0.2, 0));
  EXPECT_EQ(b.drive.angular_velocity, 2.0);
  EXPECT_EQ(b.drive.velocity, Eigen::Vector3d(0.5, 0, 0));
  // Initial motion: the drive's rigid motion, v = v_axis + omega z x (x - centre).
  EXPECT_LT((b.velocity - Eigen::Vector3d(0.5 - 2.0 * 0.2, 0, 0)).norm(), 1e-15);
  EXPECT_EQ(b.angular_velocity, Eigen::Vector3d(0, 0, 2));
  const Eigen::VectorXd q0 =
      Eigen::Map<const Eigen::VectorXd>(w.world.mesh.V.data(), 3 * w.world.mesh.num_vertices());
  const Eigen::VectorXd v0 = initial_velocities(q0, w.world.bodies);
  for (int v = 0; v < w.world.mesh.num_vertices(); ++v) {
    EXPECT_LT((v0.segment<3>(3 * v) - b.drive.point_velocity(q0.segment<3>(3 * v), 0.0)).norm(),
              1e-14);
  }
  // A driven single object is simulated as a body (with its drive), not as the whole mesh.
  EXPECT_EQ(simulated_bodies(w.world).size(), 1u);
}

TEST(SceneDriven, SelectorsPickTheEndOfTheBodysOwnFrame) {
  // The 5 farthest along the body's own -z: the 5 largest world y.
  const World far = world_of(driven_cube("{toward: [0, 0, -1], count: 5}"));
  const std::vector<int>& ids = far.world.bodies.front().driven_vertices;
  ASSERT_EQ(ids.size(), 5u);
  const Eigen::VectorXd y = world_y(far.world);
  double lowest_selected = 1, highest_other = -1;
  for (int v = 0; v < y.size(); ++v) {
    const bool selected = std::find(ids.begin(), ids.end(), v) != ids.end();
    if (selected)
      lowest_selected = std::min(lowest_selected, y[v]);
    else
      highest_other = std::max(highest_other, y[v]);
  }
  EXPECT_GE(lowest_selected, highest_other);
  EXPECT_NEAR(y.maxCoeff(), 0.05, 1e-9);

  // The end slab: the whole face at world y = 0.05.
  const World slab = world_of(driven_cube("{toward: [0, 0, -1], depth: 1.0e-9}"));
  const std::vector<int>& face = slab.world.bodies.front().driven_vertices;
  int on_face = 0;
  for (int v = 0; v < y.size(); ++v) on_face += y[v] >= 0.05 - 1e-9;
  EXPECT_EQ(static_cast<int>(face.size()), on_face);
  EXPECT_GT(on_face, 8);

  // Of the slab, the 3 nearest the body's axis (the world y line through its centre of mass).
  const World knob = world_of(driven_cube("{toward: [0, 0, -1], depth: 1.0e-9, count: 3}"));
  const std::vector<int>& near = knob.world.bodies.front().driven_vertices;
  ASSERT_EQ(near.size(), 3u);
  const Eigen::MatrixXd& V = knob.world.mesh.V;
  auto radius = [&](int v) { return std::hypot(V(v, 0) - 0.0, V(v, 2) - 0.3); };
  double farthest_selected = 0;
  for (int v : near) {
    EXPECT_GE(y[v], 0.05 - 1e-9);
    farthest_selected = std::max(farthest_selected, radius(v));
  }
  for (int v : face) {
    if (std::find(near.begin(), near.end(), v) == near.end()) {
      EXPECT_GE(radius(v), farthest_selected - 1e-12);  // ties at round-off
    }
  }
}

TEST(SceneDriven, AFurtherBodyCanBeDrivenAndATableGivesTheSpeed) {
  const std::string yaml =
      "mesh: {shape: sphere, radius: 0.03, target_tets: 200}\n"
      "object: {position: [0.3, 0, 0]}\n"
      "gravity: off\n"
      "bodies:\n"
      "  - name: bat\n"
      "    mesh: {shape: cube, side: 0.05, target_tets: 100}\n"
      "    position: [0, 0, 0]\n"
      "    driven: {vertices: {toward: [-1, 0, 0], count: 4}, angular_velocity: [[0, 0], [0.1, "
      "5]]}\n";
  const World w = world_of(yaml);
  ASSERT_EQ(w.world.bodies.size(), 2u);
  const Body& bat = w.world.bodies[1];
  ASSERT_EQ(bat.driven_vertices.size(), 4u);
  for (int v : bat.driven_vertices) {
    EXPECT_GE(v, bat.vertex_begin);
    EXPECT_NEAR(w.world.mesh.V(v, 0), -0.025, 1e-9);
  }
  EXPECT_EQ(bat.drive.angular_velocity_table.size(), 2u);
  EXPECT_NEAR(bat.drive.angle(0.1), 0.25, 1e-15);
  EXPECT_FALSE(w.world.bodies[0].is_driven());
}

TEST(SceneDriven, BadInputIsAOneLineErrorNamingTheKeyAndTheValue) {
  struct Case {
    std::string yaml, key, value;
    std::vector<std::string> overrides = {};
  };
  const std::vector<Case> cases = {
      {driven_cube("knob"), "object.driven.vertices", "'knob'"},
      {driven_cube("{toward: [0, 0, 1], count: 100000}"), "object.driven.vertices.count", "100000"},
      {driven_cube("{toward: [0, 0, 1], depth: 1.0e-9, count: 500}"),
       "object.driven.vertices.count", "500"},
      {driven_cube("{toward: [0, 0, 0], count: 3}"), "object.driven.vertices.toward", "zero"},
      {driven_cube("{toward: [0, 0, 1], cout: 3}"), "object.driven.vertices.cout", "unknown key"},
      {driven_cube("{toward: [0, 0, 1]}"), "object.driven.vertices", "give depth, count or both"},
      {driven_cube("[1, 2, 2]"), "object.driven.vertices", "vertex 2 is listed twice"},
      {driven_cube("[1, 100000]"), "object.driven.vertices", "vertex 100000"},
      {driven_cube("[1, 2.5]"), "object.driven.vertices", "2.5"},
      {driven_cube("[1]", "    spin: 3\n"), "object.driven.spin", "unknown key"},
      {driven_cube("[1]"), "object.driven.axis", "[0, 0, 0]", {"object.driven.axis=[0, 0, 0]"}},
      {driven_cube("[1]"),
       "object.driven.angular_velocity",
       "time 0 s",
       {"object.driven.angular_velocity=[[0, 1], [0, 2]]"}},
      {driven_cube("[1]"), "object.velocity", "driven body", {"object.velocity=[1, 0, 0]"}},
  };
  for (const Case& c : cases) {
    const std::string m = test::scene_world_error(c.yaml, c.overrides);
    EXPECT_NE(m.find("test.yaml"), std::string::npos) << c.key << ": " << m;
    EXPECT_NE(m.find("'" + c.key + "'"), std::string::npos) << c.key << ": " << m;
    EXPECT_NE(m.find(c.value), std::string::npos) << c.key << ": " << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

TEST(SceneDriven, TheFingerprintSeesTheDrive) {
  const std::string fp = scene_fingerprint(parse_scene(driven_cube("[1, 2]"), "a.yaml", ""));
  for (const std::string o :
       {"object.driven.vertices=[1, 3]", "object.driven.axis=[0, 1, 0]",
        "object.driven.centre=[0, 0, 0]", "object.driven.angular_velocity=3",
        "object.driven.angular_velocity=[[0, 2], [1, 3]]", "object.driven.velocity=[0, 0, 0]"}) {
    EXPECT_NE(scene_fingerprint(parse_scene(driven_cube("[1, 2]"), "a.yaml", "", {o})), fp) << o;
  }
}

TEST(SceneDriven, ADrivenSceneSimulatesWithItsVerticesOnTheirPath) {
  const Scene s = parse_scene(driven_cube("{toward: [0, 0, -1], depth: 1.0e-9}"), "test.yaml", "");
  const TetMesh mesh = make_scene_mesh(s);
  const SimulationRun run = run_simulation(
      s, mesh,
      MaterialField::uniform(mesh.num_tets(), s.reference_Y, s.reference_nu, s.reference_rho));
  const Body& b = run.settings.bodies.at(0);
  ASSERT_TRUE(b.is_driven());
  const Trajectory& t = run.trajectory;
  ASSERT_EQ(t.num_steps(), 5);
  double worst = 0;
  for (int k = 0; k <= t.num_steps(); ++k) {
    for (int v : b.driven_vertices) {
      const Eigen::Vector3d expected = b.drive.position(t.q[0].segment<3>(3 * v), k * t.time_step);
      worst = std::max(worst, (t.q[k].segment<3>(3 * v) - expected).norm());
    }
  }
  EXPECT_LE(worst, 1e-12);
  // The rest of the cube went along: its centre of mass moved with the drive.
  const Eigen::Vector3d c0 = run.observables.front().centre_of_mass,
                        cN = run.observables.back().centre_of_mass;
  const Eigen::Vector3d rigid = b.drive.position(c0, 0.05);
  EXPECT_LT((cN - rigid).norm(), 0.05 * (rigid - c0).norm());
  // The run's wall time (what `rbaa evaluate` reports per run) holds its set-up and every step.
  double steps = 0;
  for (const StepStats& st : t.steps) steps += st.seconds;
  EXPECT_GT(run.setup_seconds, 0.0);
  EXPECT_GE(run.simulate_seconds, steps);
  EXPECT_EQ(run.seconds(), run.setup_seconds + run.simulate_seconds);
}

}  // namespace
}  // namespace rbaa
