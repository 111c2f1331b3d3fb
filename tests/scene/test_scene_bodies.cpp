// bodies: further bodies besides the object, each with its mesh, initial state and fixed
// material; stacked after the object into one mesh (SceneWorld); bad input a one-line error
// naming the key; a body starting in an obstacle refused naming it; the fingerprint sees them.

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <string>

#include "rbaa/error.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/scene/scene.hpp"
#include "rbaa/scene/scene_fingerprint.hpp"
#include "rbaa/scene/scene_mesh.hpp"
#include "rbaa/scene/scene_world.hpp"
#include "scene/scene_errors.hpp"

namespace rbaa {
namespace {

// Two cubes 0.2 m apart along x, the second one spinning, on no obstacle, without gravity.
std::string two_cubes(const std::string& extra = "") {
  return "mesh: {shape: cube, side: 0.1, target_tets: 300}\n"
         "object: {position: [0, 0, 0], velocity: [1, 0, 0]}\n"
         "gravity: off\n"
         "bodies:\n"
         "  - name: second\n"
         "    mesh: {shape: cube, side: 0.05, target_tets: 100}\n"
         "    position: [0.2, 0.01, 0]\n"
         "    velocity: [-1, 0, 0]\n"
         "    angular_velocity: [0, 0, 3]\n" +
         extra;
}


TEST(SceneBodies, AreStackedAfterTheObjectWithTheirOwnPlacementAndMotion) {
  const Scene s = parse_scene(two_cubes(), "test.yaml", "");
  ASSERT_EQ(s.bodies.size(), 1u);
  EXPECT_EQ(s.bodies[0].name, "second");
  const TetMesh object = make_scene_mesh(s);
  const SceneWorld w = make_world(s, object);
  ASSERT_EQ(w.bodies.size(), 2u);
  const Body& a = w.bodies[0];
  const Body& b = w.bodies[1];
  EXPECT_EQ(a.vertex_begin, 0);
  EXPECT_EQ(a.vertex_end, object.num_vertices());
  EXPECT_EQ(b.vertex_begin, a.vertex_end);
  EXPECT_EQ(b.vertex_end, w.mesh.num_vertices());
  EXPECT_EQ(b.element_begin, a.element_end);
  EXPECT_EQ(b.element_end, w.mesh.num_tets());
  // The second body's elements index its own vertices only.
  EXPECT_GE(w.mesh.T.bottomRows(b.num_elements()).minCoeff(), b.vertex_begin);
  // Its centre of mass is at its position; its side is 0.05 m.
  TetMesh second;
  second.V = w.mesh.V.middleRows(b.vertex_begin, b.num_vertices());
  second.T = w.mesh.T.bottomRows(b.num_elements()).array() - b.vertex_begin;
  const Moments m = compute_moments(second, 1.0);
  EXPECT_LT((m.centre_of_mass() - Eigen::Vector3d(0.2, 0.01, 0)).norm(), 1e-12);
  EXPECT_NEAR((second.V.colwise().maxCoeff() - second.V.colwise().minCoeff()).maxCoeff(), 0.05, 1e-12);
  EXPECT_EQ(b.velocity, Eigen::Vector3d(-1, 0, 0));
  EXPECT_EQ(b.angular_velocity, Eigen::Vector3d(0, 0, 3));
  // Initial velocities: each body's rigid motion about its own centre.
  const Eigen::VectorXd q0 = Eigen::Map<const Eigen::VectorXd>(w.mesh.V.data(), 3 * w.mesh.num_vertices());
  const Eigen::VectorXd v0 = initial_velocities(q0, w.bodies);
  EXPECT_EQ(v0.segment<3>(0), Eigen::Vector3d(1, 0, 0));
  const int v = b.vertex_begin;
  const Eigen::Vector3d expected =
      Eigen::Vector3d(-1, 0, 0) + Eigen::Vector3d(0, 0, 3).cross(q0.segment<3>(3 * v) - b.centre);
  EXPECT_LT((v0.segment<3>(3 * v) - expected).norm(), 1e-15);
  // The fixed materials are the reference material; the object's come first.
  const MaterialField all = w.materials(MaterialField::uniform(object.num_tets(), 1e9, 0.3, 1000));
  ASSERT_EQ(all.size(), w.mesh.num_tets());
  EXPECT_EQ(all.Y[0], 1e9);
  EXPECT_EQ(all.Y[b.element_begin], s.reference_Y);
  EXPECT_EQ(all.rho[w.mesh.num_tets() - 1], s.reference_rho);
}

TEST(SceneBodies, ASceneWithoutBodiesIsTheObjectAlone) {
  const Scene s = parse_scene("mesh: {shape: cube, target_tets: 100}\nobject: {velocity: [1, 0, 0]}\n",
                              "test.yaml", "");
  const TetMesh object = make_scene_mesh(s);
  const SceneWorld w = make_world(s, object);
  ASSERT_EQ(w.bodies.size(), 1u);
  EXPECT_EQ(w.mesh.V, object.V);
  EXPECT_EQ(w.mesh.T, object.T);
  EXPECT_EQ(w.fixed_materials.size(), 0);
}

TEST(SceneBodies, BadBodiesAreRefusedInOneLineNamingTheKey) {
  const std::string dup = test::scene_world_error(two_cubes("  - name: second\n    mesh: {shape: cube}\n    position: [1, 0, 0]\n"));
  EXPECT_NE(dup.find("bodies[1].name"), std::string::npos) << dup;
  EXPECT_NE(dup.find("'second' names two bodies"), std::string::npos) << dup;
  const std::string object_name = test::scene_world_error(two_cubes("  - name: object\n    mesh: {shape: cube}\n"));
  EXPECT_NE(object_name.find("'object' names two bodies"), std::string::npos) << object_name;
  const std::string no_mesh = test::scene_world_error(two_cubes("  - position: [1, 0, 0]\n"));
  EXPECT_NE(no_mesh.find("bodies[1].mesh"), std::string::npos) << no_mesh;
  const std::string two_sources =
      test::scene_world_error(two_cubes("  - mesh: {shape: cube, file: x.msh}\n    position: [1, 0, 0]\n"));
  EXPECT_NE(two_sources.find("bodies[1].mesh"), std::string::npos) << two_sources;
  EXPECT_NE(two_sources.find("exactly one of shape, surface, file"), std::string::npos) << two_sources;
  const std::string unknown = test::scene_world_error(two_cubes("  - mesh: {shape: cube}\n    colour: red\n"));
  EXPECT_NE(unknown.find("bodies[1].colour"), std::string::npos) << unknown;
  const std::string not_a_list = test::scene_world_error("mesh: {shape: cube}\nbodies: {name: x}\n");
  EXPECT_NE(not_a_list.find("expected a list of bodies"), std::string::npos) << not_a_list;
  const std::string bad_rotation =
      test::scene_world_error(two_cubes("  - mesh: {shape: cube}\n    position: [1, 0, 0]\n    rotation: {axis: [0, 0, 0], angle_deg: 10}\n"));
  EXPECT_NE(bad_rotation.find("bodies[1].rotation.axis"), std::string::npos) << bad_rotation;
  for (const std::string& e : {dup, object_name, no_mesh, two_sources, unknown, not_a_list, bad_rotation}) {
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    EXPECT_EQ(e.rfind("test.yaml", 0), 0u) << e;
  }
}

TEST(SceneBodies, ABodyStartingOnAPlaneIsRefusedNamingIt) {
  const std::string e = test::scene_world_error(two_cubes("obstacles: {planes: [{normal: [0, 0, 1], offset: -0.02}]}\n"
                                           "contact: {kappa: 1}\n"));
  // The object (side 0.1, centred at 0) crosses z = -0.02 first; move it up to reach the body.
  EXPECT_NE(e.find("the object starts intersecting obstacles.planes[0]"), std::string::npos) << e;
  const std::string b = test::scene_world_error(
      "mesh: {shape: cube, side: 0.1, target_tets: 100}\nobject: {position: [0, 0, 1]}\n"
      "obstacles: {planes: [{normal: [0, 0, 1], offset: 0}]}\ncontact: {kappa: 1}\n"
      "bodies: [{name: low, mesh: {shape: cube, side: 0.1}, position: [1, 0, 0.04]}]\n");
  EXPECT_NE(b.find("body 'low' starts intersecting obstacles.planes[0]"), std::string::npos) << b;
  EXPECT_EQ(b.find('\n'), std::string::npos) << b;
}

TEST(SceneBodies, TheFingerprintSeesEveryBody) {
  const Scene a = parse_scene(two_cubes(), "test.yaml", "");
  std::string faster = two_cubes();
  faster.replace(faster.find("velocity: [-1"), 13, "velocity: [-2");
  const Scene b = parse_scene(faster, "test.yaml", "");
  const Scene c = parse_scene("mesh: {shape: cube, side: 0.1, target_tets: 300}\n"
                              "object: {position: [0, 0, 0], velocity: [1, 0, 0]}\ngravity: off\n",
                              "test.yaml", "");
  EXPECT_NE(scene_fingerprint(a), scene_fingerprint(b));
  EXPECT_NE(scene_fingerprint(a), scene_fingerprint(c));
}

}  // namespace
}  // namespace rbaa

namespace rbaa {
namespace {

// Friction keys: per plane, the contact default, the smoothing speed; bad values in one line.
TEST(SceneFriction, PlanesTakeTheirOwnCoefficientOrTheContactDefault) {
  const Scene s = parse_scene(
      "mesh: {shape: cube}\nobstacles: {planes: [{normal: [0, 0, 1], offset: -1, friction: 0.7},"
      " {normal: [1, 0, 0], offset: -1}]}\ncontact: {friction: 0.3, friction_eps_v: 0.01}\n",
      "test.yaml", "");
  ASSERT_EQ(s.planes.size(), 2u);
  EXPECT_EQ(s.planes[0].friction, 0.7);
  EXPECT_EQ(s.planes[1].friction, 0.3);
  EXPECT_EQ(s.friction_eps_v, 0.01);
  EXPECT_EQ(simulation_settings(s, 1.0).friction_eps_v, 0.01);
  const std::string negative = test::scene_world_error(
      "mesh: {shape: cube}\nobstacles: {planes: [{normal: [0, 0, 1], offset: -1, friction: -0.1}]}\n");
  EXPECT_NE(negative.find("obstacles.planes[0].friction"), std::string::npos) << negative;
  const std::string eps = test::scene_world_error("mesh: {shape: cube}\ncontact: {friction_eps_v: 0}\n");
  EXPECT_NE(eps.find("contact.friction_eps_v"), std::string::npos) << eps;
  const std::string mu = test::scene_world_error("mesh: {shape: cube}\ncontact: {friction: -1}\n");
  EXPECT_NE(mu.find("contact.friction"), std::string::npos) << mu;
  for (const std::string& e : {negative, eps, mu}) {
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    EXPECT_EQ(e.rfind("test.yaml", 0), 0u) << e;
  }
}

// contact.pairs: coefficients between named bodies over contact.friction's default, into the
// settings' symmetric matrix; bad pairs refused in one line naming the key.
TEST(SceneFriction, PairsOfBodiesTakeTheirOwnCoefficientOrTheContactDefault) {
  const std::string three = two_cubes(
      "  - name: third\n"
      "    mesh: {shape: cube, side: 0.05, target_tets: 100}\n"
      "    position: [0, 0.3, 0]\n");
  const Scene s = parse_scene(three +
                                  "contact:\n  friction: 0.2\n  pairs:\n"
                                  "    - {bodies: [second, object], friction: 0.6}\n"
                                  "    - {bodies: [third, second], friction: 0}\n",
                              "test.yaml", "");
  const Eigen::MatrixXd mu = simulation_settings(s, 1.0).body_friction;
  ASSERT_EQ(mu.rows(), 3);
  ASSERT_EQ(mu.cols(), 3);
  EXPECT_EQ(mu(0, 1), 0.6);
  EXPECT_EQ(mu(1, 0), 0.6);
  EXPECT_EQ(mu(0, 2), 0.2);  // object - third: the default
  EXPECT_EQ(mu(2, 1), 0.0);
  EXPECT_EQ(mu(1, 1), 0.0);
  // No further bodies: nothing between bodies.
  const Scene alone =
      parse_scene("mesh: {shape: cube}\ncontact: {friction: 0.2}\n", "test.yaml", "");
  EXPECT_EQ(body_friction(alone).size(), 0);
  // The fingerprint sees friction between bodies, and only when there is some.
  const Scene none = parse_scene(two_cubes(), "test.yaml", "");
  const Scene zero = parse_scene(
      two_cubes("contact: {pairs: [{bodies: [object, second], friction: 0}]}\n"), "test.yaml", "");
  EXPECT_EQ(scene_fingerprint_text(none), scene_fingerprint_text(zero));
  EXPECT_NE(scene_fingerprint(none), scene_fingerprint(s));
  const std::vector<std::pair<std::string, std::vector<std::string>>> bad = {
      {"contact: {pairs: [{bodies: [object, second], friction: -0.4}]}",
       {"key 'contact.pairs[0].friction'", "outside [0, inf]"}},
      {"contact: {pairs: [{bodies: [object, fourth], friction: 0.4}]}",
       {"key 'contact.pairs[0].bodies'", "'fourth' names no body (bodies: object, second)"}},
      {"contact: {pairs: [{bodies: [second, second], friction: 0.4}]}",
       {"key 'contact.pairs[0].bodies'", "itself"}},
      {"contact: {pairs: [{bodies: [object], friction: 0.4}]}",
       {"key 'contact.pairs[0].bodies'", "two body names"}},
      {"contact: {pairs: [{bodies: [object, second]}]}",
       {"key 'contact.pairs[0].friction'", "missing"}},
      {"contact: {pairs: [{bodies: [object, second], friction: 0.1}, {bodies: [second, object], "
       "friction: 0.2}]}",
       {"key 'contact.pairs[1].bodies'", "listed twice"}},
      {"contact: {pairs: [{bodies: [object, second], mu: 0.1}]}",
       {"contact.pairs[0]", "mu", "unknown key"}},
  };
  for (const auto& [yaml, fragments] : bad) {
    const std::string e = test::scene_world_error(two_cubes(yaml + "\n"));
    for (const std::string& f : fragments) {
      EXPECT_NE(e.find(f), std::string::npos) << yaml << "\n -> " << e;
    }
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    EXPECT_EQ(e.rfind("test.yaml", 0), 0u) << e;
  }
}


// swap_object puts a further body in the object's place (rbaa evaluate and export, for an attack
// on attack.body): the same world with the two bodies' blocks traded, pairs' coefficients
// following their bodies, kappa frozen at the original object's; swapping back
// gives the original scene's world bit for bit.
TEST(SceneBodies, SwapObjectPutsABodyInTheObjectsPlaceAndBack) {
  const std::string three = two_cubes(
      "  - name: third\n"
      "    mesh: {shape: cube, side: 0.05, target_tets: 100}\n"
      "    position: [0, 0.3, 0]\n"
      "    rotation: {axis: [0, 0, 1], angle_deg: 30}\n"
      "contact:\n  friction: 0.2\n  pairs:\n"
      "    - {bodies: [third, object], friction: 0.6}\n"
      "    - {bodies: [third, second], friction: 0.1}\n");
  const Scene s = parse_scene(three, "test.yaml", "");
  const Scene t = swap_object(s, "third");
  EXPECT_EQ(t.object_name, "third");
  EXPECT_EQ(body_name(t, 0), "third");
  EXPECT_EQ(body_name(t, 2), "object");
  EXPECT_EQ(t.kappa, scene_barrier_stiffness(s, make_scene_mesh(s)));
  ASSERT_GT(t.kappa, 0);
  const SceneWorld w = make_world(s, make_scene_mesh(s));
  const SceneWorld u = make_world(t, make_scene_mesh(t));
  ASSERT_EQ(u.bodies.size(), 3u);
  // World index k of s is index perm[k] of t.
  const int perm[3] = {2, 1, 0};
  for (int k = 0; k < 3; ++k) {
    const Body& a = w.bodies[k];
    const Body& b = u.bodies[perm[k]];
    ASSERT_EQ(a.num_vertices(), b.num_vertices()) << k;
    ASSERT_EQ(a.num_elements(), b.num_elements()) << k;
    EXPECT_EQ(w.mesh.V.middleRows(a.vertex_begin, a.num_vertices()),
              u.mesh.V.middleRows(b.vertex_begin, b.num_vertices()))
        << k;
    EXPECT_EQ(a.velocity, b.velocity) << k;
    EXPECT_EQ(a.angular_velocity, b.angular_velocity) << k;
    EXPECT_EQ(a.centre, b.centre) << k;
  }
  const Eigen::MatrixXd mu = body_friction(s), nu = body_friction(t);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) EXPECT_EQ(mu(i, j), nu(perm[i], perm[j])) << i << ", " << j;
  }
  EXPECT_EQ(mu(0, 2), 0.6);
  // Back: the original world, bit for bit; evaluation.body naming the object comes back empty.
  Scene back = swap_object(t, "object");
  EXPECT_EQ(back.object_name, "object");
  const SceneWorld v = make_world(back, make_scene_mesh(back));
  EXPECT_EQ(v.mesh.V, w.mesh.V);
  EXPECT_EQ(v.mesh.T, w.mesh.T);
  EXPECT_EQ(body_friction(back), mu);
  // The object itself: the scene unchanged.
  EXPECT_EQ(swap_object(s, "object").object_name, "object");
  EXPECT_EQ(swap_object(s, "object").bodies[1].name, "third");
}

TEST(SceneBodies, SwapObjectRefusesAMissingBodyAndOneWithAMaterialsFile) {
  const Scene s = parse_scene(two_cubes(), "test.yaml", "");
  try {
    swap_object(s, "fourth");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "test.yaml: no body named 'fourth' to put in the object's place");
  }
  Scene with_file = s;
  with_file.bodies[0].materials_file = "second.msh";
  try {
    swap_object(with_file, "second");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("body 'second' has a materials file (second.msh)"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace rbaa
