#include "rbaa/eval/path_plot.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <tuple>

#include "rbaa/eval/gnuplot.hpp"
#include "rbaa/io/atomic_file.hpp"
#include "rbaa/io/number_text.hpp"

namespace rbaa {

std::pair<int, int> plot_axes(const std::vector<PathSeries>& series) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = Eigen::Vector3d::Constant(-INFINITY);
  for (const auto& s : series) {
    if (s.points.rows() == 0) continue;
    lo = lo.cwiseMin(s.points.colwise().minCoeff().transpose());
    hi = hi.cwiseMax(s.points.colwise().maxCoeff().transpose());
  }
  const Eigen::Vector3d spread = (hi - lo).cwiseMax(0.0);
  int drop = 0;
  spread.minCoeff(&drop);
  const int a = drop == 0 ? 1 : 0;
  const int b = drop == 2 ? 1 : 2;
  return {a, b};
}

PlotView plot_view(const std::vector<PathSeries>& series, double straight_ratio) {
  PlotView view;
  std::tie(view.horizontal, view.vertical) = plot_axes(series);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = Eigen::Vector3d::Constant(-INFINITY);
  bool timed = !series.empty();
  for (const auto& s : series) {
    timed = timed && s.times.size() == s.points.rows() && s.points.rows() > 1;
    if (s.points.rows() == 0) continue;
    lo = lo.cwiseMin(s.points.colwise().minCoeff().transpose());
    hi = hi.cwiseMax(s.points.colwise().maxCoeff().transpose());
  }
  if (!timed) return view;
  Eigen::Vector3d spread = (hi - lo).cwiseMax(0.0);
  int widest = 0;
  const double largest = spread.maxCoeff(&widest);
  spread[widest] = 0;
  if (largest > 0 && spread.maxCoeff() <= straight_ratio * largest) {
    view.time_axis = true;
    view.vertical = widest;
  }
  return view;
}

std::string write_path_plot(const std::string& stem, const std::string& title,
                            const std::vector<PathSeries>& series,
                            const std::vector<Plane>& planes) {
  const PlotView view = plot_view(series);
  const int a = view.horizontal, b = view.vertical;
  const char* names = "xyz";
  Eigen::Vector2d lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
  for (size_t i = 0; i < series.size(); ++i) {
    const Eigen::MatrixXd& p = series[i].points;
    write_file_atomically(stem + "_" + std::to_string(i) + ".dat", [&](std::ostream& out) {
      for (Eigen::Index r = 0; r < p.rows(); ++r) {
        const Eigen::Vector2d uv(view.time_axis ? series[i].times[r] : p(r, a), p(r, b));
        out << exact(uv[0]) << " " << exact(uv[1]) << "\n";
        lo = lo.cwiseMin(uv);
        hi = hi.cwiseMax(uv);
      }
    });
  }
  // In the time view a plane is a fixed height only when its normal is the plotted axis.
  std::vector<Plane> shown;
  for (const Plane& plane : planes) {
    if (!view.time_axis) {
      shown.push_back(plane);
    } else if (std::abs(std::abs(plane.normal[b]) - 1.0) < 1e-9) {
      shown.push_back(Plane{Eigen::Vector3d::UnitY() * plane.normal[b], plane.offset});  // (t, u) view
    }
  }
  const int pa = view.time_axis ? 0 : a, pb = view.time_axis ? 1 : b;
  // Show every plane: extend the view to the point of each plane's trace nearest the paths.
  const Eigen::Vector2d centre = (lo + hi) / 2;
  for (const Plane& plane : shown) {
    const Eigen::Vector2d n(plane.normal[pa], plane.normal[pb]);
    if (n.squaredNorm() < 1e-12) continue;
    const Eigen::Vector2d foot = centre - (n.dot(centre) - plane.offset) / n.squaredNorm() * n;
    lo = lo.cwiseMin(foot);
    hi = hi.cwiseMax(foot);
  }
  Eigen::Vector2d pad = 0.1 * (hi - lo).cwiseMax(1e-3);
  if (view.time_axis) pad[0] = 0;
  lo -= pad;
  hi += pad;
  const std::string base = std::filesystem::path(stem).filename().string();
  write_file_atomically(stem + ".gp", [&](std::ostream& out) {
    out << "set terminal pngcairo size 1000,750 noenhanced\n"
        << "set output '" << base << ".png'\n"
        << "set title '" << gnuplot_quoted(title) << "'\n"
        << "set xlabel '" << (view.time_axis ? std::string("t (s)") : std::string(1, names[a]) + " (m)")
        << "'\nset ylabel '" << names[b] << " (m)'\n"
        << (view.time_axis ? "" : "set size ratio -1\n") << "set grid\nset key outside right top\n"
        << "set xrange [" << lo[0] << ":" << hi[0] << "]\nset yrange [" << lo[1] << ":" << hi[1] << "]\n";
    // A plane n . x = c shows as the line n_a u + n_b v = c in the (u, v) view, unless it is
    // parallel to the view (its normal along the dropped axis).
    int arrow = 1;
    for (const Plane& plane : shown) {
      const double na = plane.normal[pa], nb = plane.normal[pb], c = plane.offset;
      if (std::abs(nb) > std::abs(na) && std::abs(nb) > 1e-12) {
        out << "set arrow " << arrow++ << " from " << lo[0] << "," << (c - na * lo[0]) / nb << " to "
            << hi[0] << "," << (c - na * hi[0]) / nb << " nohead lw 3 lc rgb 'black'\n";
      } else if (std::abs(na) > 1e-12) {
        out << "set arrow " << arrow++ << " from " << (c - nb * lo[1]) / na << "," << lo[1] << " to "
            << (c - nb * hi[1]) / na << "," << hi[1] << " nohead lw 3 lc rgb 'black'\n";
      }
    }
    out << "plot ";
    for (size_t i = 0; i < series.size(); ++i) {
      out << (i ? ", " : "") << "'" << base << "_" << i << ".dat' using 1:2 with lines lw 2 title '"
          << gnuplot_quoted(series[i].label) << "'";
    }
    out << "\n";
  });
  return render_gnuplot(stem);
}

}  // namespace rbaa
