// Demonstration predicates (eval/demonstration.hpp) on synthetic paths: each predicate's true and
// false cases and its edges (a crossing upwards, a crossing outside the opening, a body that
// bounced out over the bin's top and fell back in, a tilted or fallen cube).

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "rbaa/error.hpp"
#include "rbaa/eval/demonstration.hpp"

namespace rbaa {
namespace {

// A straight path from a to b in n + 1 samples, not rotating.
BodyPath straight(const Eigen::Vector3d& a, const Eigen::Vector3d& b, int n = 10,
                  double radius = 0.1) {
  BodyPath p;
  p.name = "object";
  p.bounding_radius = radius;
  for (int k = 0; k <= n; ++k) {
    const double s = static_cast<double>(k) / n;
    p.time.push_back(0.1 * k);
    p.centre.push_back(a + s * (b - a));
    p.rotation.push_back(Eigen::Quaterniond::Identity());
    p.velocity.push_back((b - a) / (0.1 * n));
  }
  return p;
}

const Eigen::Vector3d kHoop(0, 0, 3);
const Eigen::Vector3d kUp(0, 0, 1);

TEST(ThroughHoop, ADownwardCrossingInsideTheOpeningCounts) {
  // Radius 0.25, bounding radius 0.1: crossings within 0.15 of the centre count.
  const PredicateOutcome o = through_hoop(straight({0.12, 0, 4}, {0.12, 0, 2}), kHoop, kUp, 0.25);
  EXPECT_TRUE(o.holds) << o.detail;
  // A slanted path: the crossing point is interpolated between the samples around it.
  EXPECT_TRUE(through_hoop(straight({-0.3, 0, 4}, {0.3, 0, 2.5}, 7), kHoop, kUp, 0.25).holds);
}

TEST(ThroughHoop, CrossingUpwardsDoesNotCount) {
  const PredicateOutcome o = through_hoop(straight({0, 0, 2}, {0, 0, 4}), kHoop, kUp, 0.25);
  EXPECT_FALSE(o.holds);
  EXPECT_NE(o.detail.find("never crosses"), std::string::npos) << o.detail;
}

TEST(ThroughHoop, CrossingOutsideTheRadiusLessTheBodysDoesNotCount) {
  // 0.16 from the centre: inside the opening (0.25), but the body (0.1) would hit the rim.
  EXPECT_FALSE(through_hoop(straight({0.16, 0, 4}, {0.16, 0, 2}), kHoop, kUp, 0.25).holds);
  EXPECT_FALSE(through_hoop(straight({1.0, 0, 4}, {1.0, 0, 2}), kHoop, kUp, 0.25).holds);
  // The same path for a point-sized body passes.
  EXPECT_TRUE(through_hoop(straight({0.16, 0, 4}, {0.16, 0, 2}, 10, 0.0), kHoop, kUp, 0.25).holds);
}

TEST(ThroughHoop, UpThroughThenDownOutsideIsFalseAndTheAxisSetsDown) {
  // Up through the middle, then down beside the hoop.
  BodyPath p = straight({0, 0, 2}, {0, 0, 4});
  const BodyPath down = straight({0.6, 0, 4}, {0.6, 0, 2});
  p.centre.insert(p.centre.end(), down.centre.begin(), down.centre.end());
  p.time.resize(p.centre.size(), 0.0);
  EXPECT_FALSE(through_hoop(p, kHoop, kUp, 0.25).holds);
  // With the axis reversed, "down" is +z: the path up through the middle counts.
  EXPECT_TRUE(through_hoop(p, kHoop, -kUp, 0.25).holds);
}

TEST(ThroughHoop, DippingInAndComingBackUpThroughTheOpeningIsARimOut) {
  // Down through the middle to 0.2 m below the plane, back up through it, away beside the hoop.
  BodyPath p = straight({0.05, 0, 3.5}, {0.05, 0, 2.8}, 7);
  const BodyPath back = straight({0.05, 0, 2.8}, {0.1, 0, 3.5}, 7);
  const BodyPath away = straight({0.1, 0, 3.5}, {1.0, 0, 2.0}, 7);
  p.centre.insert(p.centre.end(), back.centre.begin() + 1, back.centre.end());
  p.centre.insert(p.centre.end(), away.centre.begin() + 1, away.centre.end());
  p.time.resize(p.centre.size(), 0.0);
  const PredicateOutcome o = through_hoop(p, kHoop, kUp, 0.25);
  EXPECT_FALSE(o.holds);
  EXPECT_NE(o.detail.find("came back up"), std::string::npos) << o.detail;
  // Up again outside the opening (a bounce off the floor beside the hoop) cancels nothing.
  BodyPath in = straight({0.05, 0, 3.5}, {0.05, 0, 2.0}, 7);
  const BodyPath bounce = straight({0.05, 0, 2.0}, {0.6, 0, 3.5}, 7);
  in.centre.insert(in.centre.end(), bounce.centre.begin() + 1, bounce.centre.end());
  in.time.resize(in.centre.size(), 0.0);
  EXPECT_TRUE(through_hoop(in, kHoop, kUp, 0.25).holds);
}

TEST(ThroughHoop, TheCrossingIsJudgedWhereItHappensNotAtTheSamples) {
  // Two samples, 1 m either side of the plane, the line between them crossing at 0.05 m from the
  // centre although both samples are 0.5 m off the axis.
  BodyPath p;
  p.name = "object";
  p.bounding_radius = 0.1;
  p.time = {0, 1};
  p.centre = {Eigen::Vector3d(-0.45, 0, 4), Eigen::Vector3d(0.55, 0, 2)};
  EXPECT_TRUE(through_hoop(p, kHoop, kUp, 0.25).holds);
}

TEST(InsideBox, EndsInsideOrOutside) {
  const Eigen::Vector3d lo(-1, -1, 0), hi(1, 1, 1);
  EXPECT_TRUE(inside_box(straight({0, 5, 3}, {0, 0.5, 0.3}), lo, hi, false).holds);
  const PredicateOutcome out = inside_box(straight({0, 5, 3}, {0, -1.2, 0.3}), lo, hi, false);
  EXPECT_FALSE(out.holds);
  EXPECT_NE(out.detail.find("outside"), std::string::npos) << out.detail;
  // Passing through the box and leaving it is not ending inside.
  EXPECT_FALSE(inside_box(straight({0, 5, 0.5}, {0, -5, 0.5}), lo, hi, false).holds);
}

TEST(InsideBox, StaysBelowTopRefusesABounceOutAndBackIn) {
  const Eigen::Vector3d lo(-1, -1, 0), hi(1, 1, 1);
  // In at z = 0.5, up to 1.5 (above the top), back down to 0.2.
  BodyPath p = straight({0, 0, 0.5}, {0, 0, 1.5}, 4);
  const BodyPath back = straight({0, 0, 1.5}, {0, 0, 0.2}, 4);
  p.centre.insert(p.centre.end(), back.centre.begin() + 1, back.centre.end());
  p.time.resize(p.centre.size(), 0.0);
  EXPECT_TRUE(inside_box(p, lo, hi, false).holds);
  EXPECT_FALSE(inside_box(p, lo, hi, true).holds);
  // Falling in from above the top is fine: only after the first sample inside does it count.
  EXPECT_TRUE(inside_box(straight({0, 0, 3}, {0, 0, 0.2}), lo, hi, true).holds);
}

TEST(Stands, TiltAndHeight) {
  BodyPath p = straight({0, 0, 0.1}, {0, 0, 0.1});
  EXPECT_TRUE(stands(p, 10, 0.05).holds);
  EXPECT_FALSE(stands(p, 10, 0.2).holds);  // below the height
  p.rotation.back() =
      Eigen::Quaterniond(Eigen::AngleAxisd(9.0 * M_PI / 180, Eigen::Vector3d::UnitX()));
  EXPECT_TRUE(stands(p, 10, 0.05).holds);
  p.rotation.back() =
      Eigen::Quaterniond(Eigen::AngleAxisd(11.0 * M_PI / 180, Eigen::Vector3d::UnitY()));
  EXPECT_FALSE(stands(p, 10, 0.05).holds);
  // A spin about the vertical is no tilt.
  p.rotation.back() = Eigen::Quaterniond(Eigen::AngleAxisd(2.0, Eigen::Vector3d::UnitZ()));
  EXPECT_TRUE(stands(p, 10, 0.05).holds);
  // Fallen on its side.
  p.rotation.back() = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()));
  EXPECT_FALSE(stands(p, 10, 0.05).holds);
}

TEST(EvaluatePredicate, StandsNeedsEveryNamedBodyAndNamesTheOneThatFell) {
  PredicateSpec spec;
  spec.kind = PredicateSpec::Kind::kStands;
  spec.bodies = {"low", "high"};
  spec.min_height = {0.02, 0.1};
  BodyPath low = straight({0, 0, 0.026}, {0, 0, 0.026});
  low.name = "low";
  BodyPath high = straight({0, 0, 0.128}, {0, 0, 0.128});
  high.name = "high";
  EXPECT_TRUE(evaluate_predicate(spec, {low, high}).holds);
  high.centre.back().z() = 0.03;  // fell off
  const PredicateOutcome o = evaluate_predicate(spec, {low, high});
  EXPECT_FALSE(o.holds);
  EXPECT_NE(o.detail.find("high: tilt"), std::string::npos) << o.detail;
  // One height for all.
  spec.min_height = {0.02};
  EXPECT_TRUE(evaluate_predicate(spec, {low, high}).holds);
  // A name without a path.
  spec.bodies = {"low", "gone"};
  EXPECT_THROW(evaluate_predicate(spec, {low, high}), InputError);
}

TEST(EvaluatePredicate, HoopAndBoxReadTheirBody) {
  PredicateSpec hoop;
  hoop.kind = PredicateSpec::Kind::kThroughHoop;
  hoop.body = "ball";
  hoop.centre = kHoop;
  hoop.radius = 0.25;
  BodyPath ball = straight({0, 0, 4}, {0, 0, 2});
  ball.name = "ball";
  const BodyPath beside = straight({1, 0, 4}, {1, 0, 2});  // the object, beside the hoop
  EXPECT_TRUE(evaluate_predicate(hoop, {beside, ball}).holds);
  hoop.body = "object";
  EXPECT_FALSE(evaluate_predicate(hoop, {beside, ball}).holds);
}

// A body flying free under gravity g after leaving at velocity v0 (t = 0): its velocity at t.
Eigen::Vector3d falling(const Eigen::Vector3d& v0, double t) {
  return v0 + t * Eigen::Vector3d(0, 0, -9.8);
}

TEST(ProjectedAngle, TheHorizontalHeadingSurvivesTheFallThe3dAngleDoesNot) {
  // Two balls leaving 5 deg apart in heading, both level: after 2 s of free fall the 3D angle
  // between their velocities has shrunk (both now mostly point down), the heading has not.
  const double a = 5 * M_PI / 180;
  const Eigen::Vector3d v1(0, 7.5, 0), v2(7.5 * std::sin(a), 7.5 * std::cos(a), 0);
  const Eigen::Vector3d g(0, 0, -9.8);
  EXPECT_NEAR(angle_between_deg(v1, v2), 5.0, 1e-12);
  EXPECT_LT(angle_between_deg(falling(v1, 2), falling(v2, 2)), 2.0);
  EXPECT_NEAR(projected_angle_deg(falling(v1, 2), falling(v2, 2), g), 5.0, 1e-12);
  // Without a normal, the plain angle; the normal's length does not matter.
  EXPECT_EQ(projected_angle_deg(falling(v1, 2), falling(v2, 2), Eigen::Vector3d::Zero()),
            angle_between_deg(falling(v1, 2), falling(v2, 2)));
  EXPECT_NEAR(projected_angle_deg(falling(v1, 2), falling(v2, 2), 1e-3 * g), 5.0, 1e-12);
  // A velocity along the normal has no heading: 0, as for a zero vector.
  EXPECT_EQ(projected_angle_deg(Eigen::Vector3d(0, 0, -3), v2, g), 0.0);
}

// Six runs whose figure body leaves in the directions given (deg from +y, in the xy-plane).
std::vector<DemonstrationRun> six_runs(const std::vector<double>& heading_deg) {
  const char* names[6][3] = {{"rigid reference", "rigid", "reference"},
                             {"rigid adversarial", "rigid", "adversarial"},
                             {"rigid soft control", "rigid", "soft control"},
                             {"deformable reference", "deformable", "reference"},
                             {"deformable adversarial", "deformable", "adversarial"},
                             {"deformable soft control", "deformable", "soft control"}};
  std::vector<DemonstrationRun> runs;
  for (int i = 0; i < 6; ++i) {
    const double a = heading_deg[i] * M_PI / 180;
    BodyPath p = straight({0, 0, 0}, {std::sin(a), std::cos(a), -2});
    p.name = "ball";
    runs.push_back({names[i][0], names[i][1], names[i][2], {straight({0, 0, 0}, {0, 0, 1}), p}});
  }
  return runs;
}

TEST(DemonstrationOutcomes, TheFigureAgainstTheRigidOrTheOwnSimulatorsReference) {
  DemonstrationSpec demo;
  demo.enabled = true;
  demo.figure = "angle";
  demo.figure_body = "ball";
  demo.figure_horizontal = true;
  const Eigen::Vector3d g(0, 0, -9.8);
  // The deformable reference leaves 2 deg off the rigid one, the deformable adversarial 10 deg.
  const std::vector<DemonstrationRun> runs = six_runs({0, 0, 0, 2, 10, 6});
  const std::vector<DemonstrationOutcome> rigid = demonstration_outcomes(demo, runs, g);
  ASSERT_EQ(rigid.size(), 6u);
  EXPECT_NEAR(rigid[1].figure, 0.0, 1e-12);
  EXPECT_NEAR(rigid[3].figure, 2.0, 1e-9);
  EXPECT_NEAR(rigid[4].figure, 10.0, 1e-9);
  EXPECT_FALSE(rigid[4].has_predicate);

  demo.figure_against_own_simulator = true;
  const std::vector<DemonstrationOutcome> own = demonstration_outcomes(demo, runs, g);
  EXPECT_NEAR(own[1].figure, 0.0, 1e-12);
  EXPECT_NEAR(own[3].figure, 0.0, 1e-12);  // the deformable reference against itself
  EXPECT_NEAR(own[4].figure, 8.0, 1e-9);   // the separation the paper reports
  EXPECT_NEAR(own[5].figure, 4.0, 1e-9);
  EXPECT_EQ(own[4].run, "deformable adversarial");

  // Unprojected, the common fall (z -2 against a heading of length 1) shrinks the angle.
  demo.figure_horizontal = false;
  EXPECT_LT(demonstration_outcomes(demo, runs, g)[4].figure, 4.0);

  // A run that was not made has no row; a missing reference run leaves the figure NaN.
  std::vector<DemonstrationRun> no_deformable_reference = runs;
  no_deformable_reference[3].paths.clear();
  const auto rows = demonstration_outcomes(demo, no_deformable_reference, g);
  ASSERT_EQ(rows.size(), 5u);
  EXPECT_TRUE(std::isnan(rows[3].figure)) << rows[3].run;
  EXPECT_FALSE(std::isnan(rows[1].figure));
}

TEST(DemonstrationOutcomes, AFigureBodyWithoutAPathIsAnError) {
  DemonstrationSpec demo;
  demo.figure = "angle";
  demo.figure_body = "ghost";
  try {
    demonstration_outcomes(demo, six_runs({0, 0, 0, 0, 0, 0}), Eigen::Vector3d(0, 0, -9.8));
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("body 'ghost'"), std::string::npos) << e.what();
  }
}

TEST(BoundingRadius, FarthestVertex) {
  Eigen::MatrixXd V(3, 3);
  V << 1, 0, 0, 0, 2, 0, 0, 0, -0.5;
  EXPECT_DOUBLE_EQ(bounding_radius(V, Eigen::Vector3d::Zero()), 2.0);
}

}  // namespace
}  // namespace rbaa
