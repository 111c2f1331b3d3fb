// The demonstration scenes' obstacle meshes (scripts/make_obstacle_meshes.py): the rim and the bin
// are closed, consistently outward-oriented, not self-intersecting, and have the sizes the issue
// asks for (rim inner diameter 0.4572 m, tube radius 8 mm).

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <map>
#include <string>
#include <utility>

#include "rbaa/io/triangle_soup.hpp"
#include "rbaa/mesh/surface.hpp"

namespace rbaa {
namespace {

std::string mesh_path(const std::string& name) {
  return std::string(RBAA_SOURCE_DIR) + "/configs/meshes/" + name;
}

// Every directed edge once and its reverse once: closed, manifold, consistently oriented.
void expect_closed_and_consistent(const SurfaceMesh& s, const std::string& name) {
  std::map<std::pair<int, int>, int> edges;
  for (Eigen::Index f = 0; f < s.F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) ++edges[{s.F(f, k), s.F(f, (k + 1) % 3)}];
  }
  for (const auto& [e, count] : edges) {
    EXPECT_EQ(count, 1) << name << ": edge " << e.first << "-" << e.second << " repeated";
    const auto back = edges.find({e.second, e.first});
    ASSERT_NE(back, edges.end()) << name << ": edge " << e.first << "-" << e.second
                                 << " is a border";
    EXPECT_EQ(back->second, 1) << name;
  }
}

// Signed volume: positive for outward orientation.
double signed_volume(const SurfaceMesh& s) {
  double v = 0;
  for (Eigen::Index f = 0; f < s.F.rows(); ++f) {
    const Eigen::Vector3d a = s.V.row(s.F(f, 0)).transpose(), b = s.V.row(s.F(f, 1)).transpose(),
                          c = s.V.row(s.F(f, 2)).transpose();
    v += a.dot(b.cross(c)) / 6.0;
  }
  return v;
}

TEST(ObstacleMeshes, TheHoopIsAClosedOutwardTorusOfTheRimsSize) {
  const SurfaceMesh hoop = read_triangle_soup(mesh_path("hoop.obj"));
  expect_closed_and_consistent(hoop, "hoop.obj");
  // A torus of ring radius R = 0.2366 and tube radius r = 0.008 holds 2 pi^2 R r^2; the
  // 64 x 12 polygon a few per cent less.
  const double torus = 2 * M_PI * M_PI * 0.2366 * 0.008 * 0.008;
  EXPECT_GT(signed_volume(hoop), 0.9 * torus);
  EXPECT_LT(signed_volume(hoop), torus);
  double inner = 1e9, outer = 0;
  for (Eigen::Index v = 0; v < hoop.V.rows(); ++v) {
    const double rho = hoop.V.row(v).head<2>().norm();
    inner = std::min(inner, rho);
    outer = std::max(outer, rho);
    EXPECT_LE(std::abs(hoop.V(v, 2)), 0.008 + 1e-12);
  }
  EXPECT_NEAR(2 * inner, 0.4572, 1e-6);
  EXPECT_NEAR(outer - inner, 0.016, 1e-6);
  // CGAL's checks too: manifold, closed, not self-intersecting.
  EXPECT_NO_THROW(read_surface(mesh_path("hoop.obj")));
}

TEST(ObstacleMeshes, TheBinIsAClosedOutwardSolidWithAnOpenTop) {
  const SurfaceMesh bin = read_triangle_soup(mesh_path("bin.obj"));
  expect_closed_and_consistent(bin, "bin.obj");
  EXPECT_GT(signed_volume(bin), 0);
  EXPECT_NO_THROW(read_surface(mesh_path("bin.obj")));
  // Standing on z = 0, centred on the z axis.
  EXPECT_DOUBLE_EQ(bin.V.col(2).minCoeff(), 0.0);
  EXPECT_NEAR(bin.V.col(0).minCoeff() + bin.V.col(0).maxCoeff(), 0.0, 1e-12);
  EXPECT_NEAR(bin.V.col(1).minCoeff() + bin.V.col(1).maxCoeff(), 0.0, 1e-12);
}

}  // namespace
}  // namespace rbaa
