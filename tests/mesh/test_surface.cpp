#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include "rbaa/error.hpp"
#include "rbaa/mesh/primitives.hpp"
#include "rbaa/mesh/surface.hpp"
#include "rbaa/mesh/tetrahedralize.hpp"

namespace rbaa {
namespace {

class SurfaceFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::path(::testing::TempDir()) /
           ("rbaa_surface_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }

  std::string write_off(const std::string& name, const SurfaceMesh& s) {
    std::ostringstream out;
    out.precision(17);
    out << "OFF\n" << s.V.rows() << " " << s.F.rows() << " 0\n";
    for (Eigen::Index i = 0; i < s.V.rows(); ++i) out << s.V(i, 0) << " " << s.V(i, 1) << " " << s.V(i, 2) << "\n";
    for (Eigen::Index i = 0; i < s.F.rows(); ++i) out << "3 " << s.F(i, 0) << " " << s.F(i, 1) << " " << s.F(i, 2) << "\n";
    return write(name, out.str());
  }

  // The error must name the file and say what is wrong.
  void expect_error(const std::string& path, const std::string& fault) {
    try {
      read_surface(path);
      FAIL() << "no error for " << path;
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(path), std::string::npos) << what;
      EXPECT_NE(what.find(fault), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << "one line: " << what;
    }
  }

  std::filesystem::path dir_;
};

TEST_F(SurfaceFiles, ClosedCubeIsReadAndMeshed) {
  const std::string path = write_off("cube.off", cube_surface(1.0));
  SurfaceMesh s = read_surface(path);
  EXPECT_NEAR(enclosed_volume(s), 1.0, 1e-12);
  const TetMesh mesh = mesh_surface_file(path, 300, 2.0);
  EXPECT_NEAR(tet_volumes(mesh).sum(), 2.0, 1e-9);
}

TEST_F(SurfaceFiles, ObjAndStlAreRead) {
  const SurfaceMesh cube = cube_surface(1.0);
  std::ostringstream obj, stl;
  obj.precision(17);
  stl.precision(17);
  stl << "solid cube\n";
  for (Eigen::Index i = 0; i < cube.V.rows(); ++i) obj << "v " << cube.V.row(i) << "\n";
  for (Eigen::Index f = 0; f < cube.F.rows(); ++f) {
    obj << "f " << cube.F(f, 0) + 1 << " " << cube.F(f, 1) + 1 << " " << cube.F(f, 2) + 1 << "\n";
    stl << "facet normal 0 0 0\nouter loop\n";
    for (int c = 0; c < 3; ++c) stl << "vertex " << cube.V.row(cube.F(f, c)) << "\n";
    stl << "endloop\nendfacet\n";
  }
  stl << "endsolid cube\n";
  EXPECT_NEAR(enclosed_volume(read_surface(write("cube.obj", obj.str()))), 1.0, 1e-12);
  EXPECT_NEAR(enclosed_volume(read_surface(write("cube.stl", stl.str()))), 1.0, 1e-12);
}

TEST_F(SurfaceFiles, InwardSurfaceIsReoriented) {
  SurfaceMesh s = cube_surface(1.0);
  s.F.col(1).swap(s.F.col(2));
  EXPECT_NEAR(enclosed_volume(read_surface(write_off("inward.off", s))), 1.0, 1e-12);
}

// A point no face uses (here one before the cube's and one after) is no part of the surface: it
// is dropped, the faces renumbered, and the cube meshed as without it (CGAL's mesher crashed on
// such a point: a segmentation fault in `rbaa mesh --surface`).
TEST_F(SurfaceFiles, PointsNoFaceUsesAreDropped) {
  const SurfaceMesh cube = cube_surface(1.0);
  SurfaceMesh stray;
  stray.V.resize(cube.V.rows() + 2, 3);
  stray.V.row(0) << 5, 5, 5;
  stray.V.middleRows(1, cube.V.rows()) = cube.V;
  stray.V.row(cube.V.rows() + 1) << -7, 0, 2;
  stray.F = cube.F.array() + 1;
  const std::string path = write_off("stray.off", stray);
  const SurfaceMesh s = read_surface(path);
  EXPECT_EQ(s.V.rows(), cube.V.rows());
  EXPECT_NEAR(enclosed_volume(s), 1.0, 1e-12);
  const TetMesh mesh = mesh_surface_file(path, 300, 2.0);
  EXPECT_NEAR(tet_volumes(mesh).sum(), 2.0, 1e-9);
}

TEST_F(SurfaceFiles, UnreadableFile) { expect_error((dir_ / "missing.off").string(), "cannot open"); }

TEST_F(SurfaceFiles, MalformedFile) {
  expect_error(write("garbage.off", "OFF\n8 12 0\n0 0 zero\n"), "cannot read");
}

TEST_F(SurfaceFiles, OpenSurface) {
  SurfaceMesh s = cube_surface(1.0);
  SurfaceMesh open = s;
  open.F.conservativeResize(s.F.rows() - 1, 3);
  expect_error(write_off("open.off", open), "not closed");
}

TEST_F(SurfaceFiles, NonManifoldEdge) {
  // Two cubes sharing one edge: that edge borders four faces.
  SurfaceMesh a = cube_surface(1.0), b = cube_surface(1.0);
  b.V.rowwise() += Eigen::RowVector3d(1.0, 1.0, 0.0);
  SurfaceMesh s;
  s.V.resize(16, 3);
  s.V << a.V, b.V;
  s.F.resize(24, 3);
  s.F << a.F, (b.F.array() + 8).matrix();
  // Merge b's vertices that coincide with a's (the shared edge x = y = 0.5).
  for (int i = 8; i < 16; ++i) {
    for (int j = 0; j < 8; ++j) {
      if ((s.V.row(i) - s.V.row(j)).norm() < 1e-12) {
        for (Eigen::Index k = 0; k < s.F.size(); ++k) {
          if (s.F.data()[k] == i) s.F.data()[k] = j;
        }
      }
    }
  }
  expect_error(write_off("edge.off", s), "non-manifold");
}

TEST_F(SurfaceFiles, NonManifoldVertex) {
  // Two cubes touching at one corner.
  SurfaceMesh a = cube_surface(1.0), b = cube_surface(1.0);
  b.V.rowwise() += Eigen::RowVector3d(1.0, 1.0, 1.0);
  SurfaceMesh s;
  s.V.resize(15, 3);
  s.F.resize(24, 3);
  s.V.topRows(8) = a.V;
  // b's corner (-0.5,-0.5,-0.5)+1 = a's corner 7 (0.5, 0.5, 0.5); b's vertex 0 maps to 7.
  int next = 8;
  std::vector<int> map(8);
  for (int i = 0; i < 8; ++i) {
    if (i == 0) {
      map[i] = 7;
    } else {
      s.V.row(next) = b.V.row(i);
      map[i] = next++;
    }
  }
  s.F.topRows(12) = a.F;
  for (int f = 0; f < 12; ++f) {
    for (int c = 0; c < 3; ++c) s.F(12 + f, c) = map[b.F(f, c)];
  }
  expect_error(write_off("vertex.off", s), "non-manifold");
}

TEST_F(SurfaceFiles, SelfIntersectingSurface) {
  // Two overlapping closed cubes in one file: each is closed and manifold, together they cross.
  SurfaceMesh a = cube_surface(1.0), b = cube_surface(1.0);
  b.V.rowwise() += Eigen::RowVector3d(0.5, 0.3, 0.2);
  SurfaceMesh s;
  s.V.resize(16, 3);
  s.V << a.V, b.V;
  s.F.resize(24, 3);
  s.F << a.F, (b.F.array() + 8).matrix();
  expect_error(write_off("crossing.off", s), "intersects itself");
}

TEST(Primitives, SurfacesAreClosedWithTheRightVolume) {
  auto check = [](SurfaceMesh s, double volume, double tol, const char* name) {
    EXPECT_NO_THROW(validate_surface(s, name)) << name;
    EXPECT_NEAR(enclosed_volume(s) / volume, 1.0, tol) << name;
  };
  check(cube_surface(0.05), 0.05 * 0.05 * 0.05, 1e-12, "cube");
  check(sphere_surface(0.121), 4.0 / 3.0 * M_PI * std::pow(0.121, 3), 2e-3, "sphere");
  // Star area: 10 triangles of 1/2 R r sin(36 deg).
  check(star_surface(), 10 * 0.5 * 1.0 * 0.4 * std::sin(M_PI / 5) * 0.3, 1e-12, "star");
  check(lathe_surface({{0, 1}, {1, 1}}, 256), M_PI, 1e-3, "cylinder");
}

}  // namespace
}  // namespace rbaa
