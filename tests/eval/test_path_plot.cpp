#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "io/io_test_support.hpp"
#include "rbaa/eval/path_plot.hpp"
#include "rbaa/scene/scene.hpp"

namespace rbaa {
namespace {

PathSeries sampled(const std::string& label, const std::function<Eigen::Vector3d(double)>& x, int n = 51) {
  PathSeries s{label, Eigen::MatrixXd(n, 3), Eigen::VectorXd(n)};
  for (int i = 0; i < n; ++i) {
    s.times[i] = 1.5 * i / (n - 1);
    s.points.row(i) = x(s.times[i]).transpose();
  }
  return s;
}

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// A throw in the yz-plane is drawn in that plane; a bounce along z (the cube between two planes)
// is drawn as z against time, since its paths would all lie on one vertical line.
TEST(PathPlot, ChoosesThePlaneOfMotionOrHeightAgainstTime) {
  const PathSeries thrown = sampled("thrown", [](double t) { return Eigen::Vector3d(0.001 * t, 2 - 3 * t, 2 + t - 4.9 * t * t); });
  const PlotView spatial = plot_view({thrown});
  EXPECT_FALSE(spatial.time_axis);
  EXPECT_EQ(spatial.horizontal, 1);
  EXPECT_EQ(spatial.vertical, 2);

  const PathSeries bouncing = sampled("bouncing", [](double t) {
    return Eigen::Vector3d(1e-6 * t, -2e-6 * t, 0.05 + 0.025 * std::sin(4 * t));
  });
  const PlotView timed = plot_view({bouncing, thrown});
  EXPECT_FALSE(timed.time_axis);  // together they span two axes
  const PlotView straight = plot_view({bouncing});
  EXPECT_TRUE(straight.time_axis);
  EXPECT_EQ(straight.vertical, 2);

  PathSeries untimed = bouncing;
  untimed.times.resize(0);
  EXPECT_FALSE(plot_view({untimed}).time_axis);  // no times, no time axis
}

TEST(PathPlot, TimeViewWritesTimesAndTheHorizontalPlanes) {
  const std::string dir = (std::filesystem::temp_directory_path() / "rbaa_path_plot_test").string();
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const PathSeries bouncing = sampled("bouncing", [](double t) { return Eigen::Vector3d(0, 0, 0.05 + 0.02 * std::sin(4 * t)); });
  const std::vector<Plane> planes = {Plane{Eigen::Vector3d::UnitZ(), 0.0}, Plane{-Eigen::Vector3d::UnitZ(), -0.1},
                                     Plane{Eigen::Vector3d::UnitY(), 0.0}};
  write_path_plot(dir + "/paths", "bounce", {bouncing}, planes);
  const std::string script = read(dir + "/paths.gp");
  EXPECT_NE(script.find("set xlabel 't (s)'"), std::string::npos) << script;
  EXPECT_NE(script.find("set ylabel 'z (m)'"), std::string::npos) << script;
  EXPECT_EQ(script.find("size ratio"), std::string::npos) << script;
  // The floor at z = 0 and the ceiling at z = 0.1 as lines across the whole time range; the wall
  // y = 0 is no fixed height and is left out.
  EXPECT_NE(script.find("set arrow 1 from 0,0 to 1.5,0 "), std::string::npos) << script;
  EXPECT_NE(script.find("set arrow 2 from 0,0.1"), std::string::npos) << script;
  EXPECT_EQ(script.find("set arrow 3"), std::string::npos) << script;
  // Round trip of the data: time in the first column, z in the second.
  std::ifstream data(dir + "/paths_0.dat");
  for (int i = 0; i < bouncing.points.rows(); ++i) {
    double t = 0, z = 0;
    ASSERT_TRUE(data >> t >> z);
    EXPECT_EQ(t, bouncing.times[i]);
    EXPECT_EQ(z, bouncing.points(i, 2));
  }
  std::filesystem::remove_all(dir);
}

// The legend goes inside the canvas, into the corner whose box (0.4 of the width by 0.3 of the
// height) holds the fewest drawn points; among equally empty corners the first of top right
// (gnuplot's own default), top left, bottom right, bottom left.
TEST(PathPlot, TheLegendTakesTheFirstCornerThePathsLeaveEmpty) {
  const test::ScratchDir dir;
  // The path (y, z(y)) in the yz-plane for y from 0 to 1.
  auto key_of = [&](const std::string& name, const std::function<double(double)>& z) {
    const PathSeries path =
        sampled(name, [&](double t) { return Eigen::Vector3d(0, t / 1.5, z(t / 1.5)); });
    write_path_plot(dir.file(name), name, {path}, {});
    const std::string script = read(dir.file(name + ".gp"));
    const size_t at = script.find("set key inside ");
    EXPECT_NE(at, std::string::npos) << script;
    const size_t end = script.find(" opaque", at);
    return at == std::string::npos ? std::string() : script.substr(at + 15, end - at - 15);
  };
  // Bottom left and top right taken; top left and bottom right free.
  EXPECT_EQ(key_of("rising", [](double y) { return y; }), "top left");
  // Top left and bottom right taken; top right and bottom left free.
  EXPECT_EQ(key_of("falling", [](double y) { return 1 - y; }), "top right");
  // A V: both top corners taken, both bottom ones free.
  EXPECT_EQ(key_of("vee", [](double y) { return 2 * std::abs(y - 0.5); }), "bottom right");
  // A flat line through the middle of its canvas (widened to 4:3): every corner free.
  EXPECT_EQ(key_of("flat", [](double y) { return 0.2 * y; }), "top right");
}

// A closed unit cube [0, 1]^3 as 12 triangles.
ObstacleMesh unit_cube() {
  ObstacleMesh m;
  m.name = "cube";
  m.V.resize(8, 3);
  for (int i = 0; i < 8; ++i) m.V.row(i) << (i & 1), (i >> 1) & 1, (i >> 2) & 1;
  m.F.resize(12, 3);
  m.F << 0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6,
      1, 3, 5, 3, 7, 5;
  return m;
}

TEST(PathPlot, MeshSectionOfACubeIsItsSquare) {
  const ObstacleMesh cube = unit_cube();
  // Cut half way up, seen from the side along y: the square's trace is z = 0.5 from x = 0 to 1;
  // seen from above (u = x, v = y), the whole square, perimeter 4.
  const Eigen::MatrixXd top =
      mesh_section(cube.V, cube.F, Eigen::Vector3d(0.5, 0.5, 0.5), Eigen::Vector3d::UnitZ(),
                   Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY());
  double perimeter = 0;
  for (Eigen::Index r = 0; r < top.rows(); ++r) {
    perimeter += (top.row(r).head<2>() - top.row(r).tail<2>()).norm();
    for (int c = 0; c < 4; ++c) {
      EXPECT_GE(top(r, c), -1e-15);
      EXPECT_LE(top(r, c), 1 + 1e-15);
    }
  }
  EXPECT_NEAR(perimeter, 4.0, 1e-12);
  // A plane that misses the cube cuts nothing.
  EXPECT_EQ(mesh_section(cube.V, cube.F, Eigen::Vector3d(0, 0, 2), Eigen::Vector3d::UnitZ(),
                         Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY())
                .rows(),
            0);
}

// The ball's demonstration (configs/demos/ball_hoop.yaml): the release flies diagonally at the
// board, so the side view is the vertical plane of motion (u along the throw, v = z); the board
// shows as a vertical line and the rim as its two tube circles, on either side of the hoop's
// centre; the legend is inside the canvas.
TEST(PathPlot, TheBallsSideViewDrawsTheBoardAndTheRimsSections) {
  const Scene scene = load_scene(std::string(RBAA_SOURCE_DIR) + "/configs/demos/ball_hoop.yaml");
  ASSERT_EQ(scene.obstacle_meshes.size(), 2u);
  const Eigen::Vector3d x0 = scene.position, v0 = scene.velocity;
  const PathSeries thrown = sampled("thrown", [&](double t) {
    return Eigen::Vector3d(x0 + 0.25 * t * v0 + Eigen::Vector3d(0, 0, -4.9 * 0.0625 * t * t));
  });
  const PlotView view = plot_view({thrown});
  EXPECT_FALSE(view.time_axis);
  EXPECT_EQ(view.horizontal, -1);
  const Eigen::Vector3d along = Eigen::Vector3d(v0.x(), v0.y(), 0).normalized();
  EXPECT_NEAR(view.u.dot(along), 1.0, 1e-9);  // the throw runs left to right
  EXPECT_EQ(view.v, Eigen::Vector3d::UnitZ());

  const std::string dir = (std::filesystem::temp_directory_path() / "rbaa_path_plot_hoop").string();
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  write_path_plot(dir + "/paths", "hoop", {thrown}, scene.planes, scene.obstacle_meshes);
  const std::string script = read(dir + "/paths.gp");
  EXPECT_NE(script.find("paths_obstacles.dat' using 1:2 with lines"), std::string::npos) << script;
  EXPECT_NE(script.find("set key inside"), std::string::npos) << script;
  EXPECT_EQ(script.find("set key outside"), std::string::npos) << script;
  EXPECT_NE(script.find("set xlabel 'along ("), std::string::npos) << script;
  EXPECT_NE(script.find(", 0) (m)'"), std::string::npos) << script;  // not -0

  // Read the sections back, mesh by mesh (a comment line opens each).
  std::ifstream data(dir + "/paths_obstacles.dat");
  std::vector<std::vector<Eigen::Vector2d>> points;
  std::vector<std::string> names;
  for (std::string line; std::getline(data, line);) {
    if (line.rfind("# ", 0) == 0) {
      names.push_back(line);
      points.emplace_back();
    } else if (!line.empty()) {
      std::istringstream in(line);
      Eigen::Vector2d p;
      ASSERT_TRUE(in >> p.x() >> p.y()) << line;
      ASSERT_FALSE(points.empty());
      points.back().push_back(p);
    }
  }
  ASSERT_EQ(points.size(), 2u);
  EXPECT_NE(names[0].find("backboard.obj"), std::string::npos) << names[0];
  EXPECT_NE(names[1].find("hoop.obj"), std::string::npos) << names[1];
  // The board (y = 0, 1.83 x 1.07 m, lower edge 2.9 m up, centred on x = 0): the line u = 0
  // from z = 2.9 to 3.97.
  ASSERT_FALSE(points[0].empty());
  double z_lo = INFINITY, z_hi = -INFINITY;
  for (const Eigen::Vector2d& p : points[0]) {
    EXPECT_NEAR(p.x(), 0.0, 1e-9);
    z_lo = std::min(z_lo, p.y());
    z_hi = std::max(z_hi, p.y());
  }
  EXPECT_NEAR(z_lo, 2.9, 1e-9);
  EXPECT_NEAR(z_hi, 2.9 + 1.07, 1e-9);
  // The rim: every point within the 8 mm tube of a circle of radius 0.2286 + 0.008 about the
  // hoop's centre, and points on both sides of it, near z = 3.048. The mesh's chords (64 around
  // the ring) may lie outside the smooth tube by at most 0.2446 (1 - cos(pi / 64)) = 0.3 mm.
  // The hoop's centre: the config's predicate names it (the rim's placement, y = -0.3796 m,
  // z = 3.048 m; along the board x = -0.12 m since the rim moved).
  const Eigen::Vector3d hoop = scene.demonstration.predicate.centre;
  EXPECT_NEAR(hoop.y(), -0.3796, 1e-12);
  EXPECT_NEAR(hoop.z(), 3.048, 1e-12);
  const double u0 = view.u.dot(hoop), ring = 0.2286 + 0.008;
  int left = 0, right = 0;
  for (const Eigen::Vector2d& p : points[1]) {
    const double side = p.x() < u0 ? -1 : 1;
    const double off = (p - Eigen::Vector2d(u0 + side * ring, 3.048)).norm();
    EXPECT_LT(off, 0.008 + 0.2446 * (1 - std::cos(M_PI / 64)) + 1e-12) << p.transpose();
    (side < 0 ? left : right) += 1;
  }
  EXPECT_GT(left, 8);
  EXPECT_GT(right, 8);
  // The sections extend the view towards them, but no farther than the paths' own extent beyond
  // the paths: this short throw ends 2.9 m before the board, so along u the view runs from the
  // paths' start to their end plus their length (then 10 % padding each side), not to the board.
  double u_lo = INFINITY, u_hi = -INFINITY;
  for (Eigen::Index i = 0; i < thrown.points.rows(); ++i) {
    const double u = view.u.dot(thrown.points.row(i).transpose());
    u_lo = std::min(u_lo, u);
    u_hi = std::max(u_hi, u);
  }
  const double cap = u_hi + (u_hi - u_lo), pad = 0.1 * (cap - u_lo);
  ASSERT_LT(cap, 0.0);  // the board's section (u = 0) lies beyond the cap
  const size_t at = script.find("set xrange [");
  ASSERT_NE(at, std::string::npos) << script;
  std::istringstream xrange(script.substr(at + 12));
  double x_lo = 0, x_hi = 0;
  char colon = 0;
  ASSERT_TRUE(xrange >> x_lo >> colon >> x_hi) << script.substr(at, 60);
  EXPECT_NEAR(x_lo, u_lo - pad, 1e-6);
  EXPECT_NEAR(x_hi, cap + pad, 1e-6);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace rbaa
