#include "rbaa/eval/path_plot.hpp"

#include <Eigen/Eigenvalues>
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

PlotView plot_view(const std::vector<PathSeries>& series, double straight_ratio,
                   double coordinate_deg) {
  PlotView view;
  std::tie(view.horizontal, view.vertical) = plot_axes(series);
  view.u = Eigen::Vector3d::Unit(view.horizontal);
  view.v = Eigen::Vector3d::Unit(view.vertical);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = Eigen::Vector3d::Constant(-INFINITY);
  bool timed = !series.empty();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Index count = 0;
  for (const auto& s : series) {
    timed = timed && s.times.size() == s.points.rows() && s.points.rows() > 1;
    if (s.points.rows() == 0) continue;
    lo = lo.cwiseMin(s.points.colwise().minCoeff().transpose());
    hi = hi.cwiseMax(s.points.colwise().maxCoeff().transpose());
    sum += s.points.colwise().sum().transpose();
    count += s.points.rows();
  }
  if (count == 0) return view;
  view.origin = sum / static_cast<double>(count);
  Eigen::Vector3d spread = (hi - lo).cwiseMax(0.0);
  int widest = 0;
  const double largest = spread.maxCoeff(&widest);
  Eigen::Vector3d others = spread;
  others[widest] = 0;
  if (timed && largest > 0 && others.maxCoeff() <= straight_ratio * largest) {
    view.time_axis = true;
    view.vertical = widest;
    return view;
  }
  // The best-fit plane of every sample: its normal is the scatter matrix's weakest direction.
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const auto& s : series) {
    for (Eigen::Index r = 0; r < s.points.rows(); ++r) {
      const Eigen::Vector3d d = s.points.row(r).transpose() - view.origin;
      scatter += d * d.transpose();
    }
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(scatter);
  const Eigen::Vector3d normal = eig.eigenvectors().col(0);
  const double cos_tol = std::cos(coordinate_deg * M_PI / 180.0);
  if (normal.cwiseAbs().maxCoeff() >= cos_tol) return view;  // a coordinate plane
  if (std::abs(normal.z()) > std::sin(coordinate_deg * M_PI / 180.0)) return view;  // not vertical
  // A vertical plane of motion: u its horizontal direction, pointing the way the first path
  // travels (it starts on the left).
  Eigen::Vector3d u = Eigen::Vector3d::UnitZ().cross(normal);
  u.z() = 0;
  u.normalize();
  for (const auto& s : series) {
    if (s.points.rows() < 2) continue;
    const Eigen::Vector3d travel =
        (s.points.row(s.points.rows() - 1) - s.points.row(0)).transpose();
    if (u.dot(travel) < 0) u = -u;
    break;
  }
  view.u = u;
  view.v = Eigen::Vector3d::UnitZ();
  view.horizontal = -1;
  view.vertical = 2;
  return view;
}

Eigen::MatrixXd mesh_section(const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>& V,
                             const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>& F,
                             const Eigen::Vector3d& point, const Eigen::Vector3d& normal,
                             const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  const Eigen::Vector3d n = normal.normalized();
  std::vector<Eigen::Vector4d> segments;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    Eigen::Vector3d x[3];
    double d[3];
    for (int k = 0; k < 3; ++k) {
      x[k] = V.row(F(f, k)).transpose();
      d[k] = n.dot(x[k] - point);
    }
    // An edge is cut where its ends lie on opposite sides (a vertex on the plane counts as
    // above, so a plane through a vertex cuts the triangle once, not twice).
    std::vector<Eigen::Vector3d> cut;
    for (int k = 0; k < 3; ++k) {
      const int l = (k + 1) % 3;
      if ((d[k] >= 0) != (d[l] >= 0)) {
        const double t = d[k] / (d[k] - d[l]);
        cut.push_back(x[k] + t * (x[l] - x[k]));
      }
    }
    if (cut.size() == 2) {
      segments.emplace_back(u.dot(cut[0]), v.dot(cut[0]), u.dot(cut[1]), v.dot(cut[1]));
    }
  }
  Eigen::MatrixXd out(segments.size(), 4);
  for (size_t i = 0; i < segments.size(); ++i) out.row(i) = segments[i].transpose();
  return out;
}

namespace {

std::string axis_label(const Eigen::Vector3d& axis) {
  const char* names = "xyz";
  for (int k = 0; k < 3; ++k) {
    if (std::abs(axis[k]) == 1.0) return std::string(axis[k] < 0 ? "-" : "") + names[k] + " (m)";
  }
  // + 0.0 turns a negative zero (a flipped horizontal direction's z) into 0.
  return "along (" + format_significant(axis.x() + 0.0, 3) + ", " +
         format_significant(axis.y() + 0.0, 3) + ", " + format_significant(axis.z() + 0.0, 3) +
         ") (m)";
}

// The corner ("top right", ...) whose quarter-sized box holds the fewest of `points` (u, v).
std::string emptiest_corner(const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& lo,
                            const Eigen::Vector2d& hi) {
  const Eigen::Vector2d size = hi - lo;
  const char* names[4] = {"top right", "top left", "bottom right", "bottom left"};
  size_t best = 0, fewest = SIZE_MAX;
  for (int c = 0; c < 4; ++c) {
    const bool right = c % 2 == 0, top = c < 2;
    const double u0 = right ? hi[0] - 0.4 * size[0] : lo[0],
                 u1 = right ? hi[0] : lo[0] + 0.4 * size[0];
    const double v0 = top ? hi[1] - 0.3 * size[1] : lo[1], v1 = top ? hi[1] : lo[1] + 0.3 * size[1];
    size_t n = 0;
    for (const Eigen::Vector2d& p : points)
      n += p[0] >= u0 && p[0] <= u1 && p[1] >= v0 && p[1] <= v1;
    if (n < fewest) {
      fewest = n;
      best = c;
    }
  }
  return names[best];
}

}  // namespace

std::string write_path_plot(const std::string& stem, const std::string& title,
                            const std::vector<PathSeries>& series, const std::vector<Plane>& planes,
                            const std::vector<ObstacleMesh>& meshes) {
  const PlotView view = plot_view(series);
  const int b = view.vertical;
  const char* names = "xyz";
  Eigen::Vector2d lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
  std::vector<Eigen::Vector2d> drawn;  // every point drawn, for the legend's corner
  for (size_t i = 0; i < series.size(); ++i) {
    const Eigen::MatrixXd& p = series[i].points;
    write_file_atomically(stem + "_" + std::to_string(i) + ".dat", [&](std::ostream& out) {
      for (Eigen::Index r = 0; r < p.rows(); ++r) {
        const Eigen::Vector3d x = p.row(r).transpose();
        const Eigen::Vector2d uv(view.time_axis ? series[i].times[r] : view.u.dot(x),
                                 view.time_axis ? x[b] : view.v.dot(x));
        out << exact(uv[0]) << " " << exact(uv[1]) << "\n";
        lo = lo.cwiseMin(uv);
        hi = hi.cwiseMax(uv);
        drawn.push_back(uv);
      }
    });
  }
  // Obstacle meshes: each cut through its own centre by a plane parallel to the view, so that a
  // hoop off the paths' plane still shows (a side view, as a person would sketch the scene).
  const Eigen::Vector3d w = view.u.cross(view.v);
  bool any_section = false;
  if (!view.time_axis && !meshes.empty()) {
    // Sections extend the view, but no farther than the paths' own extent on every side (a
    // large floor mesh must not shrink the paths to a dot).
    const Eigen::Vector2d reach = (hi - lo).cwiseMax(1e-3);
    const Eigen::Vector2d cap_lo = lo - reach, cap_hi = hi + reach;
    write_file_atomically(stem + "_obstacles.dat", [&](std::ostream& out) {
      for (const ObstacleMesh& m : meshes) {
        const Eigen::Vector3d centre =
            0.5 * (m.V.colwise().minCoeff() + m.V.colwise().maxCoeff()).transpose();
        const Eigen::MatrixXd cut = mesh_section(m.V, m.F, centre, w, view.u, view.v);
        out << "# " << m.name << ": " << cut.rows() << " segments of its section through "
            << exact(centre.x()) << " " << exact(centre.y()) << " " << exact(centre.z()) << "\n";
        for (Eigen::Index r = 0; r < cut.rows(); ++r) {
          out << exact(cut(r, 0)) << " " << exact(cut(r, 1)) << "\n"
              << exact(cut(r, 2)) << " " << exact(cut(r, 3)) << "\n\n";
          for (int e = 0; e < 2; ++e) {
            const Eigen::Vector2d q(cut(r, 2 * e), cut(r, 2 * e + 1));
            lo = lo.cwiseMin(q.cwiseMax(cap_lo));
            hi = hi.cwiseMax(q.cwiseMin(cap_hi));
            drawn.push_back(q);
          }
        }
        any_section = any_section || cut.rows() > 0;
      }
    });
  }
  // In the time view a plane is a fixed height only when its normal is the plotted axis. In a
  // spatial view the plane n . x = c meets the view's plane {x : w . x = w . origin} in the line
  // (n . u) s + (n . v) t = c - (n . w)(w . origin), (s, t) the picture's coordinates.
  struct Trace {
    double na, nb, c;
  };
  std::vector<Trace> shown;
  for (const Plane& plane : planes) {
    if (!view.time_axis) {
      shown.push_back({plane.normal.dot(view.u), plane.normal.dot(view.v),
                       plane.offset - plane.normal.dot(w) * w.dot(view.origin)});
    } else if (std::abs(std::abs(plane.normal[b]) - 1.0) < 1e-9) {
      shown.push_back({0.0, plane.normal[b], plane.offset});  // (t, u) view
    }
  }
  // Show every plane: extend the view to the point of each plane's trace nearest the paths.
  const Eigen::Vector2d centre = (lo + hi) / 2;
  for (const Trace& t : shown) {
    const Eigen::Vector2d n(t.na, t.nb);
    if (n.squaredNorm() < 1e-12) continue;
    const Eigen::Vector2d foot = centre - (n.dot(centre) - t.c) / n.squaredNorm() * n;
    lo = lo.cwiseMin(foot);
    hi = hi.cwiseMax(foot);
  }
  Eigen::Vector2d pad = 0.1 * (hi - lo).cwiseMax(1e-3);
  if (view.time_axis) pad[0] = 0;
  lo -= pad;
  hi += pad;
  if (!view.time_axis) {
    // At equal scales, widen the narrower extent to the canvas's 4:3, so that the picture fills
    // it and the legend finds room inside (a star's tall path would leave a thin strip).
    const Eigen::Vector2d size = hi - lo;
    const Eigen::Vector2d want(std::max(size[0], size[1] * 4.0 / 3.0),
                               std::max(size[1], size[0] * 3.0 / 4.0));
    lo -= (want - size) / 2;
    hi += (want - size) / 2;
  }
  const std::string base = std::filesystem::path(stem).filename().string();
  write_file_atomically(stem + ".gp", [&](std::ostream& out) {
    out << "set terminal pngcairo size 1000,750 noenhanced\n"
        << "set output '" << base << ".png'\n"
        << "set title '" << gnuplot_quoted(title) << "'\n"
        << "set xlabel '" << (view.time_axis ? std::string("t (s)") : axis_label(view.u))
        << "'\nset ylabel '"
        << (view.time_axis ? std::string(1, names[b]) + " (m)" : axis_label(view.v)) << "'\n"
        << (view.time_axis ? "" : "set size ratio -1\n") << "set grid\n"
        << "set key inside " << emptiest_corner(drawn, lo, hi) << " opaque box\n"
        << "set xrange [" << lo[0] << ":" << hi[0] << "]\nset yrange [" << lo[1] << ":" << hi[1]
        << "]\n";
    int arrow = 1;
    for (const Trace& t : shown) {
      const double na = t.na, nb = t.nb, c = t.c;
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
    if (any_section) {
      out << (series.empty() ? "" : ", ") << "'" << base
          << "_obstacles.dat' using 1:2 with lines lw 3 lc rgb '#505050' title 'obstacles "
             "(sections)'";
    }
    out << "\n";
  });
  return render_gnuplot(stem);
}

}  // namespace rbaa
