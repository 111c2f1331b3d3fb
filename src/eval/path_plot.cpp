#include "rbaa/eval/path_plot.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

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

std::string write_path_plot(const std::string& stem, const std::string& title,
                            const std::vector<PathSeries>& series,
                            const std::vector<Plane>& planes) {
  const auto [a, b] = plot_axes(series);
  const char* names = "xyz";
  Eigen::Vector2d lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
  for (size_t i = 0; i < series.size(); ++i) {
    const Eigen::MatrixXd& p = series[i].points;
    write_file_atomically(stem + "_" + std::to_string(i) + ".dat", [&](std::ostream& out) {
      for (Eigen::Index r = 0; r < p.rows(); ++r) {
        out << exact(p(r, a)) << " " << exact(p(r, b)) << "\n";
        lo = lo.cwiseMin(Eigen::Vector2d(p(r, a), p(r, b)));
        hi = hi.cwiseMax(Eigen::Vector2d(p(r, a), p(r, b)));
      }
    });
  }
  // Show every plane: extend the view to the point of each plane's trace nearest the paths.
  const Eigen::Vector2d centre = (lo + hi) / 2;
  for (const Plane& plane : planes) {
    const Eigen::Vector2d n(plane.normal[a], plane.normal[b]);
    if (n.squaredNorm() < 1e-12) continue;
    const Eigen::Vector2d foot = centre - (n.dot(centre) - plane.offset) / n.squaredNorm() * n;
    lo = lo.cwiseMin(foot);
    hi = hi.cwiseMax(foot);
  }
  const Eigen::Vector2d pad = 0.1 * (hi - lo).cwiseMax(1e-3);
  lo -= pad;
  hi += pad;
  const std::string base = std::filesystem::path(stem).filename().string();
  write_file_atomically(stem + ".gp", [&](std::ostream& out) {
    out << "set terminal pngcairo size 1000,750 noenhanced\n"
        << "set output '" << base << ".png'\n"
        << "set title '" << title << "'\n"
        << "set xlabel '" << names[a] << " (m)'\nset ylabel '" << names[b] << " (m)'\n"
        << "set size ratio -1\nset grid\nset key outside right top\n"
        << "set xrange [" << lo[0] << ":" << hi[0] << "]\nset yrange [" << lo[1] << ":" << hi[1] << "]\n";
    // A plane n . x = c shows as the line n_a u + n_b v = c in the (u, v) view, unless it is
    // parallel to the view (its normal along the dropped axis).
    int arrow = 1;
    for (const Plane& plane : planes) {
      const double na = plane.normal[a], nb = plane.normal[b], c = plane.offset;
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
          << series[i].label << "'";
    }
    out << "\n";
  });
  const std::string dir = std::filesystem::path(stem).parent_path().string();
  const std::string command = "cd '" + (dir.empty() ? std::string(".") : dir) + "' && gnuplot '" +
                              base + ".gp' >/dev/null 2>&1";
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0 || std::system(command.c_str()) != 0) {
    return "";
  }
  return stem + ".png";
}

}  // namespace rbaa
