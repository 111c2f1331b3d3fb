// Driven (Dirichlet) vertices: they follow their prescribed motion exactly while the rest of their
// body deforms; they are not penalised but eliminated, so the drive exerts a reaction force, and
// the system's momentum changes by exactly the impulse of those reactions; a driven body starts
// carried by its drive (its BDF past is the drive's), so a uniformly spinning driven body feels the
// same force from the first step on; a prescribed step that would pass through an obstacle or
// another body is a one-line error naming the step and the body; one whose CCD its iteration cap
// stopped is checked again in pieces, and taken, or refused as uncertified, not as intersecting.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <string>

#include "driven_fixtures.hpp"
#include "obstacle_fixtures.hpp"
#include "rbaa/error.hpp"
#include "rbaa/sim/observables.hpp"
#include "rbaa/sim/simulator.hpp"
#include "support/intersection_free.hpp"

namespace rbaa {
namespace {

// The largest distance of a driven vertex from where its drive puts it at step k.
double follow_error(const test::DrivenScene& s, const Eigen::VectorXd& q, int k) {
  double worst = 0;
  for (int i : s.driven().driven_vertices) {
    const Eigen::Vector3d expected =
        s.driven().drive.position(s.q0.segment<3>(3 * i), k * s.settings.time_step);
    worst = std::max(worst, (q.segment<3>(3 * i) - expected).norm());
  }
  return worst;
}

// BDF-2's momentum balance over a run. Step n solves M (q_{n+1} - q_hat) + w grad V = 0 at the free
// dofs; summed over every dof (grad V of the elastic and contact forms sums to zero: they do not
// change under a translation; no gravity) it reads sum M (q_{n+1} - q_hat) = w f_n, f_n the drives'
// reaction (StepStats::dirichlet_force). With P_n = sum M v_n (BDF-2 velocities) the left side is
// (2h/3) (Pi_{n+1} - Pi_n), Pi_n = P_n - P_{n-1} / 3, so (3/2) (Pi_N - Pi_0) = h sum_n f_n: the
// momentum change, once the motion is steady at both ends (Pi = 2P/3), equals the drives' impulse.
struct MomentumBalance {
  Eigen::Vector3d change = Eigen::Vector3d::Zero();   // (3/2) (Pi_N - Pi_0), kg m/s
  Eigen::Vector3d impulse = Eigen::Vector3d::Zero();  // h sum f_n, N s
};

Eigen::Vector3d momentum(Simulator& sim, const Trajectory& t, int k, const Body* body = nullptr) {
  const Eigen::VectorXd Mv = sim.inertia_form().multiply(t.velocity(k));
  if (body == nullptr) return linear_momentum(Mv);
  return linear_momentum(Mv.segment(3 * body->vertex_begin, 3 * body->num_vertices()));
}

MomentumBalance balance(Simulator& sim, const Trajectory& t, const Body* body = nullptr) {
  MomentumBalance b;
  const int N = t.num_steps();
  auto Pi = [&](int k) {
    return Eigen::Vector3d(momentum(sim, t, k, body) - momentum(sim, t, k - 1, body) / 3.0);
  };
  b.change = 1.5 * (Pi(N) - Pi(0));
  for (const StepStats& s : t.steps) b.impulse += t.time_step * s.dirichlet_force;
  return b;
}

TEST(PrescribedMotion, AngleIntegratesThePiecewiseLinearSpeedAndVelocityIsTheDerivative) {
  PrescribedMotion m;
  m.axis = Eigen::Vector3d(1, 2, 2) / 3.0;
  m.centre = Eigen::Vector3d(0.1, -0.2, 0.3);
  m.velocity = Eigen::Vector3d(0.5, 0, -1);
  m.angular_velocity_table = {Eigen::Vector2d(0.1, 2.0), Eigen::Vector2d(0.3, 6.0),
                              Eigen::Vector2d(0.4, -1.0)};
  // Held at 2 before 0.1: angle(0.1) = 0.2; then the trapezoids 0.8 and 0.25, then -1 rad/s.
  EXPECT_NEAR(m.angle(0.1), 0.2, 1e-15);
  EXPECT_NEAR(m.angle(0.3), 1.0, 1e-15);
  EXPECT_NEAR(m.angle(0.4), 1.25, 1e-15);
  EXPECT_NEAR(m.angle(0.6), 1.05, 1e-15);
  EXPECT_NEAR(m.angle(-0.1), -0.2, 1e-15);
  EXPECT_NEAR(m.angular_speed(0.2), 4.0, 1e-15);
  const Eigen::Vector3d x0(0.4, 0.1, -0.2);
  EXPECT_LT((m.position(x0, 0.0) - x0).norm(), 1e-16);
  for (double t : {-0.05, 0.05, 0.2, 0.35, 0.5}) {
    const double e = 1e-6;
    const Eigen::Vector3d fd = (m.position(x0, t + e) - m.position(x0, t - e)) / (2 * e);
    EXPECT_LT((fd - m.point_velocity(x0, t)).norm(), 1e-8) << t;
    // A rigid motion: distances to the moving axis point keep.
    EXPECT_NEAR((m.position(x0, t) - m.centre - t * m.velocity).norm(), (x0 - m.centre).norm(),
                1e-15);
  }
}

TEST(Driven, VerticesFollowThePrescribedMotionExactlyWhileTheBarBends) {
  // A soft bar at rest, its end face spun up about z from 0 to 20 rad/s over 0.02 s.
  test::DrivenScene s = test::driven_bar(10, 20.0, 0.02);
  s.settings.num_steps = 40;
  s.materials = MaterialField::uniform(s.mesh.num_tets(), 2e6, 0.3, 1000);
  Simulator sim(s.mesh, s.materials, s.settings);
  EXPECT_EQ(sim.driven_dofs().size(), 12u);
  double worst = 0;
  int newton = 0;
  const Trajectory t =
      sim.run(s.q0, s.v0, [&](int k, const Eigen::VectorXd& q, const StepStats& st) {
        worst = std::max(worst, follow_error(s, q, k));
        newton += st.newton_iterations;
      });
  // The history the first steps used is the drive's past.
  double past = 0;
  for (int k = 1; k <= 3; ++k) past = std::max(past, follow_error(s, t.position(-k), -k));
  // The free end (the x = 0.2 face's centre) lags behind the driven face's angle.
  const double T = s.settings.num_steps * s.settings.time_step;
  const double driven_angle = s.driven().drive.angle(T);
  Eigen::Vector3d tip = Eigen::Vector3d::Zero(), tip0 = Eigen::Vector3d::Zero();
  int count = 0;
  for (int v = 0; v < s.mesh.num_vertices(); ++v) {
    if (s.mesh.V(v, 0) > 0.2 - 1e-9) {
      tip += t.q.back().segment<3>(3 * v);
      tip0 += s.q0.segment<3>(3 * v);
      ++count;
    }
  }
  tip /= count;
  tip0 /= count;
  const Eigen::Vector3d c = s.driven().drive.centre;
  const double tip_angle = std::atan2(tip.y() - c.y(), tip.x() - c.x());
  const double rigid_miss = (tip - s.driven().drive.position(tip0, T)).norm();
  std::printf(
      "driven bar: follow error %.2e m (history %.2e m), driven face at %.4f rad, free end at "
      "%.4f rad (lag %.4f rad, %.2e m off the rigid position); %d Newton iterations in %d steps\n",
      worst, past, driven_angle, tip_angle, driven_angle - tip_angle, rigid_miss, newton,
      s.settings.num_steps);
  EXPECT_LE(worst, 1e-12);
  EXPECT_LE(past, 1e-12);
  EXPECT_GT(driven_angle - tip_angle, 0.02);
  EXPECT_GT(rigid_miss, 1e-3);
}

TEST(Driven, AFreeBallStruckByADrivenPaddleGainsTheDrivesImpulse) {
  const test::DrivenScene s = test::driven_paddle();
  Simulator sim(s.mesh, s.materials, s.settings);
  ASSERT_NE(sim.body_contact_form(), nullptr);
  int contact_steps = 0;
  bool intersecting = false;
  double worst = 0, closest = 1;
  const Trajectory t =
      sim.run(s.q0, s.v0, [&](int k, const Eigen::VectorXd& q, const StepStats& st) {
        contact_steps += st.active_pairs > 0;
        const BodyClearance c = sim.body_contact_form()->clearance(q, 1.0);
        intersecting = intersecting || c.intersecting;
        closest = std::min(closest, c.distance);
        worst = std::max(worst, follow_error(s, q, k));
      });
  const Body& ball = s.bodies[1];
  const Eigen::Vector3d gain = momentum(sim, t, t.num_steps(), &ball) - momentum(sim, t, 0, &ball);
  const MomentumBalance b = balance(sim, t);
  const double error = (b.change - b.impulse).norm() / gain.norm();
  std::printf(
      "driven paddle: contact in %d of %d steps, closest %.3e m; ball's momentum gain (%.6f, "
      "%.2e, %.2e) kg m/s, drives' impulse (%.6f, %.2e, %.2e) N s, balance error %.2e "
      "(relative to the gain); follow error %.2e m\n",
      contact_steps, t.num_steps(), closest, gain.x(), gain.y(), gain.z(), b.impulse.x(),
      b.impulse.y(), b.impulse.z(), error, worst);
  EXPECT_GE(contact_steps, 3);
  EXPECT_FALSE(intersecting);
  EXPECT_EQ(test::first_intersection(s.mesh, s.settings, t), "");
  EXPECT_GT(closest, 0);
  EXPECT_LE(worst, 1e-12);
  // The ball left the paddle faster than it (an elastic push), and all of its gain came from the
  // drives: the paddle's own momentum is prescribed and constant.
  EXPECT_GT(gain.x(), 0.1 * 1000 * 4.0 / 3.0 * M_PI * std::pow(0.025, 3));
  EXPECT_LE((gain - b.impulse).norm(), 1e-10 * gain.norm());
  EXPECT_LE(error, 1e-10);
}

TEST(Driven, MomentumBalanceOfABarSweepingIntoABallIncludesTheDirichletReactions) {
  // A bat in miniature: a bar swung at 10 rad/s by its end face strikes a free ball; the bar bends.
  const test::DrivenScene s = test::driven_bar(6, 10.0, 0.0, 0.025);
  Simulator sim(s.mesh, s.materials, s.settings);
  int contact_steps = 0;
  bool intersecting = false;
  double worst = 0, closest = 1;
  const Trajectory t =
      sim.run(s.q0, s.v0, [&](int k, const Eigen::VectorXd& q, const StepStats& st) {
        contact_steps += st.active_pairs > 0;
        const BodyClearance c = sim.body_contact_form()->clearance(q, 1.0);
        intersecting = intersecting || c.intersecting;
        closest = std::min(closest, c.distance);
        worst = std::max(worst, follow_error(s, q, k));
      });
  const Body& ball = s.bodies[1];
  const Eigen::Vector3d gain = momentum(sim, t, t.num_steps(), &ball) - momentum(sim, t, 0, &ball);
  const MomentumBalance b = balance(sim, t);
  const MomentumBalance bar = balance(sim, t, &s.bodies[0]);
  const double error = (b.change - b.impulse).norm() / gain.norm();
  std::printf(
      "driven bar and ball: contact in %d of %d steps, closest %.3e m; ball's gain |%.4e| kg m/s, "
      "bar's change |%.4e|, drives' impulse |%.4e| N s; balance error %.2e (relative to the "
      "ball's gain); follow error %.2e m\n",
      contact_steps, t.num_steps(), closest, gain.norm(), bar.change.norm(), b.impulse.norm(),
      error, worst);
  EXPECT_GE(contact_steps, 3);
  EXPECT_FALSE(intersecting);
  EXPECT_EQ(test::first_intersection(s.mesh, s.settings, t), "");
  EXPECT_GT(closest, 0);
  EXPECT_LE(worst, 1e-12);
  EXPECT_GT(gain.y(), 0.0);  // struck along the bar's sweep
  EXPECT_LE(error, 1e-10);
}

TEST(Driven, ASpinningDrivenBodyFeelsTheSameForceFromTheFirstStep) {
  // Every vertex of the bar driven at a constant 10 rad/s: its motion is exactly rigid and
  // uniform, so every step's equation is the first one's rotated, provided the BDF past is the
  // drive's (a ballistic past would jolt the first three steps). The force is BDF-2's centripetal
  // force, m omega^2 |c_m - c| to O((h omega)^2).
  test::DrivenScene s = test::driven_bar(6, 10.0);
  Body& bar = s.bodies[0];
  bar.driven_vertices.clear();
  for (int v = 0; v < s.mesh.num_vertices(); ++v) bar.driven_vertices.push_back(v);
  s.settings.bodies = s.bodies;
  s.settings.time_step = 1e-2;
  s.settings.num_steps = 10;
  Simulator sim(s.mesh, s.materials, s.settings);
  std::vector<double> forces;
  sim.run(s.q0, s.v0, [&](int, const Eigen::VectorXd&, const StepStats& st) {
    forces.push_back(st.dirichlet_force.norm());
  });
  const double m = sim.vertex_masses().sum();
  const Eigen::Vector3d cm = centre_of_mass(s.q0, sim.vertex_masses());
  const double centripetal = m * 100.0 * (cm - bar.drive.centre).norm();
  double spread = 0;
  for (double f : forces) spread = std::max(spread, std::abs(f - forces.back()) / forces.back());
  std::printf(
      "spinning driven bar: |f| first %.12e last %.12e N (spread %.2e), centripetal %.6e N\n",
      forces.front(), forces.back(), spread, centripetal);
  EXPECT_LE(spread, 1e-9);
  EXPECT_NEAR(forces.front(), centripetal, 0.02 * centripetal);
}

// The run's error message; every position it reached before the error is checked for
// intersections (the first finding in `intersection`).
// The run's error (empty if none), its first intersection and, if asked, its steps' CCD caps.
std::string error_of(Simulator& sim, const test::DrivenScene& s, std::string& intersection,
                     long* ccd_caps = nullptr) {
  const test::IntersectionCheck check(s.mesh, s.settings);
  intersection = check.first_intersection(s.q0);
  try {
    sim.run(s.q0, s.v0, [&](int step, const Eigen::VectorXd& q, const StepStats& stats) {
      if (ccd_caps) *ccd_caps += stats.ccd_caps;
      if (intersection.empty()) {
        const std::string what = check.first_intersection(q);
        if (!what.empty()) intersection = "q[" + std::to_string(step) + "]: " + what;
      }
    });
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Driven, APrescribedStepThroughAnObstacleIsAnErrorNamingTheStep) {
  // The paddle driven back (-x) at 2 m/s towards the plane x = -0.005 (normal +x) from 5 mm in
  // front of it: the third step's prescribed move (h = 1e-3, 2 mm per step) would end beyond it.
  test::DrivenScene s = test::driven_paddle();
  s.bodies[0].drive.velocity = Eigen::Vector3d(-2.0, 0, 0);
  s.settings.bodies = s.bodies;
  s.v0 = initial_velocities(s.q0, s.bodies);
  s.settings.planes = {Plane{Eigen::Vector3d::UnitX(), -0.005}};
  Simulator sim(s.mesh, s.materials, s.settings);
  std::string intersection;
  const std::string m = error_of(sim, s, intersection);
  std::printf("through a plane: %s\n", m.c_str());
  EXPECT_EQ(intersection, "");
  EXPECT_NE(m.find("step 3 "), std::string::npos) << m;
  EXPECT_NE(m.find(" would intersect"), std::string::npos) << m;
  EXPECT_NE(m.find("'striker'"), std::string::npos) << m;
  EXPECT_EQ(m.find('\n'), std::string::npos) << m;
}

TEST(Driven, APrescribedStepThroughAnotherBodyIsAnErrorNamingTheStep) {
  // The paddle at 40 m/s with h = 2e-3: its first step (8 cm) passes through the ball 5 mm ahead.
  test::DrivenScene s = test::driven_paddle(40.0);
  s.settings.time_step = 2e-3;
  Simulator sim(s.mesh, s.materials, s.settings);
  std::string intersection;
  const std::string m = error_of(sim, s, intersection);
  std::printf("through a body: %s\n", m.c_str());
  EXPECT_EQ(intersection, "");
  EXPECT_NE(m.find("step 1 "), std::string::npos) << m;
  EXPECT_NE(m.find(" would intersect"), std::string::npos) << m;
  EXPECT_NE(m.find("'striker'"), std::string::npos) << m;
  EXPECT_EQ(m.find('\n'), std::string::npos) << m;
}

TEST(Driven, APrescribedStepThroughAnObstacleMeshIsAnErrorNamingTheStep) {
  // The paddle driven back (-x) at 1 m/s towards a square obstacle at x = -0.0025 (spanning the
  // paddle's back face, y, z in [0.005, 0.035]) from 2.5 mm in front of it: the third step's
  // prescribed move (h = 1e-3, 1 mm per step) would carry the back face's middle vertex through it.
  test::DrivenScene s = test::driven_paddle();
  s.bodies[0].drive.velocity = Eigen::Vector3d(-1.0, 0, 0);
  s.settings.bodies = s.bodies;
  s.v0 = initial_velocities(s.q0, s.bodies);
  const double x = -0.0025, lo = 0.005, hi = 0.035;
  s.settings.obstacle_meshes = {test::obstacle_mesh(
      {{x, lo, lo}, {x, hi, lo}, {x, hi, hi}, {x, lo, hi}}, {{0, 1, 2}, {0, 2, 3}}, "wall")};
  Simulator sim(s.mesh, s.materials, s.settings);
  std::string intersection;
  const std::string m = error_of(sim, s, intersection);
  std::printf("through an obstacle mesh: %s\n", m.c_str());
  EXPECT_EQ(intersection, "");
  EXPECT_NE(m.find("step 3 "), std::string::npos) << m;
  EXPECT_NE(m.find("'striker'"), std::string::npos) << m;
  EXPECT_NE(m.find(" would intersect"), std::string::npos) << m;
  EXPECT_EQ(m.find('\n'), std::string::npos) << m;
}

// A fully driven 1 cm cube sliding by `slide` in one step (h = 1e-3) along its edge from corner 0
// to corner 1, whose direction is d = (1, 1, 1) / sqrt(3) in the world, and a triangular fin
// whose edge runs parallel to that edge, `gap` away along the bisector of the cube's two faces
// there, the fin pointing away from the cube (tilted off the bisector, so that the cube's edge is
// not coplanar with it: the clearance's double-precision orientation test then reads a 1e-10 m gap
// as a crossing). Along a diagonal direction (the offset perpendicular to it) the two edges'
// axis-aligned boxes meet without inflation, so is_step_valid searches the pair; parallel edges
// have no plane certificate, and the additive iteration needs ~slide / gap iterations. d_hat is
// gap / 2: the cube starts out of contact.
test::DrivenScene sliding_cube(double gap, double slide) {
  const Eigen::Vector3d d = Eigen::Vector3d::Ones().normalized();
  const Eigen::Matrix3d R =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitX(), d).toRotationMatrix();
  TetMesh cube = test::box_mesh(1, 1, 1, 0.01);
  for (int v = 0; v < cube.num_vertices(); ++v) {
    cube.V.row(v) = (R * cube.V.row(v).transpose()).transpose();
  }
  std::vector<int> all(cube.num_vertices());
  for (int v = 0; v < cube.num_vertices(); ++v) all[v] = v;
  const double h = 1e-3;
  PrescribedMotion drive;
  drive.velocity = (slide / h) * d;
  test::DrivenScene s = test::stack(cube, all, drive, 0.0, Eigen::Vector3d::Zero());
  // In the cube's frame the edge runs from the origin along x, the faces y = 0 and z = 0 meet
  // there, and (0, 1, 1) / sqrt(2) points into the cube.
  const Eigen::Vector3d in = Eigen::Vector3d(0, 1, 1).normalized();
  const Eigen::Vector3d o = -gap * in;
  s.settings.obstacle_meshes = {test::obstacle_mesh(
      {R * (o + Eigen::Vector3d(-0.02, 0, 0)), R * (o + Eigen::Vector3d(0.05, 0, 0)),
       R * (o + Eigen::Vector3d(0.015, 0, 0) - 0.02 * Eigen::Vector3d(0, 1, 2).normalized())},
      {{0, 1, 2}}, "fin")};
  s.settings.time_step = h;
  s.settings.num_steps = 1;
  s.settings.d_hat = gap / 2;
  s.settings.kappa = 1e3;
  return s;
}

// The cube's q0 moved by `fraction` of one step's slide.
Eigen::VectorXd slid(const test::DrivenScene& s, double fraction) {
  Eigen::VectorXd q = s.q0;
  const Eigen::Vector3d step = s.settings.time_step * s.driven().drive.velocity;
  for (Eigen::Index v = 0; v < q.size() / 3; ++v) q.segment<3>(3 * v) += fraction * step;
  return q;
}

TEST(Driven, AStepWhoseCcdIsCappedButHarmlessIsCheckedInPiecesAndTaken) {
  // 1 cm of slide per step 1e-8 m from the fin's edge: ~1e6 iterations, the cap is 1e5.
  const test::DrivenScene s = sliding_cube(1e-8, 0.01);
  Simulator sim(s.mesh, s.materials, s.settings);
  // The first step's straight move, checked whole: refused, and only because searches were capped.
  IncrementalPotential& E = sim.potential();
  const Eigen::VectorXd q1 = slid(s, 1.0);
  EXPECT_FALSE(E.is_step_valid(s.q0, q1));
  const long whole = E.ccd_caps();
  // In 16 pieces (~6e4 iterations each) every piece is certified and nothing is capped.
  bool pieces_valid = true;
  for (int k = 0; k < 16; ++k)
    pieces_valid &= E.is_step_valid(slid(s, k / 16.0), slid(s, (k + 1) / 16.0));
  const long in_pieces = E.ccd_caps() - whole;
  std::printf("capped slide: the whole step %ld capped searches, in 16 pieces %s with %ld\n", whole,
              pieces_valid ? "valid" : "INVALID", in_pieces);
  EXPECT_GE(whole, 1);
  EXPECT_TRUE(pieces_valid);
  EXPECT_EQ(in_pieces, 0);

  // The run meets the same capped searches in its driven start and takes the step, the cube on
  // its drive, nothing intersecting.
  std::string intersection;
  long reported = 0;
  const std::string m = error_of(sim, s, intersection, &reported);
  const long in_run = E.ccd_caps() - whole - in_pieces;
  std::printf("capped slide run: \"%s\", %ld capped searches in its step (%ld in its StepStats)\n",
              m.c_str(), in_run, reported);
  EXPECT_EQ(m, "");
  EXPECT_EQ(reported, in_run);  // the step reports every capped search it made
  EXPECT_EQ(intersection, "");
  EXPECT_GE(in_run, whole);
  EXPECT_EQ(sim.step_index(), 1);
  EXPECT_LE(follow_error(s, sim.integrator().current(), 1), 1e-15);
  const ObstacleClearance c = sim.mesh_obstacle_form()->clearance(sim.integrator().current(), 1e-6);
  std::printf("capped slide: clearance after 1 cm %.3e m (%s)\n", c.distance, c.pair.c_str());
  EXPECT_FALSE(c.intersecting);
  EXPECT_NEAR(c.distance, 1e-8, 1e-12);
}

TEST(Driven, AStepWhoseCcdStaysCappedInEveryPieceIsAnErrorSayingSo) {
  // 1 cm of slide 1e-10 m from the fin's edge: ~1e8 iterations, still ~4e5 on a 1/256 piece.
  const test::DrivenScene s = sliding_cube(1e-10, 0.01);
  Simulator sim(s.mesh, s.materials, s.settings);
  const IncrementalPotential& E = sim.potential();
  EXPECT_FALSE(E.is_step_valid(s.q0, slid(s, 1.0)));
  const long whole = E.ccd_caps();  // the capped searches of one check
  std::string intersection;
  const std::string m = error_of(sim, s, intersection);
  const long in_run = E.ccd_caps() - whole;
  std::printf("capped in every piece: %s (%ld capped searches, %ld in the whole move's check)\n",
              m.c_str(), in_run, whole);
  // Every one of the 1 + 2 + ... + 256 = 511 checks down to the 1/256 pieces was made and capped,
  // and none beyond: each piece at most as many as the whole move.
  EXPECT_GE(whole, 1);
  EXPECT_GE(in_run, 511);
  EXPECT_LE(in_run, 511 * whole);
  EXPECT_NE(m.find("a shorter time step helps"), std::string::npos) << m;
  EXPECT_EQ(intersection, "");
  EXPECT_NE(m.find("step 1 "), std::string::npos) << m;
  EXPECT_NE(m.find("'striker'"), std::string::npos) << m;
  EXPECT_NE(m.find(" could not be certified free of intersection"), std::string::npos) << m;
  EXPECT_EQ(m.find("would intersect"), std::string::npos) << m;
  EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  // Nothing intersects: the end of the step is as clear as its start.
  const ObstacleClearance c = sim.mesh_obstacle_form()->clearance(slid(s, 1.0), 1e-6);
  EXPECT_FALSE(c.intersecting);
  EXPECT_NEAR(c.distance, 1e-10, 1e-13);
}

TEST(Driven, BadDrivenVerticesAreRefused) {
  test::DrivenScene s = test::driven_bar(3, 1.0);
  s.settings.bodies[0].driven_vertices = {2, 1};
  EXPECT_THROW(Simulator(s.mesh, s.materials, s.settings), InputError);
  s.settings.bodies[0].driven_vertices = {1, s.mesh.num_vertices()};
  EXPECT_THROW(Simulator(s.mesh, s.materials, s.settings), InputError);
  s.settings.bodies[0].driven_vertices = {1};
  s.settings.bodies[0].drive.axis = Eigen::Vector3d::Zero();
  EXPECT_THROW(Simulator(s.mesh, s.materials, s.settings), InputError);
}

}  // namespace
}  // namespace rbaa
