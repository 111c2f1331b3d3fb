// The final-poses picture of a demonstration (eval/final_poses_plot.hpp): 2D convex hulls, a
// body's outline moved by its final pose, and a script with one panel per run whose data hold
// every body's outline (a standing and a toppled two-cube stack).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "io/io_test_support.hpp"
#include "rbaa/error.hpp"
#include "rbaa/eval/final_poses_plot.hpp"

namespace rbaa {
namespace {

TEST(ConvexHull2d, KeepsTheCornersCounterClockwise) {
  Eigen::MatrixXd p(7, 2);
  p << 0, 0, 1, 0, 1, 1, 0, 1, 0.5, 0.5, 0.5, 0, 0.2,
      0.7;  // a square, its centre, edge and inner points
  const Eigen::MatrixXd h = convex_hull_2d(p);
  ASSERT_EQ(h.rows(), 4);
  double area = 0;  // shoelace: positive when counter-clockwise
  for (int i = 0; i < 4; ++i) {
    const int j = (i + 1) % 4;
    area += h(i, 0) * h(j, 1) - h(j, 0) * h(i, 1);
  }
  EXPECT_NEAR(area / 2, 1.0, 1e-15);
  // Degenerate inputs come back as they are (deduplicated).
  Eigen::MatrixXd two(3, 2);
  two << 0, 0, 1, 1, 0, 0;
  EXPECT_EQ(convex_hull_2d(two).rows(), 2);
}

// A cube of side s about c: its 8 corners.
BodyShape cube(const std::string& name, const Eigen::Vector3d& c, double s) {
  BodyShape b{name, Eigen::MatrixXd(8, 3)};
  for (int i = 0; i < 8; ++i)
    b.V.row(i) =
        (c + 0.5 * s * Eigen::Vector3d(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1)).transpose();
  return b;
}

// A path from `from` to `to`, turning by `angle_deg` about x.
BodyPath moved(const std::string& name, const Eigen::Vector3d& from, const Eigen::Vector3d& to,
               double angle_deg) {
  BodyPath p;
  p.name = name;
  for (int k = 0; k <= 4; ++k) {
    const double s = k / 4.0;
    p.time.push_back(0.1 * k);
    p.centre.push_back(from + s * (to - from));
    p.rotation.emplace_back(
        Eigen::AngleAxisd(s * angle_deg * M_PI / 180, Eigen::Vector3d::UnitX()));
    p.velocity.push_back((to - from) / 0.4);
  }
  return p;
}

// The two-cube stack the pictures below draw: the bottom cube and the middle one offset along -y.
const Eigen::Vector3d kLow(0, 0, 0.026), kHigh(0, -0.0225, 0.077);
std::vector<BodyShape> two_cubes() {
  return {cube("bottom", kLow, 0.05), cube("middle", kHigh, 0.05)};
}
// Its final poses: standing (nothing moves), or toppled (the middle cube falls off along +y onto
// its side, or ends `far` along y).
std::vector<BodyPath> standing() {
  return {moved("bottom", kLow, kLow, 0), moved("middle", kHigh, kHigh, 0)};
}
std::vector<BodyPath> toppled(double far = 0.06) {
  return {moved("bottom", kLow, kLow, 0), moved("middle", kHigh, Eigen::Vector3d(0, far, 0.026), 90)};
}

TEST(FinalOutline, ACubeTurned45DegAboutXIsADiamondInTheSideView) {
  const BodyShape c = cube("top", Eigen::Vector3d(0, 0, 0.1), 0.05);
  const BodyPath p = moved("top", Eigen::Vector3d(0, 0, 0.1), Eigen::Vector3d(0, 0.2, 0.03), 45);
  const Eigen::MatrixXd h = final_outline(c, p, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ());
  ASSERT_EQ(h.rows(), 4);
  const double r = 0.05 / std::sqrt(2.0);  // half the diagonal
  EXPECT_NEAR(h.col(0).maxCoeff(), 0.2 + r, 1e-12);
  EXPECT_NEAR(h.col(0).minCoeff(), 0.2 - r, 1e-12);
  EXPECT_NEAR(h.col(1).maxCoeff(), 0.03 + r, 1e-12);
  EXPECT_NEAR(h.col(1).minCoeff(), 0.03 - r, 1e-12);
  BodyPath empty;
  empty.name = "top";
  EXPECT_THROW(final_outline(c, empty, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ()),
               InputError);
}

TEST(FinalPosesPlot, OnePanelPerRunWithEveryBodysOutline) {
  const test::ScratchDir dir;
  const std::vector<DemonstrationRun> runs = {
      {"rigid reference", "rigid", "reference", standing()},
      {"rigid adversarial", "rigid", "adversarial", {}},  // not made: no panel
      {"deformable adversarial", "deformable", "adversarial", toppled()},
      // Knocked 2 m away: named, not drawn, so the others keep their size.
      {"deformable soft control", "deformable", "soft control", toppled(2.0)}};
  const std::vector<Plane> ground = {Plane{Eigen::Vector3d::UnitZ(), 0.0}};
  write_final_poses_plot(dir.file("poses"), "stack", two_cubes(), runs, ground);

  const std::string s = test::read_text(dir.file("poses.gp"));
  EXPECT_NE(s.find("set multiplot layout 2,2"), std::string::npos) << s;
  EXPECT_NE(s.find("set title 'rigid reference'"), std::string::npos) << s;
  EXPECT_NE(s.find("set title 'deformable adversarial'"), std::string::npos) << s;
  EXPECT_EQ(s.find("set title 'rigid adversarial'"), std::string::npos) << s;
  EXPECT_NE(s.find("set xlabel 'y (m)'"), std::string::npos) << s;
  EXPECT_NE(s.find("set arrow 1 from"), std::string::npos) << s;  // the ground
  EXPECT_NE(s.find("'poses_1.dat' index 1 using 1:2 with filledcurves closed"), std::string::npos)
      << s;
  EXPECT_NE(s.find("middle ends off the picture at y = 2, z = 0.026 m"), std::string::npos) << s;
  EXPECT_EQ(s.find("'poses_2.dat' index 1"), std::string::npos) << s;
  // The view holds the stack, not the far cube: y within a few cube sizes of the start.
  const size_t xr = s.find("set xrange [");
  ASSERT_NE(xr, std::string::npos);
  double y_lo = 0, y_hi = 0;
  ASSERT_EQ(std::sscanf(s.c_str() + xr, "set xrange [%lf:%lf]", &y_lo, &y_hi), 2);
  EXPECT_GT(y_lo, -0.2);
  EXPECT_LT(y_hi, 0.2);

  // The toppled panel's middle cube: a closed square (5 rows) about (0.06, 0.026).
  std::ifstream data(dir.file("poses_1.dat"));
  std::string line;
  int block = -1, rows = 0;
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  while (std::getline(data, line)) {
    if (line.rfind("# ", 0) == 0) {
      ++block;
      continue;
    }
    if (block != 1 || line.empty()) continue;
    std::istringstream in(line);
    Eigen::Vector2d p;
    ASSERT_TRUE(in >> p.x() >> p.y());
    if (rows < 4) sum += p;  // the fifth repeats the first
    ++rows;
  }
  EXPECT_EQ(rows, 5);
  EXPECT_NEAR(sum.x() / 4, 0.06, 1e-12);
  EXPECT_NEAR(sum.y() / 4, 0.026, 1e-12);
}

// Planes are drawn where they are: each arrow's two ends lie on its plane in the side view
// (n_y y + n_z z = offset), for a slanted floor (drawn across the view's y range) and a steep wall
// (drawn across its z range). The ground of the test above has n_y = 0, so it cannot tell.
TEST(FinalPosesPlot, SlantedPlanesAreDrawnOnThemselves) {
  const test::ScratchDir dir;
  const std::vector<DemonstrationRun> runs = {
      {"deformable adversarial", "deformable", "adversarial", toppled()}};
  const std::vector<Plane> planes = {
      Plane{Eigen::Vector3d(0, -0.5, std::sqrt(3.0) / 2), -0.004},  // a floor tilted 30 deg
      Plane{Eigen::Vector3d(0, -0.96, 0.28), -0.09}};               // a wall leaning over +y
  write_final_poses_plot(dir.file("poses"), "stack", two_cubes(), runs, planes);
  const std::string s = test::read_text(dir.file("poses.gp"));
  ASSERT_NE(s.find("set xlabel 'y (m)'"), std::string::npos) << s;
  ASSERT_NE(s.find("set ylabel 'z (m)'"), std::string::npos) << s;
  for (int k = 0; k < 2; ++k) {
    const std::string key = "set arrow " + std::to_string(k + 1) + " from ";
    const size_t at = s.find(key);
    ASSERT_NE(at, std::string::npos) << s;
    double y0 = 0, z0 = 0, y1 = 0, z1 = 0;
    ASSERT_EQ(std::sscanf(s.c_str() + at + key.size(), "%lf,%lf to %lf,%lf", &y0, &z0, &y1, &z1),
              4)
        << s.substr(at, 80);
    const Plane& p = planes[k];
    // The script prints 6 significant digits.
    EXPECT_NEAR(p.normal.y() * y0 + p.normal.z() * z0, p.offset, 1e-6) << s.substr(at, 80);
    EXPECT_NEAR(p.normal.y() * y1 + p.normal.z() * z1, p.offset, 1e-6) << s.substr(at, 80);
    EXPECT_GT(std::hypot(y1 - y0, z1 - z0), 0.01) << s.substr(at, 80);
  }
}

}  // namespace
}  // namespace rbaa
