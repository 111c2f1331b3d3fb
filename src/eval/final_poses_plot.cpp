#include "rbaa/eval/final_poses_plot.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "rbaa/error.hpp"
#include "rbaa/eval/gnuplot.hpp"
#include "rbaa/eval/path_plot.hpp"
#include "rbaa/io/atomic_file.hpp"
#include "rbaa/io/number_text.hpp"

namespace rbaa {

Eigen::MatrixXd convex_hull_2d(const Eigen::MatrixXd& points) {
  std::vector<Eigen::Vector2d> p(points.rows());
  for (Eigen::Index i = 0; i < points.rows(); ++i) p[i] = points.row(i).transpose();
  std::sort(p.begin(), p.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 3) {
    Eigen::MatrixXd out(p.size(), 2);
    for (size_t i = 0; i < p.size(); ++i) out.row(i) = p[i].transpose();
    return out;
  }
  auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
  };
  std::vector<Eigen::Vector2d> hull(2 * p.size());
  size_t k = 0;
  for (size_t i = 0; i < p.size(); ++i) {  // lower chain
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  for (size_t i = p.size() - 1, lower = k + 1; i-- > 0;) {  // upper chain
    while (k >= lower && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  hull.resize(k - 1);  // the last point is the first
  Eigen::MatrixXd out(hull.size(), 2);
  for (size_t i = 0; i < hull.size(); ++i) out.row(i) = hull[i].transpose();
  return out;
}

Eigen::MatrixXd final_outline(const BodyShape& shape, const BodyPath& path,
                              const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  if (path.centre.empty())
    throw InputError("final poses: body '" + path.name + "' has an empty path");
  const Eigen::Matrix3d R =
      path.rotation.empty() ? Eigen::Matrix3d::Identity() : path.rotation.back().toRotationMatrix();
  Eigen::MatrixXd projected(shape.V.rows(), 2);
  for (Eigen::Index i = 0; i < shape.V.rows(); ++i) {
    const Eigen::Vector3d x =
        path.centre.back() + R * (shape.V.row(i).transpose() - path.centre.front());
    projected.row(i) << u.dot(x), v.dot(x);
  }
  return convex_hull_2d(projected);
}

std::string write_final_poses_plot(const std::string& stem, const std::string& title,
                                   const std::vector<BodyShape>& shapes,
                                   const std::vector<DemonstrationRun>& runs,
                                   const std::vector<Plane>& planes) {
  std::vector<const DemonstrationRun*> made;
  std::vector<PathSeries> every_path;  // for the view: every body's centre in every run
  for (const DemonstrationRun& r : runs) {
    if (r.paths.empty()) continue;
    made.push_back(&r);
    for (const BodyPath& p : r.paths) {
      PathSeries s{p.name, Eigen::MatrixXd(p.centre.size(), 3), Eigen::VectorXd()};
      for (size_t k = 0; k < p.centre.size(); ++k) s.points.row(k) = p.centre[k].transpose();
      every_path.push_back(std::move(s));
    }
  }
  const auto [a, b] = plot_axes(every_path);
  const Eigen::Vector3d u = Eigen::Vector3d::Unit(a), v = Eigen::Vector3d::Unit(b);
  const char* names = "xyz";
  // The scene as set up: a body that ends farther from the initial centres' mean than the
  // farthest initial centre plus two body sizes has left it (a striker knocked 1.5 m away) and
  // is named in its panel instead of shrinking every other body to a dot.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  int count = 0;
  for (const DemonstrationRun* r : made) {
    for (const BodyPath& p : r->paths) {
      if (p.centre.empty()) continue;
      mean += p.centre.front();
      ++count;
    }
  }
  mean /= std::max(count, 1);
  double reach = 0, size = 0;
  for (const DemonstrationRun* r : made) {
    for (const BodyPath& p : r->paths) {
      if (!p.centre.empty()) reach = std::max(reach, (p.centre.front() - mean).norm());
    }
  }
  for (const BodyShape& shape : shapes) {
    const Eigen::Vector3d c = shape.V.colwise().mean().transpose();
    size = std::max(size, bounding_radius(shape.V, c));
  }
  reach += 4 * size;
  Eigen::Vector2d lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
  const std::string base = std::filesystem::path(stem).filename().string();
  std::vector<std::vector<size_t>> drawn(made.size());      // shapes drawn per panel
  std::vector<std::vector<std::string>> away(made.size());  // labels of those that left
  for (size_t r = 0; r < made.size(); ++r) {
    write_file_atomically(stem + "_" + std::to_string(r) + ".dat", [&](std::ostream& out) {
      for (size_t i = 0; i < shapes.size(); ++i) {
        const BodyPath& path = find_path(made[r]->paths, shapes[i].name);
        const Eigen::MatrixXd hull = final_outline(shapes[i], path, u, v);
        if (hull.rows() == 0) continue;
        const Eigen::Vector3d end = path.centre.back();
        if ((end - mean).norm() > reach) {
          away[r].push_back(shapes[i].name + " ends off the picture at " + names[a] + " = " +
                            format_significant(end[a], 3) + ", " + names[b] + " = " +
                            format_significant(end[b], 3) + " m");
          continue;
        }
        out << "# " << shapes[i].name << " at the end of " << made[r]->run << "\n";
        for (Eigen::Index k = 0; k <= hull.rows(); ++k) {
          const Eigen::Vector2d q = hull.row(k % hull.rows()).transpose();
          out << exact(q.x()) << " " << exact(q.y()) << "\n";
          lo = lo.cwiseMin(q);
          hi = hi.cwiseMax(q);
        }
        out << "\n\n";
        drawn[r].push_back(i);
      }
    });
  }
  if (!(lo.array() <= hi.array()).all()) {  // nothing drawn anywhere
    lo.setZero();
    hi.setOnes();
  }
  // Planes normal to the picture's vertical (a floor) extend it down to themselves.
  for (const Plane& p : planes) {
    if (std::abs(std::abs(p.normal.dot(v)) - 1.0) < 1e-9) {
      const double level = p.offset / p.normal.dot(v);
      lo[1] = std::min(lo[1], level);
      hi[1] = std::max(hi[1], level);
    }
  }
  const Eigen::Vector2d pad = 0.08 * Eigen::Vector2d::Constant((hi - lo).maxCoeff()).cwiseMax(1e-3);
  lo -= pad;
  hi += pad;
  hi[1] += 0.15 * (hi - lo).maxCoeff();  // room for the labels of bodies that left
  const int columns = made.size() > 4 ? 3 : std::max<int>(1, std::min<int>(2, made.size()));
  const int rows = std::max<int>(1, (static_cast<int>(made.size()) + columns - 1) / columns);
  // Panels at the picture's aspect (equal scales), 450 px wide, within reason.
  const double aspect = std::clamp((hi[1] - lo[1]) / (hi[0] - lo[0]), 0.3, 1.5);
  const int panel_h = static_cast<int>(450 * aspect) + 90;
  const char* colours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b"};
  write_file_atomically(stem + ".gp", [&](std::ostream& out) {
    out << "set terminal pngcairo size " << 450 * columns << "," << panel_h * rows + 70
        << " noenhanced\nset output '" << base << ".png'\n"
        << "set multiplot layout " << rows << "," << columns << " title '" << gnuplot_quoted(title)
        << "'\nset xlabel '" << names[a] << " (m)'\nset ylabel '" << names[b] << " (m)'\n"
        << "set size ratio -1\nset grid\n"
        // One legend for every panel, inside the canvas under the title (the colours are the
        // bodies', the same in each panel).
        << "set key at screen 0.5, screen " << 1.0 - 30.0 / (panel_h * rows + 70)
        << " center top horizontal box\n"
        << "set xrange [" << lo[0] << ":" << hi[0] << "]\nset yrange [" << lo[1] << ":" << hi[1]
        << "]\nset style fill transparent solid 0.5 border\n";
    int arrow = 1;
    for (const Plane& p : planes) {
      const double na = p.normal.dot(u), nb = p.normal.dot(v);
      if (std::abs(nb) > std::abs(na) && std::abs(nb) > 1e-12) {
        out << "set arrow " << arrow++ << " from " << lo[0] << "," << (p.offset - na * lo[0]) / nb
            << " to " << hi[0] << "," << (p.offset - na * hi[0]) / nb
            << " nohead lw 3 lc rgb 'black'\n";
      } else if (std::abs(na) > 1e-12) {
        out << "set arrow " << arrow++ << " from " << (p.offset - nb * lo[1]) / na << "," << lo[1]
            << " to " << (p.offset - nb * hi[1]) / na << "," << hi[1]
            << " nohead lw 3 lc rgb 'black'\n";
      }
    }
    for (size_t r = 0; r < made.size(); ++r) {
      out << "set title '" << gnuplot_quoted(made[r]->run) << "'\nunset label\n";
      for (size_t k = 0; k < away[r].size(); ++k) {
        out << "set label " << k + 1 << " '" << gnuplot_quoted(away[r][k])
            << "' at graph 0.02, graph " << 0.95 - 0.06 * k << " front font ',9'\n";
      }
      out << (r == 0 ? "" : "unset key\n") << "plot ";
      for (size_t k = 0; k < drawn[r].size(); ++k) {
        out << (k ? ", " : "") << "'" << base << "_" << r << ".dat' index " << k
            << " using 1:2 with filledcurves closed lc rgb '" << colours[drawn[r][k] % 6]
            << "' title '" << gnuplot_quoted(shapes[drawn[r][k]].name) << "'";
      }
      if (r == 0) {  // the first panel's key names every body, drawn there or not
        for (size_t i = 0; i < shapes.size(); ++i) {
          if (std::count(drawn[r].begin(), drawn[r].end(), i)) continue;
          out << (drawn[r].empty() && i == 0 ? "" : ", ") << "keyentry with filledcurves lc rgb '"
              << colours[i % 6] << "' title '" << gnuplot_quoted(shapes[i].name) << "'";
        }
      } else if (drawn[r].empty()) {
        out << "NaN notitle";
      }
      out << "\n";
    }
    out << "unset multiplot\n";
  });
  return render_gnuplot(stem);
}

}  // namespace rbaa
