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
  Eigen::VectorXd times;   ///< the samples' times (s); may be empty (no time view then)
};

/// The two coordinate axes (0 = x, 1 = y, 2 = z) along which the paths spread most, in
/// increasing order, so the plot shows the plane of motion.
std::pair<int, int> plot_axes(const std::vector<PathSeries>& series);

/// What the picture shows: the plane of motion, or, when the paths run along one axis (the
/// second-widest spread is at most `straight_ratio` of the widest; a cube bouncing between a
/// floor and a ceiling), that coordinate against time, where the runs' differences are visible.
struct PlotView {
  bool time_axis = false;
  int horizontal = 1;  ///< coordinate axis along the picture's width (unused with time_axis)
  int vertical = 2;    ///< coordinate axis along its height
};
PlotView plot_view(const std::vector<PathSeries>& series, double straight_ratio = 0.02);

/// Writes `stem`.gp, `stem`_<i>.dat and, if gnuplot is installed, renders `stem`.png: the paths
/// in plot_view, with each plane drawn as its trace in that view (in the time view, the planes
/// normal to the plotted axis as horizontal lines). Returns the PNG path, or an empty string when
/// gnuplot is missing or fails (the script is still written).
std::string write_path_plot(const std::string& stem, const std::string& title,
                            const std::vector<PathSeries>& series,
                            const std::vector<Plane>& planes);

}  // namespace rbaa
