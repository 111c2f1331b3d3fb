#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <cmath>

#include "rbaa/error.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/mesh/tetrahedralize.hpp"
#include "rbaa/mesh/topology.hpp"

namespace rbaa {
namespace {

struct ShapeCase {
  std::string shape;
  double paper_m0;       // SPEC section 7, at 2500 kg/m^3
  double m0_tolerance;   // relative
};

void PrintTo(const ShapeCase& c, std::ostream* os) { *os << c.shape; }

class ShapeMeshing : public ::testing::TestWithParam<ShapeCase> {};

// Every reference shape at the paper's tet count: count within 5 % (README), every tet positive and
// non-degenerate, one closed boundary, and the paper's reference mass.
TEST_P(ShapeMeshing, PaperCountOrientationAndMass) {
  const ShapeCase c = GetParam();
  const int target = default_tet_count(c.shape);
  const TetMesh mesh = mesh_shape(c.shape, target);
  EXPECT_NEAR(static_cast<double>(mesh.num_tets()) / target, 1.0, 0.05) << mesh.num_tets();
  const Eigen::VectorXd vol = tet_volumes(mesh);
  EXPECT_GT(vol.minCoeff(), 1e-6 * vol.mean());
  EXPECT_NO_THROW(validate_tet_mesh(mesh, c.shape));
  EXPECT_EQ(count_components(mesh), 1);
  const Moments m = compute_moments(mesh, 2500.0);
  EXPECT_NEAR(m.m0 / c.paper_m0, 1.0, c.m0_tolerance) << "m0 = " << m.m0;
}

INSTANTIATE_TEST_SUITE_P(Shapes, ShapeMeshing,
                         ::testing::Values(ShapeCase{"sphere", 18.25, 0.02},
                                           ShapeCase{"star", 881.1, 0.01},
                                           ShapeCase{"cube", 0.3124, 0.01},
                                           ShapeCase{"bat", 4.132, 0.01},
                                           ShapeCase{"bunny", 3901.0, 1e-9}),
                         [](const auto& info) { return info.param.shape; });

TEST(Tetrahedralize, StarSecondMomentsMatchThePaper) {
  const Moments m = compute_moments(mesh_shape("star", 1506), 2500.0);
  EXPECT_NEAR(m.m2[0] / 217.8, 1.0, 0.01);
  EXPECT_NEAR(m.m2[1] / 115.5, 1.0, 0.01);
  EXPECT_NEAR(m.m2[2] / 115.5, 1.0, 0.01);
}

// The bat's fitted profile (primitives.cpp, scripts/fit_bat_profile.py) against the paper's
// Table 1 at the default mesh size: every moment within 1 % (measured within 0.08 %), the knob at
// the origin and the bat along +z (first moments off the axis at round-off).
TEST(Tetrahedralize, BatMomentsMatchThePapersTable1) {
  const Moments m = compute_moments(mesh_shape("bat", 9098), 2500.0);
  std::printf("bat: m0 %.4f m1_z %.4f m2_xx %.4f m2_yy %.4f m2_zz %.4e\n", m.m0, m.m1[2], m.m2[0],
              m.m2[1], m.m2[2]);
  EXPECT_NEAR(m.m0 / 4.132, 1.0, 0.01);
  EXPECT_NEAR(m.m1[2] / 2.287, 1.0, 0.01);
  EXPECT_NEAR(m.m2[0] / 1.453, 1.0, 0.01);
  EXPECT_NEAR(m.m2[1] / 1.453, 1.0, 0.01);
  EXPECT_NEAR(m.m2[2] / 1.713e-3, 1.0, 0.01);
  EXPECT_LT(std::abs(m.m1[0]) + std::abs(m.m1[1]), 1e-3 * m.m1[2]);
}

TEST(Tetrahedralize, BunnyIsUprightCentredAndScaled) {
  const TetMesh mesh = mesh_shape("bunny", 2274);
  const Moments m = compute_moments(mesh, 2500.0);
  EXPECT_NEAR(tet_volumes(mesh).sum(), 1.5604, 1e-9);
  EXPECT_LT(m.centre_of_mass().norm(), 1e-9);
  // SPEC: m2 about (1378, 850, 1052) after turning CGAL's y-up bunny upright.
  EXPECT_NEAR(m.m2[0] / 1378.0, 1.0, 0.02);
  EXPECT_NEAR(m.m2[1] / 850.0, 1.0, 0.02);
  EXPECT_NEAR(m.m2[2] / 1052.0, 1.0, 0.02);
}

TEST(Tetrahedralize, SameInputGivesTheSameMesh) {
  const TetMesh a = mesh_shape("cube", 3000);
  const TetMesh b = mesh_shape("cube", 3000);
  ASSERT_EQ(a.num_tets(), b.num_tets());
  ASSERT_EQ(a.num_vertices(), b.num_vertices());
  EXPECT_TRUE(a.T == b.T);
  EXPECT_TRUE(a.V == b.V);
}

TEST(Tetrahedralize, TargetCountIsFollowed) {
  for (int target : {500, 4000}) {
    const TetMesh mesh = mesh_shape("sphere", target);
    EXPECT_NEAR(static_cast<double>(mesh.num_tets()) / target, 1.0, 0.05) << target;
  }
}

TEST(Tetrahedralize, CoarseMeshesWithSharpFeaturesAreValid) {
  // At 400 tets Mesh_3 left a flat sliver (volume 2e-19 m^3) at a star tip; another cell size is
  // tried instead. Below ~550 tets the star's sharp edges set the count (300 gives 578), so only
  // validity is asserted here; the paper's counts are held to 5 % above.
  for (int target : {300, 400, 500}) {
    const TetMesh mesh = mesh_shape("star", target);
    EXPECT_NO_THROW(validate_tet_mesh(mesh, "star"));
    EXPECT_GT(tet_volumes(mesh).minCoeff(), 1e-6 * tet_volumes(mesh).mean()) << target;
  }
}

TEST(Tetrahedralize, UnknownShapeIsAnError) {
  EXPECT_THROW(mesh_shape("torus", 100), InputError);
}

}  // namespace
}  // namespace rbaa
