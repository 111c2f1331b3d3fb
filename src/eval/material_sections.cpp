#include "rbaa/eval/material_sections.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <ostream>

#include "rbaa/error.hpp"
#include "rbaa/eval/gnuplot.hpp"
#include "rbaa/io/atomic_file.hpp"
#include "rbaa/io/number_text.hpp"

namespace rbaa {

namespace {

// A plane's offset for a panel's title: four significant digits.
std::string short_number(double x) { return format_significant(x, 4); }

}  // namespace

std::vector<SectionPolygon> section_polygons(const TetMesh& mesh, int axis, double offset) {
  if (axis < 0 || axis > 2) throw InputError("material sections: axis must be 0, 1 or 2");
  const int u = axis == 0 ? 1 : 0, v = axis == 2 ? 1 : 2;
  std::vector<SectionPolygon> cuts;
  for (int e = 0; e < mesh.num_tets(); ++e) {
    Eigen::Vector3d x[4];
    double s[4];
    for (int a = 0; a < 4; ++a) {
      x[a] = mesh.V.row(mesh.T(e, a)).transpose();
      s[a] = x[a][axis] - offset;
    }
    SectionPolygon p;
    p.element = e;
    for (int a = 0; a < 4; ++a) {
      for (int b = a + 1; b < 4; ++b) {
        if ((s[a] >= 0) == (s[b] >= 0)) continue;
        const double t = s[a] / (s[a] - s[b]);
        const Eigen::Vector3d y = x[a] + t * (x[b] - x[a]);
        p.corners.emplace_back(y[u], y[v]);
      }
    }
    if (p.corners.size() < 3) continue;
    // Order the (convex) cut's corners by angle about their mean.
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& c : p.corners) mean += c;
    mean /= static_cast<double>(p.corners.size());
    std::sort(p.corners.begin(), p.corners.end(), [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
      return std::atan2(a.y() - mean.y(), a.x() - mean.x()) < std::atan2(b.y() - mean.y(), b.x() - mean.x());
    });
    cuts.push_back(std::move(p));
  }
  return cuts;
}

std::string write_material_sections(const std::string& stem, const std::string& title,
                                    const TetMesh& mesh, const MaterialField& materials,
                                    const Eigen::Vector3d& centre) {
  validate_material_field(materials, mesh.num_tets(), "material sections");
  const char* axis_names[] = {"x", "y", "z"};
  const std::string base = std::filesystem::path(stem).filename().string();
  struct Field {
    const char* label;
    Eigen::VectorXd values;
  };
  const Field fields[] = {
      {"log10 Y (Pa)", materials.Y.array().log10().matrix()},
      {"rho alpha (kg/m^3)", materials.effective_density()},
      {"occupancy alpha", materials.alpha}};
  // One data block per (plane, field) panel, polygons separated by blank lines, blocks by two.
  std::vector<std::vector<SectionPolygon>> cuts;
  for (int axis = 0; axis < 3; ++axis) cuts.push_back(section_polygons(mesh, axis, centre[axis]));
  write_file_atomically(stem + ".dat", [&](std::ostream& out) {
    out.precision(12);
    for (const Field& f : fields) {
      for (int axis = 0; axis < 3; ++axis) {
        out << "# " << f.label << " on " << axis_names[axis] << " = " << centre[axis] << "\n";
        for (const SectionPolygon& p : cuts[axis]) {
          for (size_t i = 0; i <= p.corners.size(); ++i) {
            const Eigen::Vector2d& c = p.corners[i % p.corners.size()];
            out << c.x() << " " << c.y() << " " << f.values[p.element] << "\n";
          }
          out << "\n";
        }
        out << "\n\n";
      }
    }
  });
  write_file_atomically(stem + ".gp", [&](std::ostream& out) {
    out << "# Cross-sections of the materials through the centre of mass; data in " << base << ".dat\n"
        << "set terminal pngcairo size 1500,1350 font ',10'\nset output '" << base << ".png'\n"
        << "set palette defined (0 '#440154', 0.25 '#3b528b', 0.5 '#21918c', 0.75 '#5ec962', 1 '#fde725')\n"
        << "set size ratio -1\nunset key\nset colorbox\n"
        // The panels' titles use enhanced text (m^3); the scene's name may hold an underscore,
        // which enhanced text would set as a subscript.
        << "set multiplot layout 3,3 title '" << gnuplot_quoted(title) << "' noenhanced\n";
    int block = 0;
    for (const Field& f : fields) {
      double lo = f.values.minCoeff(), hi = f.values.maxCoeff();
      if (!(hi > lo)) {  // a uniform field still needs a range
        lo -= 0.5 * std::max(std::abs(lo), 1.0) * 1e-3;
        hi += 0.5 * std::max(std::abs(hi), 1.0) * 1e-3;
      }
      for (int axis = 0; axis < 3; ++axis, ++block) {
        const int u = axis == 0 ? 1 : 0, v = axis == 2 ? 1 : 2;
        out << "set title '" << f.label << ", " << axis_names[axis] << " = " << short_number(centre[axis]) << " m'\n"
            << "set xlabel '" << axis_names[u] << " (m)'\nset ylabel '" << axis_names[v] << " (m)'\n"
            << "set cbrange [" << lo << ":" << hi << "]\n";
        if (cuts[axis].empty()) {
          out << "plot 1/0\n";  // the plane misses the object
        } else {
          out << "plot '" << base << ".dat' index " << block
              << " using 1:2:3 with filledcurves closed fc palette\n";
        }
      }
    }
    out << "unset multiplot\n";
  });
  return render_gnuplot(stem);
}

}  // namespace rbaa
