#pragma once
// A picture of where every body ends (the cube stack: did it stand?): one panel per run, each
// body's outline at the run's end in a side view, gnuplot from a script and data files that stay
// beside it.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "rbaa/eval/demonstration.hpp"
#include "rbaa/scene/scene.hpp"

namespace rbaa {

/// The convex hull of the points (#P by 2), counter-clockwise, no point repeated, collinear
/// points left out (Andrew's monotone chain); #H by 2.
Eigen::MatrixXd convex_hull_2d(const Eigen::MatrixXd& points);

/// The body's outline at the path's end in the view (u, v): the convex hull of its rest
/// vertices moved by the final pose, x = c(T) + R(T) (x0 - c(0)), drawn at (u.x, v.x); #H by 2.
/// Throws rbaa::InputError when the path is empty.
Eigen::MatrixXd final_outline(const BodyShape& shape, const BodyPath& path,
                              const Eigen::Vector3d& u, const Eigen::Vector3d& v);

/// Writes `stem`.gp, `stem`_<run>.dat (one block per body drawn: its final outline, closed)
/// and, if gnuplot is installed, renders `stem`.png: a panel per run that was made, the same
/// scale in each, the side view of plot_axes over every body's path (the coordinate plane they
/// spread in most), each plane drawn as its trace, one legend under the title. A body that ends
/// farther from the mean of the initial centres than the farthest initial centre plus four body
/// radii has left the scene (a striker knocked away): its panel names where it is instead of
/// drawing it, so the others keep their size. Returns the PNG path or "" (no gnuplot).
std::string write_final_poses_plot(const std::string& stem, const std::string& title,
                                   const std::vector<BodyShape>& shapes,
                                   const std::vector<DemonstrationRun>& runs,
                                   const std::vector<Plane>& planes);

}  // namespace rbaa
