#pragma once
// A picture of centre-of-mass paths among the scene's obstacles: gnuplot draws it (PNG) from a
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

/// What the picture shows. A spatial view draws the point x at (u.x, v.x): u along the picture's
/// width, v along its height, both unit and orthogonal. Usually u and v are the coordinate axes
/// of plot_axes. When the paths lie in no coordinate plane but in a vertical one (the ball thrown
/// diagonally at the board: the best-fit plane's normal is more than `coordinate_deg` from every
/// axis and within it of horizontal), u is that plane's horizontal direction, pointing the way
/// the first path travels, and v is +z: a side view in the plane of motion. When the paths run
/// along one axis (the second-widest spread is at most `straight_ratio` of the widest; a cube
/// bouncing between a floor and a ceiling), the view is that coordinate against time, where the
/// runs' differences are visible.
struct PlotView {
  bool time_axis = false;
  int horizontal = 1;  ///< coordinate axis along the picture's width, or -1 (u is oblique)
  int vertical = 2;    ///< coordinate axis along its height
  Eigen::Vector3d u = Eigen::Vector3d::UnitY(), v = Eigen::Vector3d::UnitZ();
  /// A point of the plane of motion (the paths' mean): the plane the obstacles are cut by is
  /// parallel to (u, v); see mesh_section.
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
};
PlotView plot_view(const std::vector<PathSeries>& series, double straight_ratio = 0.02,
                   double coordinate_deg = 10.0);

/// The section of a triangle mesh (V #V by 3, F #F by 3) by the plane through `point` normal to
/// `normal`, as segments in view coordinates: row i holds (u, v) of one end in columns 0-1 and of
/// the other in columns 2-3. Triangles lying in the plane give nothing.
Eigen::MatrixXd mesh_section(const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>& V,
                             const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>& F,
                             const Eigen::Vector3d& point, const Eigen::Vector3d& normal,
                             const Eigen::Vector3d& u, const Eigen::Vector3d& v);

/// Writes `stem`.gp, `stem`_<i>.dat and, if gnuplot is installed, renders `stem`.png: the paths
/// in plot_view, each plane drawn as its trace in that view (in the time view, the planes normal
/// to the plotted axis as horizontal lines), and each obstacle mesh as its section by the plane
/// parallel to the view through the mesh's bounding-box centre (`stem`_obstacles.dat: a hoop
/// seen from the side is its two tube circles, a bin its floor and walls, a board a line; the
/// time view shows no meshes). The legend sits inside the canvas, in the corner the paths cross
/// least. Returns the PNG path, or an empty string when gnuplot is missing or fails (the script
/// is still written).
std::string write_path_plot(const std::string& stem, const std::string& title,
                            const std::vector<PathSeries>& series, const std::vector<Plane>& planes,
                            const std::vector<ObstacleMesh>& meshes = {});

}  // namespace rbaa
