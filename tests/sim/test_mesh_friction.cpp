// Friction on mesh pairs in simulation does what Coulomb says (pair_friction_form.hpp): a box
// sliding on a two-triangle floor decelerates at mu g (within 2 %) along the same path as on the
// analytic plane with the same mu; on a tilted two-triangle incline it sticks at mu = 1.1
// tan(theta) (creeping as the smoothing says) and slides at g (sin - mu cos) at mu = 0.9
// tan(theta); a box sliding on a slab that rests on a plane decelerates relative to it at mu g,
// the box-slab friction forces summing to zero at every step. No step ever brings two surfaces
// into contact or crossing.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>

#include "mesh_fixtures.hpp"
#include "obstacle_fixtures.hpp"
#include "rbaa/sim/observables.hpp"
#include "rbaa/sim/simulator.hpp"
#include "support/intersection_free.hpp"

namespace rbaa {
namespace {

struct Slide {
  std::vector<double> time;
  std::vector<Eigen::Vector3d> centre, velocity;  // centre of mass, BDF velocity
  double min_distance = 1;
  bool crossing = false;
  std::string intersection;  // the exact check's first finding ("" none)
  int lagged_steps = 0;  // steps with lagged mesh-friction pairs
};

// Least-squares slope of v . e over positions [from, to].
double acceleration(const std::vector<double>& t, const std::vector<Eigen::Vector3d>& v,
                    const Eigen::Vector3d& e, int from, int to) {
  double st = 0, sv = 0, stt = 0, stv = 0;
  const int n = to - from + 1;
  for (int k = from; k <= to; ++k) {
    st += t[k];
    sv += v[k].dot(e);
    stt += t[k] * t[k];
    stv += t[k] * v[k].dot(e);
  }
  return (n * stv - st * sv) / (n * stt - st * st);
}

// A 0.1 m box of 1 kg (Y = 1e8) starting 0.5 d_hat above the floor z = 0 at (0.3, -0.3), well
// off the two-triangle square's diagonal, with velocity v0: test_friction.cpp's box, on the
// analytic plane or on the square. `R` turns box, floor and gravity's frame together (an incline).
Slide slide(bool on_mesh, double mu, const Eigen::Vector3d& v0, int steps, double h = 2e-3,
            const Eigen::Matrix3d& R = Eigen::Matrix3d::Identity()) {
  TetMesh mesh = test::lifted(test::box_mesh(2, 2, 2, 0.05, Eigen::Vector3d(0.3, -0.3, 0)), 5e-4);
  for (int v = 0; v < mesh.num_vertices(); ++v)
    mesh.V.row(v) = (R * mesh.V.row(v).transpose()).transpose();
  SimulationSettings s;
  s.time_step = h;
  s.num_steps = steps;
  s.d_hat = 1e-3;
  s.kappa = 1e3;  // rests near 0.5 d_hat
  if (on_mesh) {
    ObstacleMesh floor = test::square_obstacle(1.0);
    for (Eigen::Index v = 0; v < floor.V.rows(); ++v)
      floor.V.row(v) = (R * floor.V.row(v).transpose()).transpose();
    floor.friction = mu;
    s.obstacle_meshes = {floor};
  } else {
    Plane floor;
    floor.normal = R * Eigen::Vector3d::UnitZ();
    floor.friction = mu;
    s.planes = {floor};
  }
  Simulator sim(mesh, MaterialField::uniform(mesh.num_tets(), 1e8, 0.3, 1000), s);
  const Eigen::VectorXd q0 = test::positions(mesh);
  Slide r;
  const Trajectory t =
      sim.run(q0, rigid_velocities(q0, Eigen::Vector3d::Zero(), v0, Eigen::Vector3d::Zero()),
              [&](int, const Eigen::VectorXd&, const StepStats&) {
                if (sim.pair_friction_form()) {
                  r.lagged_steps += sim.pair_friction_form()->num_lagged_pairs() > 0;
                }
              });
  r.intersection = test::first_intersection(mesh, s, t);
  for (int k = 0; k <= steps; ++k) {
    r.time.push_back(t.time(k));
    r.centre.push_back(centre_of_mass(t.q[k], sim.vertex_masses()));
    r.velocity.push_back(centre_of_mass(t.velocity(k), sim.vertex_masses()));
    if (on_mesh) {
      const ObstacleClearance c = sim.mesh_obstacle_form()->clearance(t.q[k], 0.01);
      r.min_distance = std::min(r.min_distance, c.distance);
      r.crossing = r.crossing || c.intersecting;
    } else {
      r.min_distance = std::min(r.min_distance, test::min_vertex_plane_distance(t.q[k], s.planes));
    }
  }
  return r;
}

TEST(MeshFriction, ABoxSlidingOnAMeshFloorDeceleratesAtMuGAlongThePlanesPath) {
  const double mu = 0.4, g = 9.8;
  const Slide mesh = slide(true, mu, Eigen::Vector3d(1, 0, 0), 100);
  const Slide plane = slide(false, mu, Eigen::Vector3d(1, 0, 0), 100);
  const double a = acceleration(mesh.time, mesh.velocity, Eigen::Vector3d::UnitX(), 25, 100);
  double gap = 0, extent = 0;
  for (std::size_t k = 0; k < mesh.centre.size(); ++k) {
    gap = std::max(gap, (mesh.centre[k] - plane.centre[k]).norm());
    extent = std::max(extent, (plane.centre[k] - plane.centre[0]).norm());
  }
  std::printf(
      "box on a mesh floor, mu %.2f: deceleration %.5f m/s^2 (mu g %.5f, %.3f %%); "
      "centre-of-mass gap to the plane's path %.2e m over a %.3f m path (%.1e relative); "
      "friction lagged in %d of 100 steps; closest %.3e m\n",
      mu, -a, mu * g, 100 * (-a / (mu * g) - 1), gap, extent, gap / extent, mesh.lagged_steps,
      mesh.min_distance);
  EXPECT_NEAR(-a, mu * g, 0.02 * mu * g);
  EXPECT_GE(mesh.lagged_steps, 99);
  EXPECT_LE(gap, 1e-6 * extent);  // issue 19's bar for the frictionless landing, kept here
  EXPECT_GT(mesh.min_distance, 0);
  EXPECT_FALSE(mesh.crossing);
  EXPECT_EQ(mesh.intersection, "");
  EXPECT_EQ(plane.intersection, "");
}

TEST(MeshFriction, ABoxOnAMeshInclineSticksOrSlidesAsCoulombSays) {
  const double theta = 20.0 * M_PI / 180.0, g = 9.8;
  // Box and floor turned by theta about y: downhill is R e_x, gravity stays (0, 0, -g).
  const Eigen::Matrix3d R = Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Vector3d downhill = R * Eigen::Vector3d::UnitX();
  ASSERT_LT(downhill.z(), 0);
  const double eps_v = 1e-3;  // SimulationSettings' default
  // h = 1e-2 as in test_friction.cpp: BDF-2 damps the box's ringing on the barrier there; at 2e-3
  // it rings for the whole second, lifting off and slipping in every cycle.
  const double H = 1e-2;
  const Slide stick = slide(true, 1.1 * std::tan(theta), Eigen::Vector3d::Zero(), 100, H, R);
  const double creep = stick.velocity.back().norm();
  const double creep_expected = eps_v * (1 - std::sqrt(1 - 1 / 1.1));
  const double mu = 0.9 * std::tan(theta);
  const Slide slip = slide(true, mu, Eigen::Vector3d::Zero(), 100, H, R);
  const double a = acceleration(slip.time, slip.velocity, downhill, 25, 100);
  const double expected = g * (std::sin(theta) - mu * std::cos(theta));
  std::printf(
      "mesh incline %.0f deg: mu 1.1 tan creeps at %.4e m/s after 1 s (smoothing says "
      "%.4e); mu 0.9 tan accelerates at %.5f m/s^2 (expected %.5f, %.3f %%)\n",
      theta * 180 / M_PI, creep, creep_expected, a, expected, 100 * (a / expected - 1));
  EXPECT_NEAR(creep, creep_expected, 0.01 * creep_expected);
  EXPECT_NEAR(a, expected, 0.03 * expected);
  EXPECT_GT(slip.velocity.back().dot(downhill), 50 * eps_v);
  for (const Slide* s : {&stick, &slip}) {
    EXPECT_GT(s->min_distance, 0);
    EXPECT_FALSE(s->crossing);
    EXPECT_EQ(s->intersection, "");
  }
}

// A 0.4 x 0.15 x 0.05 slab (3 kg) resting on the plane z = 0 (mu 1: it holds the slab against
// the box's drag), and on it the 1 kg box of the tests above, turned by 7 deg about z (its edges
// cross the slab's rather than running along them) and thrown along the slab at 1 m/s.
TEST(MeshFriction, ABoxSlidingOnASlabDeceleratesRelativeToItAtMuG) {
  const double mu = 0.4, g = 9.8, d_hat = 1e-3;
  const TetMesh slab = test::box_mesh(8, 3, 1, 0.05, Eigen::Vector3d(0, 0, 0.5 * d_hat));
  TetMesh box = test::box_mesh(2, 2, 2, 0.05, Eigen::Vector3d(-0.05, -0.05, 0));
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(7 * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d box_centre(0.08, 0.0762, 0.05 + 1.1 * d_hat + 0.05);
  for (int v = 0; v < box.num_vertices(); ++v) {
    box.V.row(v) =
        (R * box.V.row(v).transpose() + box_centre - Eigen::Vector3d(0, 0, 0.05)).transpose();
  }
  TetMesh mesh;
  mesh.V.resize(slab.num_vertices() + box.num_vertices(), 3);
  mesh.V << slab.V, box.V;
  mesh.T.resize(slab.num_tets() + box.num_tets(), 4);
  mesh.T << slab.T, (box.T.array() + slab.num_vertices()).matrix();
  Body S, B;
  S.name = "slab";
  S.vertex_end = slab.num_vertices();
  S.element_end = slab.num_tets();
  S.centre = Eigen::Vector3d(0.2, 0.075, 0.025 + 0.5 * d_hat);
  B.name = "box";
  B.vertex_begin = S.vertex_end;
  B.vertex_end = mesh.num_vertices();
  B.element_begin = S.element_end;
  B.element_end = mesh.num_tets();
  B.centre = box_centre;
  B.velocity = Eigen::Vector3d(1, 0, 0);
  SimulationSettings s;
  s.time_step = 2e-3;
  s.num_steps = 100;
  s.d_hat = d_hat;
  s.kappa = 1e3;
  Plane floor;
  floor.friction = 1.0;
  s.planes = {floor};
  s.bodies = {S, B};
  s.body_friction = Eigen::MatrixXd::Zero(2, 2);
  s.body_friction(0, 1) = s.body_friction(1, 0) = mu;
  Simulator sim(mesh, MaterialField::uniform(mesh.num_tets(), 1e8, 0.3, 1000), s);
  const Eigen::VectorXd q0 = test::positions(mesh);
  const Eigen::VectorXd m = sim.vertex_masses();
  const int nb = B.num_vertices(), ns = S.num_vertices();
  auto body_velocity = [&](const Eigen::VectorXd& v, const Body& b) {
    return centre_of_mass(v.segment(3 * b.vertex_begin, 3 * b.num_vertices()),
                          m.segment(b.vertex_begin, b.num_vertices()));
  };
  // Per step, the friction between the bodies at the new q: its sum over each body.
  double worst_imbalance = 0;
  int lagged_steps = 0;
  double closest = 1;
  bool crossing = false;
  const Trajectory t = sim.run(
      q0, initial_velocities(q0, s.bodies),
      [&](int step, const Eigen::VectorXd& q, const StepStats&) {
        PairFrictionForm* f = sim.pair_friction_form();
        if (f->num_lagged_pairs() == 0) return;
        ++lagged_steps;
        Eigen::VectorXd gr = Eigen::VectorXd::Zero(q.size());
        f->add_gradient(q, 1.0, gr);
        const Eigen::Vector3d on_slab =
            Eigen::Map<const Eigen::Matrix3Xd>(gr.data(), 3, ns).rowwise().sum();
        const Eigen::Vector3d on_box =
            Eigen::Map<const Eigen::Matrix3Xd>(gr.data() + 3 * ns, 3, nb).rowwise().sum();
        worst_imbalance = std::max(worst_imbalance, (on_slab + on_box).norm() / on_box.norm());
        const BodyClearance c = sim.body_contact_form()->clearance(q, 0.01);
        closest = std::min(closest, c.distance);
        crossing = crossing || c.intersecting;
      });
  std::vector<double> time;
  std::vector<Eigen::Vector3d> relative;
  for (int k = 0; k <= s.num_steps; ++k) {
    time.push_back(t.time(k));
    relative.push_back(body_velocity(t.velocity(k), B) - body_velocity(t.velocity(k), S));
  }
  const double a = acceleration(time, relative, Eigen::Vector3d::UnitX(), 25, 100);
  // The box rings on the slab (the sum of its pairs' normal forces swings between ~1 and ~36 N
  // every ~20 steps), so the friction force at a step says little; its impulse over the window
  // is mu times the normal impulse, which averages to m g.
  std::printf(
      "box on a slab, mu %.2f: relative deceleration %.5f m/s^2 (mu g %.5f, %.3f %%); "
      "slab at %.2e m/s along x at the end; box-slab friction sums to %.1e of itself at "
      "worst over %d steps; closest %.3e m\n",
      mu, -a, mu * g, 100 * (-a / (mu * g) - 1), body_velocity(t.velocity(s.num_steps), S).x(),
      worst_imbalance, lagged_steps, closest);
  EXPECT_NEAR(-a, mu * g, 0.02 * mu * g);
  EXPECT_GE(lagged_steps, 99);
  EXPECT_LT(worst_imbalance, 1e-12);
  EXPECT_GT(closest, 0);
  EXPECT_FALSE(crossing);
  EXPECT_EQ(test::first_intersection(mesh, s, t), "");
}

}  // namespace
}  // namespace rbaa
