#include <gtest/gtest.h>

#include <Eigen/Core>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "rbaa/eval/path_plot.hpp"

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

}  // namespace
}  // namespace rbaa
