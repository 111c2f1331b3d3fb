#include "rbaa/io/triangle_soup.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/polygon_soup_io.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

#include "rbaa/error.hpp"
#include "rbaa/io/text_reader.hpp"

namespace rbaa {
namespace {

struct Soup {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 3>> triangles;
  std::vector<int> lines;  // source line of each triangle (0: unknown)
};

void fan(const std::vector<int>& polygon, int line, Soup& soup) {
  for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
    soup.triangles.push_back({polygon[0], polygon[k], polygon[k + 1]});
    soup.lines.push_back(line);
  }
}

// OBJ: "v x y z [w]" and "f a b c ..." records; everything else (vn, vt, g, o, usemtl, s, l, ...)
// carries nothing a static obstacle needs.
Soup read_obj(const std::string& path) {
  TextReader r(path);
  r.set_comment_char('#');
  Soup soup;
  while (r.next_line()) {
    const std::string_view key = r.read_word("a record");
    if (key == "v") {
      Eigen::Vector3d x;
      x.x() = r.read_double("vertex x");
      x.y() = r.read_double("vertex y");
      x.z() = r.read_double("vertex z");
      if (!x.allFinite())
        r.fail("vertex " + std::to_string(soup.points.size() + 1) + " is not finite");
      soup.points.push_back(x);
    } else if (key == "f") {
      std::vector<int> polygon;
      while (r.has_word()) {
        const std::string_view word = r.read_word("a face corner");
        const std::string_view index = word.substr(0, word.find('/'));
        const long long i = r.to_int(index, "a face corner's vertex index");
        const long long n = static_cast<long long>(soup.points.size());
        const long long v = i > 0 ? i - 1 : n + i;  // OBJ counts from 1; negative: from the end
        if (i == 0 || v < 0 || v >= n) {
          r.fail("face corner " + TextReader::quote(word) + " refers to vertex " +
                 std::to_string(i) + ", but " + std::to_string(n) + " vertices are defined so far");
        }
        polygon.push_back(static_cast<int>(v));
      }
      if (polygon.size() < 3)
        r.fail("a face needs at least 3 corners, this one has " + std::to_string(polygon.size()));
      fan(polygon, r.line(), soup);
    }
  }
  return soup;
}

// OFF: "OFF", then "#V #F #E", #V lines "x y z", #F lines "n i_1 ... i_n [colour]".
Soup read_off(const std::string& path) {
  TextReader r(path);
  r.set_comment_char('#');
  Soup soup;
  r.expect_next_line("the OFF header");
  std::string_view head = r.read_word("the OFF header");
  if (head != "OFF") r.fail("expected the header 'OFF', found " + TextReader::quote(head));
  if (!r.has_word()) r.expect_next_line("the counts #vertices #faces #edges");
  const int nv = r.read_count("the number of vertices");
  const int nf = r.read_count("the number of faces");
  for (int i = 0; i < nv; ++i) {
    r.expect_next_line("vertex " + std::to_string(i));
    Eigen::Vector3d x;
    x.x() = r.read_double("vertex x");
    x.y() = r.read_double("vertex y");
    x.z() = r.read_double("vertex z");
    if (!x.allFinite()) r.fail("vertex " + std::to_string(i) + " is not finite");
    r.expect_line_end("vertex " + std::to_string(i) + " (x y z)");
    soup.points.push_back(x);
  }
  for (int f = 0; f < nf; ++f) {
    r.expect_next_line("face " + std::to_string(f));
    const int n = r.read_count("the face's number of corners", 1000000);
    if (n < 3)
      r.fail("face " + std::to_string(f) + " has " + std::to_string(n) +
             " corners; at least 3 are needed");
    std::vector<int> polygon;
    for (int k = 0; k < n; ++k) {
      const long long v = r.read_int("a face corner's vertex index");
      if (v < 0 || v >= nv) {
        r.fail("face " + std::to_string(f) + " refers to vertex " + std::to_string(v) +
               ", but there are " + std::to_string(nv) + " (counted from 0)");
      }
      polygon.push_back(static_cast<int>(v));
    }
    fan(polygon, r.line(), soup);
  }
  // What follows the announced faces would be dropped without a word (a second body, say).
  while (r.next_line()) {
    if (r.has_word()) {
      r.fail("more than the " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
             " faces the header announces");
    }
  }
  return soup;
}

// STL, PLY: CGAL's readers (binary or ASCII).
Soup read_with_cgal(const std::string& path) {
  using Point = CGAL::Exact_predicates_inexact_constructions_kernel::Point_3;
  std::vector<Point> points;
  std::vector<std::vector<std::size_t>> polygons;
  bool ok = false;
  try {
    ok = CGAL::IO::read_polygon_soup(path, points, polygons);
  } catch (const std::exception& e) {
    throw InputError(path + ": cannot read surface (" + e.what() + ")");
  }
  if (!ok) throw InputError(path + ": cannot read surface (malformed file)");
  Soup soup;
  for (const Point& p : points) soup.points.emplace_back(p.x(), p.y(), p.z());
  for (std::size_t f = 0; f < polygons.size(); ++f) {
    if (polygons[f].size() < 3)
      throw InputError(path + ": face " + std::to_string(f) + " has fewer than 3 vertices");
    std::vector<int> polygon;
    for (std::size_t v : polygons[f]) {
      if (v >= points.size())
        throw InputError(path + ": face " + std::to_string(f) + " refers to a missing vertex " +
                         std::to_string(v));
      polygon.push_back(static_cast<int>(v));
    }
    fan(polygon, 0, soup);
  }
  return soup;
}

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext;
}

}  // namespace

SurfaceMesh read_triangle_soup(const std::string& path) {
  {
    std::ifstream probe(path);
    if (!probe) throw InputError(path + ": cannot open surface file");
  }
  const std::string ext = lower_extension(path);
  Soup soup;
  if (ext == ".obj") {
    soup = read_obj(path);
  } else if (ext == ".off") {
    soup = read_off(path);
  } else if (ext == ".stl" || ext == ".ply") {
    soup = read_with_cgal(path);
  } else {
    throw InputError(path + ": unsupported surface format '" + ext +
                     "' (use .obj, .off, .stl or .ply)");
  }
  if (soup.triangles.empty()) throw InputError(path + ": the file holds no triangles");
  SurfaceMesh s;
  s.V.resize(static_cast<Eigen::Index>(soup.points.size()), 3);
  for (std::size_t i = 0; i < soup.points.size(); ++i)
    s.V.row(static_cast<Eigen::Index>(i)) = soup.points[i].transpose();
  if (!s.V.allFinite()) throw InputError(path + ": a vertex coordinate is not finite");
  s.F.resize(static_cast<Eigen::Index>(soup.triangles.size()), 3);
  for (std::size_t f = 0; f < soup.triangles.size(); ++f) {
    const auto& t = soup.triangles[f];
    const std::string where =
        path + (soup.lines[f] > 0 ? ":" + std::to_string(soup.lines[f]) : "") + ": ";
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
      throw InputError(where + "triangle " + std::to_string(f) + " repeats a vertex (" +
                       std::to_string(t[0]) + ", " + std::to_string(t[1]) + ", " +
                       std::to_string(t[2]) + ")");
    }
    const Eigen::Vector3d a = soup.points[t[0]], b = soup.points[t[1]], c = soup.points[t[2]];
    const double scale =
        std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), (c - b).squaredNorm()});
    if (!((b - a).cross(c - a).squaredNorm() > 1e-24 * scale * scale)) {
      throw InputError(where + "triangle " + std::to_string(f) +
                       " has zero area (corners on one line)");
    }
    for (int k = 0; k < 3; ++k) s.F(static_cast<Eigen::Index>(f), k) = t[k];
  }
  return s;
}

}  // namespace rbaa
