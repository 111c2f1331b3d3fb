#pragma once
// A picture of centre-of-mass paths among planar obstacles: gnuplot draws it (PNG) from a
// script and data files that stay beside it, so a person can restyle it.

#include <Eigen/Core>

#include <string>
#include <vector>

#include "rbaa/scene/scene.hpp"

namespace rbaa {

struct PathSeries {
  std::string label;
  Eigen::MatrixXd points;  ///< #samples by 3 positions (m)
};

/// The two coordinate axes (0 = x, 1 = y, 2 = z) along which the paths spread most, in
/// increasing order, so the plot shows the plane of motion.
std::pair<int, int> plot_axes(const std::vector<PathSeries>& series);

/// Writes `stem`.gp, `stem`_<i>.dat and, if gnuplot is installed, renders `stem`.png: the paths
/// projected on plot_axes, with each plane drawn as its trace in that view. Returns the PNG path,
/// or an empty string when gnuplot is missing or fails (the script is still written).
std::string write_path_plot(const std::string& stem, const std::string& title,
                            const std::vector<PathSeries>& series,
                            const std::vector<Plane>& planes);

}  // namespace rbaa
