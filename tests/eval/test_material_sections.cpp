// Cross-sections of a material field: the cuts tile the section exactly (areas of a box's cuts
// sum to its face area on any plane through it, including planes through vertices), each cut
// lies inside its element's span, and the picture's data carries each element's own value.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/io_test_support.hpp"
#include "rbaa/eval/material_sections.hpp"
#include "rbaa/mesh/tetrahedralize.hpp"

namespace rbaa {
namespace {

double polygon_area(const std::vector<Eigen::Vector2d>& c) {
  double a = 0;
  for (size_t i = 0; i < c.size(); ++i) {
    const Eigen::Vector2d& p = c[i];
    const Eigen::Vector2d& q = c[(i + 1) % c.size()];
    a += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * a;
}

TEST(MaterialSections, CutsTileABoxSectionOnAnyPlane) {
  ShapeParameters p;
  p.side = 0.1;
  const TetMesh cube = mesh_shape("cube", 400, p);
  const Eigen::Vector3d lo = cube.V.colwise().minCoeff(), hi = cube.V.colwise().maxCoeff();
  for (int axis = 0; axis < 3; ++axis) {
    // The middle, a plane through mesh vertices (a vertex's own coordinate), and near a face.
    const double through_vertex = cube.V(cube.num_vertices() / 2, axis);
    for (double offset : {0.5 * (lo[axis] + hi[axis]), through_vertex, hi[axis] - 1e-6}) {
      const std::vector<SectionPolygon> cuts = section_polygons(cube, axis, offset);
      double area = 0;
      bool convex_ccw = true;
      for (const SectionPolygon& c : cuts) {
        ASSERT_GE(c.corners.size(), 3u);
        ASSERT_LE(c.corners.size(), 4u);
        const double a = polygon_area(c.corners);
        convex_ccw = convex_ccw && a >= -1e-18;  // ordered counter-clockwise (or degenerate)
        area += a;
      }
      const int u = axis == 0 ? 1 : 0, v = axis == 2 ? 1 : 2;
      const double face = (hi[u] - lo[u]) * (hi[v] - lo[v]);
      std::printf("axis %d at %.6f: %zu cuts, area %.15e of %.15e\n", axis, offset, cuts.size(), area, face);
      EXPECT_TRUE(convex_ccw);
      EXPECT_NEAR(area, face, 1e-12 * face);
    }
  }
  // A plane that misses the object cuts nothing.
  EXPECT_TRUE(section_polygons(cube, 2, hi[2] + 1.0).empty());
}

TEST(MaterialSections, DataCarriesEachElementsValueAndThePictureIsDrawn) {
  ShapeParameters p;
  p.radius = 0.1;
  const TetMesh ball = mesh_shape("sphere", 300, p);
  MaterialField m = MaterialField::uniform(ball.num_tets(), 1e10, 0.3, 2500, 1.0);
  for (int e = 0; e < ball.num_tets(); ++e) {
    m.Y[e] = std::pow(10.0, 9.5 + 2.0 * e / ball.num_tets());  // element index is readable back
    m.alpha[e] = 0.5 + 0.5 * (e % 2);
  }
  const test::ScratchDir scratch;
  const std::string dir = scratch.path().string();
  const std::string png = write_material_sections(dir + "/materials", "the test's ball", ball, m, Eigen::Vector3d::Zero());
  // The first block is log10 Y on x = 0: every corner's value is its cut's element's log10 Y.
  const std::vector<SectionPolygon> cuts = section_polygons(ball, 0, 0.0);
  std::ifstream in(dir + "/materials.dat");
  std::string line;
  std::getline(in, line);  // the block's comment
  for (const SectionPolygon& c : cuts) {
    for (size_t i = 0; i <= c.corners.size(); ++i) {
      ASSERT_TRUE(std::getline(in, line));
      std::istringstream row(line);
      double u, v, value;
      row >> u >> v >> value;
      EXPECT_NEAR(value, std::log10(m.Y[c.element]), 1e-8);
      EXPECT_NEAR(u, c.corners[i % c.corners.size()].x(), 1e-8);
    }
    std::getline(in, line);
    EXPECT_TRUE(line.empty());
  }
  EXPECT_TRUE(std::filesystem::exists(dir + "/materials.gp"));
  {
    // The overall title is plain text: a scene name's underscore is not a subscript.
    std::ifstream gp(dir + "/materials.gp");
    std::stringstream script;
    script << gp.rdbuf();
    EXPECT_NE(script.str().find("title 'the test''s ball' noenhanced"), std::string::npos)
        << script.str();
    // Each field's three cuts are drawn in their own planes' axes: x = c in (y, z), y = c in
    // (x, z), z = c in (x, y).
    auto count = [&](const std::string& what) {
      int n = 0;
      for (size_t at = script.str().find(what); at != std::string::npos;
           at = script.str().find(what, at + 1)) {
        ++n;
      }
      return n;
    };
    EXPECT_EQ(count("set xlabel 'y (m)'\nset ylabel 'z (m)'"), 3) << script.str();
    EXPECT_EQ(count("set xlabel 'x (m)'\nset ylabel 'z (m)'"), 3) << script.str();
    EXPECT_EQ(count("set xlabel 'x (m)'\nset ylabel 'y (m)'"), 3) << script.str();
  }
  if (std::system("command -v gnuplot >/dev/null 2>&1") == 0) {
    EXPECT_EQ(png, dir + "/materials.png");
    EXPECT_GT(std::filesystem::file_size(png), 10000u);
  }
}

}  // namespace
}  // namespace rbaa
