#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <Eigen/Dense>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "io/io_test_support.hpp"
#include "rbaa/error.hpp"
#include "rbaa/eval/evaluation.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/rigid/rigid_body.hpp"
#include "rbaa/rigid/rigid_simulation.hpp"
#include "rbaa/scene/scene.hpp"
#include "rbaa/scene/scene_mesh.hpp"

namespace rbaa {
namespace {

// A ball of ~400 tets thrown at a wall without gravity: one bounce within 0.2 s.
Scene ball_scene() {
  return parse_scene(
      "mesh: {shape: sphere, radius: 0.1, target_tets: 400}\n"
      "object: {position: [0, -0.15, 0.5], velocity: [0.5, 2.0, 0], angular_velocity: [0, 0, 3]}\n"
      "obstacles: {planes: [{normal: [0, -1, 0], offset: 0}]}\n"
      "gravity: off\n"
      "time: {step: 0.01, duration: 0.05}\n",
      "ball_test.yaml", "");
}

// Same moments as the uniform reference, different density and stiffness.
MaterialField adversarial_field(const TetMesh& mesh, const Scene& scene) {
  MaterialField f = MaterialField::uniform(mesh.num_tets(), 5e9, 0.3, scene.reference_rho, 1.0);
  const Eigen::MatrixXd S = moment_operator(mesh);
  std::srand(3);
  const Eigen::VectorXd r = Eigen::VectorXd::Random(mesh.num_tets()) * 800.0;
  f.rho += r - S.transpose() * (S * S.transpose()).ldlt().solve(S * r);
  for (int e = 0; e < mesh.num_tets(); ++e) f.Y[e] = (e % 3 == 0) ? 5e9 : 6.5e11;
  return f;
}

// A tilted, spinning 5 cm cube (300 tets) meeting the floor on a corner, gravity off, at step h:
// its rigid twin's scene, mass properties and shape.
struct TiltedCube {
  Scene scene;
  RigidMassProperties mass;
  RigidShape shape;

  explicit TiltedCube(double h)
      : scene(parse_scene(
            "mesh: {shape: cube, side: 0.05, target_tets: 300}\n"
            "object: {position: [0, 0, 0.08], velocity: [0.3, 0, -1.0], angular_velocity: [5, -3, 1],\n"
            "         rotation: {axis: [1, 2, 0], angle_deg: 8}}\n"
            "obstacles: {planes: [{normal: [0, 0, 1], offset: 0}]}\n"
            "gravity: off\n"
            "time: {step: " + std::to_string(h) + ", duration: 0.3}\n",
            "tilted_cube_test.yaml", "")) {
    const TetMesh mesh = make_scene_mesh(scene);
    mass = rigid_mass_properties(compute_moments(mesh, scene.reference_rho));
    shape = rigid_shape_from_surface(mesh);
  }
  /// The floor's restitution fitted to `target` (calibrate_restitution, from restitution 1).
  RestitutionCalibration fit(double target, double tolerance,
                             const TwinCloseness& closeness = nullptr) const {
    return calibrate_restitution(mass, shape, scene, RigidSettings{}, scene.duration, 0, target,
                                 tolerance, {}, closeness);
  }
  /// The twin's run at floor restitution e.
  std::vector<RigidState> run(double e) const {
    RigidSettings settings;
    settings.plane_restitution = {e};
    return simulate_rigid(mass, shape, scene, settings, scene.duration);
  }
  /// The twin's first rebound off the floor at restitution e.
  double rebound_at(double e) const {
    return rigid_first_rebound(run(e), scene.planes[0], Eigen::Vector3d::Zero());
  }
};

// Restitution calibration on a non-spherical body, where the rebound is not the restitution and
// not linear in it, so the search has to iterate: a tilted, spinning cube hitting the floor on a
// corner. The fitted restitution is then re-run and its rebound measured here from the states
// themselves (gravity off: the normal velocity is constant before and after the single bounce).
// compare_runs on two hand-made traces whose every figure is known: the final and the largest
// centre-of-mass gap (neither run at the origin, so a gap that forgets one run is caught), the
// angle between the final velocities and between the final rotations. The shorter trace sets
// the compared samples.
TEST(Evaluation, CompareRunsGivesTheGapsAndAnglesOfTwoKnownTraces) {
  RunTrace a, b;
  a.name = "a";
  b.name = "b";
  const Eigen::Vector3d base(1.0, 2.0, 3.0);
  for (int i = 0; i < 3; ++i) {
    a.time.push_back(0.1 * i);
    b.time.push_back(0.1 * i);
    a.centre.push_back(base + Eigen::Vector3d(0.1 * i, 0, 0));
    b.centre.push_back(base + Eigen::Vector3d(0.1 * i, i == 1 ? 0.5 : 0.03 * i, 0.04 * i));
    a.velocity.push_back(Eigen::Vector3d(1, 0, 0));
    b.velocity.push_back(Eigen::Vector3d(1, 1, 0));
    a.rotation.push_back(Eigen::Quaterniond::Identity());
    b.rotation.push_back(Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ())));
  }
  b.time.push_back(0.3);  // a sample a does not have: not compared
  b.centre.push_back(base + Eigen::Vector3d(5, 5, 5));
  b.velocity.push_back(Eigen::Vector3d(0, 0, 1));
  b.rotation.push_back(Eigen::Quaterniond::Identity());
  const RunComparison c = compare_runs(a, b);
  EXPECT_EQ(c.a, "a");
  EXPECT_EQ(c.b, "b");
  EXPECT_NEAR(c.position_gap, 0.1, 1e-15);       // (0, 0.06, 0.08) at the last common sample
  EXPECT_NEAR(c.max_position_gap, std::hypot(0.5, 0.04), 1e-15);
  EXPECT_NEAR(c.velocity_angle_deg, 45.0, 1e-12);
  EXPECT_NEAR(c.orientation_gap_deg, 0.3 * 180.0 / M_PI, 1e-9);
  const RunComparison same = compare_runs(a, a);
  EXPECT_EQ(same.position_gap, 0.0);
  EXPECT_EQ(same.max_position_gap, 0.0);
  EXPECT_EQ(same.velocity_angle_deg, 0.0);
}

TEST(Evaluation, CalibratedRestitutionReproducesTheTargetOnATiltedCube) {
  const TiltedCube cube(0.005);
  const double target = 0.6, tolerance = 1e-3;
  const RestitutionCalibration cal = cube.fit(target, tolerance);
  ASSERT_TRUE(cal.calibrated);
  const std::vector<RigidState> states = cube.run(cal.restitution);
  const double v_in = states.front().velocity.z(), v_out = states.back().velocity.z();
  const double rebound = -v_out / v_in;
  std::printf("tilted cube: restitution %.6f after %d rigid runs gives rebound %.9f (target %.3f, "
              "calibration says %.9f)\n",
              cal.restitution, cal.iterations, rebound, target, cal.rigid_rebound);
  EXPECT_GT(cal.iterations, 2);                          // the search iterated
  EXPECT_GT(std::abs(cal.restitution - target), 1e-3);   // rebound != restitution off a corner
  EXPECT_NEAR(rebound, target, tolerance * target);
  // What the calibration reports is what the rigid run does with its restitution (the same
  // deterministic run: to round-off, not to the tolerance, so a calibration that reports the
  // mirror of its error, target - f for target + f, is caught).
  EXPECT_NEAR(cal.rigid_rebound, rebound, 1e-14);
  EXPECT_GT(states.back().position.z(), states.front().position.z() - 0.05);  // it left the floor
  // Driven to 1e-12, false position must still close the bracket in a few runs after the scan's
  // 12 (measured: 3 more; Bullet's rebound is not linear in the restitution for this spinning
  // corner impact).
  const RestitutionCalibration fine = cube.fit(target, 1e-12);
  std::printf("tilted cube at 1e-12: restitution %.12f after %d rigid runs, rebound %.12f\n",
              fine.restitution, fine.iterations, fine.rigid_rebound);
  EXPECT_TRUE(fine.calibrated);
  EXPECT_LE(fine.iterations, 12 + 8);
  EXPECT_EQ(fine.roots, std::vector<double>{fine.restitution});
  EXPECT_NEAR(fine.rigid_rebound, target, 1e-12 * target);
  const std::vector<RigidState> again = cube.run(fine.restitution);
  EXPECT_NEAR(-again.back().velocity.z() / again.front().velocity.z(), fine.rigid_rebound, 1e-14);
}

// Without a touch log an impact is a change of the normal velocity by more than 10 |g| h: under
// gravity every step of a free fall changes it by |g| h, which is no impact, so the episode starts
// at the bounce, and with gravity taken off over it the rebound is the bounce's own. A ball falling
// at h = 0.01 s from -1 m/s, bouncing between samples 10 and 11 at 0.5 (its velocity reversed,
// then gravity's step), falling on to sample 30.
TEST(Evaluation, RigidReboundUnderGravityWithoutATouchLogStartsAtTheBounce) {
  const double h = 0.01, e = 0.5;
  const Eigen::Vector3d g(0, 0, -9.8);
  std::vector<RigidState> states(31);
  for (int k = 0; k <= 30; ++k) {
    states[k].time = k * h;
    const double v10 = -1 + g.z() * 10 * h;
    const double vz = k <= 10 ? -1 + g.z() * k * h : -e * v10 + g.z() * (k - 10) * h;
    states[k].velocity = Eigen::Vector3d(0.3, 0, vz);
  }
  Plane floor;
  floor.normal = Eigen::Vector3d::UnitZ();
  floor.offset = 0;
  const double rebound = rigid_first_rebound(states, floor, g);
  std::printf("synthetic bounce under gravity, no touch log: rebound %.15f\n", rebound);
  EXPECT_NEAR(rebound, e, 1e-14);
}

// The same tilted cube at a fine step (0.2 ms): its first corner leaves it still approaching the
// floor, and its next corner strikes 20 steps later. That is one bounce (the deformable run's
// episode goes on while the body approaches, impact_end), so its rebound is the whole run's:
// with gravity off, the normal velocity after the last impact over the one before the first.
TEST(Evaluation, RigidReboundSpansTheCornersOfOneBounceAtAFineStep) {
  const TiltedCube cube(0.0002);
  const Scene& scene = cube.scene;
  const std::vector<RigidState> states = cube.run(0.5);
  int impacts = 0;  // steps whose normal velocity changed: the corners' impacts
  for (size_t k = 0; k + 1 < states.size(); ++k) {
    impacts += std::abs(states[k + 1].velocity.z() - states[k].velocity.z()) > 1e-9;
  }
  const double whole_run = -states.back().velocity.z() / states.front().velocity.z();
  const double rebound = rigid_first_rebound(states, scene.planes[0], Eigen::Vector3d::Zero());
  std::printf("tilted cube at 0.2 ms, restitution 0.5: %d impacts, rebound %.9f, whole run %.9f\n",
              impacts, rebound, whole_run);
  EXPECT_GE(impacts, 2);
  EXPECT_GT(whole_run, 0);
  EXPECT_NEAR(rebound, whole_run, 1e-12);
  // Cut off before it turns away, the bounce is unfinished: no rebound.
  const std::vector<RigidState> cut(states.begin(), states.begin() + 300);
  EXPECT_LT(cut.back().velocity.z(), 0);
  EXPECT_TRUE(std::isnan(rigid_first_rebound(cut, scene.planes[0], Eigen::Vector3d::Zero())));

  // At this step the rebound tops out near 0.38 (restitution 0.5; at 0.6 the cube leaves its first
  // corner and meets no second): 0.45 has no restitution, and the fit keeps, not fitted, the one
  // whose rebound comes nearest of all it tried, here not the last it tried (1).
  const RestitutionCalibration none = cube.fit(0.45, 1e-3);
  std::printf("rebound 0.45: none; kept restitution %.3f, rebound %.6f\n", none.restitution,
              none.rigid_rebound);
  EXPECT_FALSE(none.calibrated);
  EXPECT_TRUE(none.roots.empty());
  EXPECT_NE(none.restitution, 1.0);
  EXPECT_NEAR(cube.rebound_at(none.restitution), none.rigid_rebound, 1e-14);
  for (int i = 0; i <= 10; ++i) {
    EXPECT_LE(std::abs(none.rigid_rebound - 0.45), std::abs(cube.rebound_at(0.1 * i) - 0.45)) << i;
  }
}

// A blow from something else starts no rebound off the plane: the normal velocity -4 m/s, then
// -1 m/s after a blow at step 10 (another body's), then +0.75 m/s after the plane's own impact at
// step 20. Told which impacts are the plane's, the rebound is 0.75 / 1; without, the episode
// starts at the blow and gives 0.75 / 4.
TEST(Evaluation, RigidReboundStartsAtAnImpactWithThePlaneItself) {
  const Plane floor{Eigen::Vector3d::UnitZ(), 0.0};
  std::vector<RigidState> states(30);
  for (int k = 0; k < 30; ++k) {
    states[k].time = 0.01 * k;
    states[k].velocity = {0.3, 0, k <= 10 ? -4.0 : k <= 20 ? -1.0 : 0.75};
  }
  EXPECT_DOUBLE_EQ(rigid_first_rebound(states, floor, Eigen::Vector3d::Zero()), 0.75 / 4);
  EXPECT_DOUBLE_EQ(
      rigid_first_rebound(states, floor, Eigen::Vector3d::Zero(), [](int k) { return k == 20; }),
      0.75);
  EXPECT_TRUE(std::isnan(
      rigid_first_rebound(states, floor, Eigen::Vector3d::Zero(), [](int k) { return k == 5; })));
  // A body at rest against the plane (normal velocity exactly 0) is struck towards it at step 5:
  // no episode starts there (it was not approaching, and -v_out / 0 is no ratio); the bounce that
  // follows, -1 -> +0.5 at step 20, is the rebound.
  std::vector<RigidState> kicked(30);
  for (int k = 0; k < 30; ++k) {
    kicked[k].time = 0.01 * k;
    kicked[k].velocity = {0, 0, k <= 5 ? 0.0 : k <= 20 ? -1.0 : 0.5};
  }
  EXPECT_DOUBLE_EQ(
      rigid_first_rebound(kicked, floor, Eigen::Vector3d::Zero(), [](int) { return true; }), 0.5);
}

// The same through calibrate_restitution and Bullet: a ball dropped onto a 30 deg slope bounces
// off it (its vertical velocity -2.7 -> +1.4 m/s) and lands on the floor 0.49 s later. The
// floor's restitution is fitted to the floor's own rebound, not to the slope's, which no floor
// restitution changes (measured: unfitted, the rebound off the slope 0.48 at every restitution).
TEST(Evaluation, PlaneCalibrationFitsThePlanesOwnBounceAfterABlowFromAnother) {
  const Scene scene = parse_scene(
      "mesh: {shape: sphere, radius: 0.1, target_tets: 300}\n"
      "object: {position: [0, 0, 1], velocity: [0, 0, 0]}\n"
      "obstacles: {planes: [{normal: [0, 0, 1], offset: 0},\n"
      "                     {normal: [0.5, 0, 0.8660254037844386], offset: 0.4330127018922193}]}\n"
      "time: {step: 0.005, duration: 1.2}\n",
      "slope_then_floor.yaml", "");
  const TetMesh mesh = make_scene_mesh(scene);
  const RigidMassProperties mass = rigid_mass_properties(compute_moments(mesh, scene.reference_rho));
  const RigidShape shape = rigid_shape_from_surface(mesh);
  const double target = 0.7, tolerance = 1e-3;
  const RestitutionCalibration cal =
      calibrate_restitution(mass, shape, scene, RigidSettings{}, scene.duration, 0, target, tolerance);
  std::printf("slope then floor: floor restitution %.6f (calibrated %d) gives rebound %.6f\n",
              cal.restitution, cal.calibrated, cal.rigid_rebound);
  ASSERT_TRUE(cal.calibrated);
  EXPECT_NEAR(cal.rigid_rebound, target, tolerance * target);
  // The run itself: the slope first (moving +x, rising), then the floor, whose bounce is the fit.
  RigidSettings settings;
  settings.plane_restitution = {cal.restitution, 1.0};
  const std::vector<RigidState> states = simulate_rigid(mass, shape, scene, settings, scene.duration);
  int floor_impact = -1, first_rise = -1;
  for (int k = 0; k + 1 < static_cast<int>(states.size()); ++k) {
    if (first_rise < 0 && states[k + 1].velocity.z() > 0) first_rise = k;
    if (states[k + 1].position.z() < 0.11 && states[k + 1].velocity.z() > 0 && floor_impact < 0 &&
        states[k + 1].position.x() > 0.5) {
      floor_impact = k;
    }
  }
  ASSERT_GE(first_rise, 0);
  ASSERT_GT(floor_impact, first_rise);
  EXPECT_GT(states[first_rise].position.z(), 0.5);  // the slope's bounce, well above the floor
  const double g_step = 9.8 * scene.time_step;
  const double in = states[floor_impact].velocity.z(), out = states[floor_impact + 1].velocity.z();
  EXPECT_NEAR(-out / in, target, tolerance * target + g_step / std::abs(in));
  // A plane it never reaches has no rebound of its twin's: not fitted, restitution 1, NaN.
  Scene far = scene;
  far.planes[0].offset = -100;
  const RestitutionCalibration never =
      calibrate_restitution(mass, shape, far, RigidSettings{}, 0.2, 0, target, tolerance);
  EXPECT_FALSE(never.calibrated);
  EXPECT_EQ(never.restitution, 1.0);
  EXPECT_TRUE(std::isnan(never.rigid_rebound)) << never.rigid_rebound;
}

// A rebound several restitutions give: off this tilted cube's corner, the rebound 0.4 at a 5 ms
// step comes at two restitutions (measured: 0.381 and 0.513; between them the twin's rebound
// jumps, as it meets a second corner within the bounce or not). Each is found and gives it;
// without a measure of closeness the one nearest the target is kept, with one the closest twin.
TEST(Evaluation, CalibrationFindsEveryRestitutionThatGivesTheReboundAndKeepsTheClosestTwin) {
  const TiltedCube cube(0.005);
  const double target = 0.4, tolerance = 1e-6;
  auto rebound_at = [&](double e) { return cube.rebound_at(e); };
  const RestitutionCalibration nearest = cube.fit(target, tolerance);
  std::printf("rebound %.1f from restitutions:", target);
  for (double e : nearest.roots) std::printf(" %.6f", e);
  std::printf(" (kept %.6f)\n", nearest.restitution);
  ASSERT_TRUE(nearest.calibrated);
  ASSERT_GE(nearest.roots.size(), 2u);
  for (double e : nearest.roots) EXPECT_NEAR(rebound_at(e), target, tolerance * target) << e;
  double nearest_root = nearest.roots.front();
  for (double e : nearest.roots) {
    if (std::abs(e - target) < std::abs(nearest_root - target)) nearest_root = e;
  }
  EXPECT_EQ(nearest.restitution, nearest_root);
  EXPECT_NEAR(nearest.rigid_rebound, target, tolerance * target);

  // Closeness: asked for the twin that ends where the run at the other restitution ends, the
  // calibration keeps that one, not the nearest to the target.
  const double other = nearest.roots.front() == nearest.restitution ? nearest.roots.back()
                                                                     : nearest.roots.front();
  const Eigen::Vector3d end = cube.run(other).back().position;
  const TwinCloseness ends_there = [&](const std::vector<std::vector<RigidState>>& states) {
    return (states.at(0).back().position - end).norm();
  };
  const RestitutionCalibration closest = cube.fit(target, tolerance, ends_there);
  EXPECT_EQ(closest.roots, nearest.roots);
  EXPECT_EQ(closest.restitution, other);
  EXPECT_NE(closest.restitution, nearest.restitution);
  EXPECT_NEAR(closest.rigid_rebound, target, tolerance * target);

  // A root between the scan's last two points, 0.9 and 1: the rebound 0.8.
  const RestitutionCalibration high = cube.fit(0.8, tolerance);
  std::printf("rebound 0.8 from restitution %.6f\n", high.restitution);
  ASSERT_TRUE(high.calibrated);
  EXPECT_GT(high.restitution, 0.9);
  EXPECT_LT(high.restitution, 1.0);
  EXPECT_NEAR(rebound_at(high.restitution), 0.8, tolerance * 0.8);
  // The rebound 0.95 needs a restitution above 1 (about 1.08), which adds energy: not fitted, the
  // nearest rebound's restitution kept. A rebound above 1 (1.3) gained energy in the run: fitted
  // above 1 (measured 1.43).
  const RestitutionCalibration over = cube.fit(0.95, tolerance);
  std::printf("rebound 0.95: restitution %.6f, rebound %.6f, calibrated %d\n", over.restitution,
              over.rigid_rebound, over.calibrated);
  EXPECT_FALSE(over.calibrated);
  EXPECT_TRUE(over.roots.empty());
  EXPECT_LE(over.restitution, 1.0);
  EXPECT_NEAR(rebound_at(1.0), over.rigid_rebound, 1e-14);  // the nearest rebound: e = 1's
  EXPECT_GT(rebound_at(1.1), 0.95);  // a restitution above 1 would give it
  const RestitutionCalibration gained = cube.fit(1.3, tolerance);
  std::printf("rebound 1.3 from restitution %.6f\n", gained.restitution);
  ASSERT_TRUE(gained.calibrated);
  EXPECT_GT(gained.restitution, 1.0);
  EXPECT_NEAR(rebound_at(gained.restitution), 1.3, tolerance * 1.3);
  EXPECT_EQ(closest.iterations, nearest.iterations + static_cast<int>(nearest.roots.size()));
}

// Two restitutions give the star's rebound off its wall (configs/demos/star.yaml, coarse: 0.027 and
// 0.526 for 0.101; at the first the star still approaches the wall after its first corner, so its
// second corner joins the bounce). evaluate keeps the one whose twin follows the baseline closer,
// here not the one nearer the rebound. Each candidate's twin is re-run here as evaluate runs it
// (checked: the kept one reproduces evaluate's rigid reference exactly).
TEST(Evaluation, OfTheRestitutionsThatGiveAReboundTheTwinClosestToTheBaselineIsKept) {
  const double h = 1.0 / 480;
  Scene scene = load_scene(std::string(RBAA_SOURCE_DIR) + "/configs/demos/star.yaml",
                           {"mesh.target_tets=300"});
  const TetMesh mesh = make_scene_mesh(scene);
  const MaterialField stiff = MaterialField::uniform(mesh.num_tets(), scene.reference_Y,
                                                     scene.reference_nu, scene.reference_rho, 1.0);
  EvaluationOptions options;
  options.time_step = h;
  options.soft_control = false;
  const Evaluation ev = evaluate(scene, mesh, mesh, stiff, options);
  ASSERT_EQ(ev.calibrations.size(), 2u);
  const RestitutionCalibration& wall = ev.calibrations[1];
  EXPECT_EQ(wall.plane, 1);
  ASSERT_EQ(wall.roots.size(), 2u);
  std::printf("wall rebound %.4f from restitutions %.6f and %.6f; kept %.6f\n",
              wall.deformable_rebound, wall.roots[0], wall.roots[1], wall.restitution);

  scene.time_step = h;
  scene.duration = ev.duration;
  RigidSettings settings = options.rigid;
  settings.margin = std::min(settings.margin, scene.d_hat);
  auto twin_gap = [&](double wall_restitution, RunComparison* against_rigid) {
    settings.plane_restitution = {ev.calibrations[0].restitution, wall_restitution};
    RunTrace twin;
    for (const RigidState& state :
         simulate_rigid(rigid_mass_properties(ev.reference_moments), rigid_shape_from_surface(mesh),
                        scene, settings, scene.duration)) {
      twin.time.push_back(state.time);
      twin.centre.push_back(state.position);
      twin.velocity.push_back(state.velocity);
      twin.rotation.push_back(state.orientation);
    }
    if (against_rigid) *against_rigid = compare_runs(twin, ev.rigid_reference);
    return compare_runs(twin, ev.deformable_reference).max_position_gap;
  };
  RunComparison kept_vs_rigid;
  const double kept = twin_gap(wall.restitution, &kept_vs_rigid);
  EXPECT_EQ(kept_vs_rigid.max_position_gap, 0.0);  // the re-run is evaluate's twin
  const double other_restitution = wall.roots[0] == wall.restitution ? wall.roots[1] : wall.roots[0];
  const double other = twin_gap(other_restitution, nullptr);
  std::printf("twin vs baseline: kept %.4f m, other %.4f m\n", kept, other);
  EXPECT_LT(kept, other);
  // Not the nearest to the rebound: picked by closeness, not by the default.
  EXPECT_GT(std::abs(wall.restitution - wall.deformable_rebound),
            std::abs(other_restitution - wall.deformable_rebound));
}

TEST(Evaluation, RigidTwinsAgreeCalibrationHoldsAndOutputsRoundTrip) {
  const Scene scene = ball_scene();
  const TetMesh mesh = make_scene_mesh(scene);
  const MaterialField adv = adversarial_field(mesh, scene);
  EvaluationOptions options;
  options.duration = 0.2;
  options.time_step = scene.time_step;
  const auto clock_start = std::chrono::steady_clock::now();
  const Evaluation ev = evaluate(scene, mesh, mesh, adv, options);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - clock_start).count();

  // Calibration: the rigid reference reproduces the baseline's first rebound within 1 %.
  ASSERT_EQ(ev.calibrations.size(), 1u);
  const RestitutionCalibration& cal = ev.calibrations[0];
  ASSERT_TRUE(cal.calibrated);
  EXPECT_GT(cal.deformable_rebound, 0.1);
  EXPECT_NEAR(cal.rigid_rebound / cal.deformable_rebound, 1.0, 0.01);
  // Equal moments: identical rigid trajectories; the deformable ones may differ.
  EXPECT_LT(ev.rigid_vs_rigid.max_position_gap, 1e-9);
  EXPECT_LT(ev.rigid_vs_rigid.orientation_gap_deg, 1e-6);
  EXPECT_EQ(ev.rigid_reference.centre.size(), 21u);
  EXPECT_EQ(ev.deformable_adversarial.centre.size(), 21u);
  EXPECT_NEAR((ev.reference_moments.as_vector() - ev.adversarial_moments.as_vector()).norm() /
                  ev.reference_moments.m0, 0.0, 1e-10);

  // Each deformable run's wall time (report.json's timing_s, the outcome table's wall column) is
  // its own, its set-up and its steps: positive (its 20 steps take ~25x its set-up) and within the
  // whole evaluation's.
  for (const RunTrace* t : {&ev.deformable_reference, &ev.deformable_adversarial, &ev.deformable_soft}) {
    EXPECT_GT(t->seconds, 0) << t->name;
    EXPECT_LT(t->seconds, wall) << t->name;
  }

  const test::ScratchDir scratch;
  const std::string dir = scratch.path().string();
  write_evaluation(ev, scene, dir);
  std::ifstream in(dir + "/report.json");
  const auto report = nlohmann::json::parse(in);
  EXPECT_EQ(report["moments"]["reference"].size(), 10u);
  EXPECT_DOUBLE_EQ(report["deformable_vs_deformable"]["com_gap_m"].get<double>(),
                   ev.deformable_vs_deformable.position_gap);
  EXPECT_DOUBLE_EQ(report["calibration"][0]["restitution"].get<double>(), cal.restitution);
  EXPECT_DOUBLE_EQ(report["soft_control"]["vs_baseline"]["com_gap_m"].get<double>(), ev.soft_vs_deformable.position_gap);
  EXPECT_DOUBLE_EQ(report["adversarial_vs_rigid"]["com_gap_m"].get<double>(), ev.adversarial_vs_rigid.position_gap);
  // The summary's prose carries the same figures as report.json: the baseline's disagreement in
  // percent of its path.
  {
    const std::string summary = test::read_text(dir + "/summary.md");
    const std::string lead = "The baseline strays from the rigid reference by at most ";
    const std::size_t at = summary.find(lead);
    ASSERT_NE(at, std::string::npos) << summary;
    const double percent = std::stod(summary.substr(at + lead.size()));
    EXPECT_NEAR(percent, 100 * ev.baseline_disagreement, 1e-2 * 100 * ev.baseline_disagreement + 1e-12);
    // And it names what it compared: the object, by that word when it has no other name.
    EXPECT_NE(summary.find("Compared: the object's centre of mass."), std::string::npos) << summary;
  }
  // Another name, and a contact the twin never met (its rigid rebound NaN): "body 'ball'", no
  // stray possessive, and "-" where the rebound would be, not "nan" and not 0.
  {
    Scene named = scene;
    named.object_name = "ball";
    Evaluation unmet = ev;
    unmet.calibrations[0].calibrated = false;
    unmet.calibrations[0].restitution = 1.0;
    unmet.calibrations[0].rigid_rebound = std::nan("");
    write_evaluation(unmet, named, dir);
    const std::string summary = test::read_text(dir + "/summary.md");
    EXPECT_NE(summary.find("Compared: the centre of mass of body 'ball'."), std::string::npos) << summary;
    EXPECT_EQ(summary.find("''s"), std::string::npos) << summary;
    EXPECT_NE(summary.find(" | - (not fitted) | 1 |"), std::string::npos) << summary;
    std::ifstream json(dir + "/report.json");
    EXPECT_TRUE(nlohmann::json::parse(json)["calibration"][0]["rigid_first_rebound"].is_null());
    write_evaluation(ev, scene, dir);  // back to the run's own outputs, read below
  }
  // The adversarial object's materials picture (data and script always; PNG with gnuplot).
  EXPECT_TRUE(std::filesystem::exists(dir + "/adversarial_materials.dat"));
  if (std::system("command -v gnuplot >/dev/null 2>&1") == 0) {
    EXPECT_EQ(report["materials_plot"].get<std::string>(), "adversarial_materials.png");
  }
  for (const char* f : {"summary.md", "rigid_reference.csv", "rigid_adversarial.csv", "deformable_reference.csv",
                        "deformable_adversarial.csv", "deformable_soft_uniform.csv", "paths.gp"}) {
    EXPECT_TRUE(std::filesystem::exists(dir + "/" + f)) << f;
  }

  // A step search whose disagreement did not fall with h (the bin's: 7.69, 4.70, 6.85 %): the
  // summary names the least and its step beside the finest one it keeps; one that fell does not.
  const auto summary_of = [&](const std::vector<double>& strays) {
    Evaluation searched = ev;
    searched.step_search.clear();
    for (size_t i = 0; i < strays.size(); ++i) {
      BaselineTrial t;
      t.time_step = 0.01 / std::pow(4.0, static_cast<double>(i));
      t.disagreement = strays[i];
      searched.step_search.push_back(t);
    }
    searched.baseline_tolerance = 0.005;
    searched.baseline_disagreement = strays.back();
    write_evaluation(searched, scene, dir);
    const std::string summary = test::read_text(dir + "/summary.md");
    return summary;
  };
  const std::string rose = summary_of({0.0769, 0.0470, 0.0685});
  EXPECT_NE(rose.find("A coarser step strayed less (4.7 % at h = 0.0025 s)"), std::string::npos) << rose;
  EXPECT_NE(rose.find("the last took it from 4.7 % to 6.85 %"), std::string::npos) << rose;
  const std::string fell = summary_of({0.0769, 0.0470, 0.0185});
  EXPECT_EQ(fell.find("A coarser step strayed less"), std::string::npos) << fell;
}

// Issue 20 item 4: every deformable run also gets a rigid twin calibrated to its own rebound.
// Each twin reproduces its own run's first rebound (1 %); report.json carries the figures. (At
// this coarse step all three balls rebound at ~0.43 and every twin strays ~9 % of the path: the
// step, not the object, dominates, which is why evaluate refines its step; a fitted rebound
// is also no promise of a smaller largest gap, so none is asserted.)
TEST(Evaluation, EachRunHasARigidTwinCalibratedToItsOwnRebound) {
  const Scene scene = ball_scene();
  const TetMesh mesh = make_scene_mesh(scene);
  const MaterialField adv = adversarial_field(mesh, scene);
  EvaluationOptions options;
  options.duration = 0.2;
  options.time_step = scene.time_step;
  const Evaluation ev = evaluate(scene, mesh, mesh, adv, options);
  ASSERT_FALSE(ev.deformable_soft.time.empty());
  struct Named {
    const char* name;
    const OwnTwin* twin;
    const RunTrace* run;
  };
  for (const Named& n : {Named{"reference", &ev.reference_own_twin, &ev.deformable_reference},
                         Named{"adversarial", &ev.adversarial_own_twin, &ev.deformable_adversarial},
                         Named{"soft", &ev.soft_own_twin, &ev.deformable_soft}}) {
    ASSERT_EQ(n.twin->calibrations.size(), 1u) << n.name;
    const RestitutionCalibration& c = n.twin->calibrations[0];
    ASSERT_TRUE(c.calibrated) << n.name;
    EXPECT_NEAR(c.rigid_rebound / c.deformable_rebound, 1.0, 0.01) << n.name;
    const RunComparison against_reference_twin = compare_runs(*n.run, ev.rigid_reference);
    std::printf("%-11s: own restitution %.4f (rebound %.4f), unexplained %.3e of %.3f m; against the "
                "reference's twin %.3e m, own twin %.3e m\n",
                n.name, c.restitution, c.deformable_rebound, n.twin->unexplained, n.twin->path_length,
                against_reference_twin.max_position_gap, n.twin->gap.max_position_gap);
    EXPECT_NEAR(n.twin->unexplained, n.twin->gap.max_position_gap / n.twin->path_length, 1e-15);
  }
  // The baseline's own twin is the rigid reference itself.
  EXPECT_EQ(ev.reference_own_twin.gap.max_position_gap, ev.deformable_vs_rigid.max_position_gap);
  // The soft control's twin is fitted to the soft run's rebound, not the baseline's.
  EXPECT_NE(ev.soft_own_twin.calibrations[0].deformable_rebound, ev.calibrations[0].deformable_rebound);

  const test::ScratchDir scratch;
  const std::string dir = scratch.path().string();
  write_evaluation(ev, scene, dir);
  std::ifstream in(dir + "/report.json");
  const auto twins = nlohmann::json::parse(in)["own_calibrated_twins"];
  EXPECT_DOUBLE_EQ(twins["adversarial"]["unexplained"].get<double>(), ev.adversarial_own_twin.unexplained);
  EXPECT_DOUBLE_EQ(twins["soft_control"]["calibration"][0]["restitution"].get<double>(),
                   ev.soft_own_twin.calibrations[0].restitution);
  EXPECT_DOUBLE_EQ(twins["reference"]["vs_own_twin"]["max_com_gap_m"].get<double>(),
                   ev.deformable_vs_rigid.max_position_gap);
}

TEST(Evaluation, RunsAtTheConfigsEvaluationStepAndTheFlagOverridesIt) {
  Scene scene = ball_scene();
  scene.evaluation_search_step = false;
  scene.evaluation_time_step = 0.005;
  scene.evaluation_duration = 0.1;
  const TetMesh mesh = make_scene_mesh(scene);
  const MaterialField adv = adversarial_field(mesh, scene);
  const Evaluation ev = evaluate(scene, mesh, mesh, adv);
  EXPECT_DOUBLE_EQ(ev.time_step, 0.005);
  EXPECT_DOUBLE_EQ(ev.attack_time_step, 0.01);
  EXPECT_DOUBLE_EQ(ev.duration, 0.1);
  for (const RunTrace* t : {&ev.rigid_reference, &ev.deformable_reference, &ev.deformable_adversarial}) {
    ASSERT_EQ(t->time.size(), 21u) << t->name;
    EXPECT_NEAR(t->time[1], 0.005, 1e-15) << t->name;
  }
  // The baseline's path: 0.1 s at about 2 m/s; its disagreement with the rigid reference is a
  // fraction of it, and the adversarial-vs-rigid comparison is filled in.
  EXPECT_GT(ev.baseline_path_length, 0.15);
  EXPECT_LT(ev.baseline_path_length, 0.25);
  EXPECT_NEAR(ev.baseline_disagreement, ev.deformable_vs_rigid.max_position_gap / ev.baseline_path_length, 1e-15);
  EXPECT_EQ(ev.adversarial_vs_rigid.a, "deformable adversarial");
  EXPECT_EQ(ev.adversarial_vs_rigid.b, "rigid reference");
  // The soft control: same shape and moments, uniform at the lowest Y; it bounces differently
  // from the stiff baseline, and the rigid twins cannot tell.
  EXPECT_DOUBLE_EQ(ev.soft_Y, scene.Y_range.lo);
  ASSERT_EQ(ev.deformable_soft.time.size(), 21u);
  EXPECT_GT(ev.soft_vs_deformable.max_position_gap, 0.0);
  EXPECT_EQ(ev.soft_vs_deformable.b, "deformable soft uniform");

  EvaluationOptions options;
  options.time_step = 0.02;  // the command line's --time_step wins over the config
  options.soft_control = false;
  const Evaluation coarse = evaluate(scene, mesh, mesh, adv, options);
  EXPECT_DOUBLE_EQ(coarse.time_step, 0.02);
  EXPECT_EQ(coarse.deformable_reference.time.size(), 6u);
  EXPECT_TRUE(coarse.deformable_soft.time.empty());
  options.duration = 0.01;  // shorter than one step
  EXPECT_THROW(evaluate(scene, mesh, mesh, adv, options), InputError);
}

TEST(Evaluation, StepSearchRefinesUntilTheBaselineAgreesWithItsRigidTwin) {
  Scene scene = ball_scene();
  scene.time_step = 0.02;  // coarse: the bounce takes a whole step and the baseline lags its twin
  scene.duration = 0.05;
  scene.evaluation_duration = 0.16;
  scene.evaluation_baseline_tolerance = 0.01;
  const TetMesh mesh = make_scene_mesh(scene);
  const MaterialField adv = adversarial_field(mesh, scene);
  const Evaluation ev = evaluate(scene, mesh, mesh, adv);
  ASSERT_GE(ev.step_search.size(), 2u);
  for (size_t k = 0; k < ev.step_search.size(); ++k) {
    EXPECT_DOUBLE_EQ(ev.step_search[k].time_step, 0.02 / std::pow(4.0, k));
  }
  // It stops at the first step within the tolerance (or after the last refinement).
  for (size_t k = 0; k + 1 < ev.step_search.size(); ++k) EXPECT_GT(ev.step_search[k].disagreement, 0.01);
  EXPECT_TRUE(ev.step_search.back().disagreement <= 0.01 ||
              static_cast<int>(ev.step_search.size()) == scene.evaluation_max_refinements + 1);
  EXPECT_LT(ev.step_search.back().disagreement, ev.step_search.front().disagreement);
  EXPECT_DOUBLE_EQ(ev.time_step, ev.step_search.back().time_step);
  EXPECT_DOUBLE_EQ(ev.baseline_disagreement, ev.step_search.back().disagreement);
  EXPECT_NEAR(ev.deformable_adversarial.time[1], ev.time_step, 1e-15);

  EvaluationOptions fixed;
  fixed.time_step = 0.01;  // an explicit step turns the search off
  EXPECT_EQ(evaluate(scene, mesh, mesh, adv, fixed).step_search.size(), 1u);
}

// An object whose materials are not moment-matched (here dense on the +x side) starts with its
// own centre of mass at object.position, in both simulators, not with its centroid there.
TEST(Evaluation, AdversarialCentreOfMassStartsAtThePosition) {
  const Scene scene = ball_scene();
  const TetMesh mesh = make_scene_mesh(scene);
  MaterialField adv = MaterialField::uniform(mesh.num_tets(), 1e10, 0.3, 2500);
  for (int e = 0; e < mesh.num_tets(); ++e) {
    double x = 0;
    for (int k = 0; k < 4; ++k) x += mesh.V(mesh.T(e, k), 0) / 4;
    adv.rho[e] = x > scene.position.x() ? 11300 : 800;
  }
  ASSERT_GT(
      (compute_moments(mesh, adv.effective_density()).centre_of_mass() - scene.position).norm(),
      1e-3);
  EvaluationOptions options;
  options.time_step = scene.time_step;
  options.soft_control = false;
  const Evaluation ev = evaluate(scene, mesh, mesh, adv, options);
  const double tol = 1e-12 * scene.position.norm();
  EXPECT_LT((ev.deformable_adversarial.centre[0] - scene.position).norm(), tol);
  // The twin's centre is on its grid (rigid_mass_properties: 2^-24 of the radius of gyration).
  EXPECT_LT((ev.rigid_adversarial.centre[0] - scene.position).norm(),
            tol + std::ldexp(radius_of_gyration(ev.adversarial_moments), -22));
  EXPECT_LT((ev.adversarial_moments.centre_of_mass() - scene.position).norm(), tol);
}

// An object that never moves (at rest, no gravity, nothing to meet): its path is round-off
// (4e-18 m) and its twin sits the twin's own resolution away (3.7e-10 m: the centre on a grid of
// 2^-24 of the radius of gyration). The shares the twins do not explain count the path at least
// as long as the ball's radius (0.1 m), so they read ~4e-9, not 8.9e7 (gap / round-off).
TEST(Evaluation, AnObjectAtRestHasNoUnexplainedShareOfItsPath) {
  Scene scene = ball_scene();
  scene.velocity.setZero();
  scene.angular_velocity.setZero();
  scene.kappa = 1e3;  // the energy rule has no motion to go by
  const TetMesh mesh = make_scene_mesh(scene);
  EvaluationOptions options;
  options.time_step = scene.time_step;
  options.duration = scene.duration;
  const Evaluation ev =
      evaluate(scene, mesh, mesh, MaterialField::uniform(mesh.num_tets(), 1e10, 0.3, 2500), options);
  for (const OwnTwin* t : {&ev.reference_own_twin, &ev.adversarial_own_twin, &ev.soft_own_twin}) {
    EXPECT_LT(t->path_length, 1e-15);
    EXPECT_LT(t->gap.max_position_gap, 1e-9);
    EXPECT_LT(t->unexplained, 1e-8) << t->gap.max_position_gap << " m over " << t->path_length << " m";
  }
  EXPECT_LT(ev.baseline_path_length, 1e-15);
  EXPECT_LT(ev.baseline_disagreement, 1e-8);
}

TEST(Evaluation, MismatchedObjectsAreRejected) {
  const Scene scene = ball_scene();
  const TetMesh mesh = make_scene_mesh(scene);
  TetMesh other = mesh;
  other.V.col(0) *= 1.01;  // not the same surface
  const MaterialField adv = MaterialField::uniform(mesh.num_tets(), 1e10, 0.3, 2500);
  EXPECT_THROW(evaluate(scene, mesh, other, adv), InputError);
  const MaterialField short_field = MaterialField::uniform(mesh.num_tets() - 1, 1e10, 0.3, 2500);
  EXPECT_THROW(evaluate(scene, mesh, mesh, short_field), InputError);
}

}  // namespace
}  // namespace rbaa
