#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>

#include "rbaa/geometry/moments.hpp"
#include "rbaa/mesh/grid_mesh.hpp"
#include "rbaa/mesh/tetrahedralize.hpp"

namespace rbaa {
namespace {

// Closed-form moments of a uniform box [lo, hi] about the origin.
Moments box_moments(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double rho) {
  const Eigen::Vector3d l = hi - lo, c = (hi + lo) / 2;
  Moments m;
  m.m0 = rho * l.prod();
  m.m1 = m.m0 * c;
  // int x_i^2 = m0 (l_i^2 / 12 + c_i^2); int x_i x_j = m0 c_i c_j (i != j).
  Eigen::Vector3d sq;
  for (int i = 0; i < 3; ++i) sq[i] = m.m0 * (l[i] * l[i] / 12 + c[i] * c[i]);
  m.m2 << sq[1] + sq[2], sq[0] + sq[2], sq[0] + sq[1], -m.m0 * c[0] * c[1], -m.m0 * c[0] * c[2],
      -m.m0 * c[1] * c[2];
  return m;
}

TEST(Moments, BoxMatchesClosedForm) {
  const Eigen::Vector3d lo(0.3, -1.2, 0.5), hi(1.1, -0.4, 2.0);
  const TetMesh mesh = box_tet_mesh(lo, hi, 3, 2, 4);
  const Moments m = compute_moments(mesh, 2500.0);
  const Moments ref = box_moments(lo, hi, 2500.0);
  const MomentVector d = m.as_vector() - ref.as_vector();
  for (int i = 0; i < 10; ++i) {
    EXPECT_NEAR(d[i], 0.0, 1e-12 * std::abs(ref.as_vector().cwiseAbs().maxCoeff())) << "moment " << i;
  }
}

// A box of two densities (lower half rho_a, upper half in z rho_b) against the sum of two
// closed-form uniform boxes: a non-uniform density checked independently of the operator.
TEST(Moments, TwoDensityBoxMatchesClosedForm) {
  const Eigen::Vector3d lo(0.3, -1.2, 0.5), hi(1.1, -0.4, 2.1);
  const TetMesh mesh = box_tet_mesh(lo, hi, 3, 2, 4);  // 4 cells in z: the split at z = 1.3 is a grid plane
  const double rho_a = 1200.0, rho_b = 9100.0, z_split = 0.5 * (lo.z() + hi.z());
  Eigen::VectorXd density(mesh.num_tets());
  for (int e = 0; e < mesh.num_tets(); ++e) {
    double zc = 0;
    for (int a = 0; a < 4; ++a) zc += mesh.V(mesh.T(e, a), 2) / 4;
    density[e] = zc < z_split ? rho_a : rho_b;
  }
  const Moments m = compute_moments(mesh, density);
  const MomentVector ref = box_moments(lo, {hi.x(), hi.y(), z_split}, rho_a).as_vector() +
                           box_moments({lo.x(), lo.y(), z_split}, hi, rho_b).as_vector();
  const MomentVector d = m.as_vector() - ref;
  for (int i = 0; i < 10; ++i) {
    EXPECT_NEAR(d[i], 0.0, 1e-12 * ref.cwiseAbs().maxCoeff()) << "moment " << i;
  }
  // The centre of mass lies in the heavy half, where the closed form puts it.
  EXPECT_NEAR(m.centre_of_mass().z(), ref[3] / ref[0], 1e-12);
  EXPECT_GT(m.centre_of_mass().z(), z_split);
}

TEST(Moments, OperatorIsLinearInDensity) {
  const TetMesh mesh = box_tet_mesh({0, 0, 0}, {1, 2, 3}, 2, 2, 2);
  const Eigen::VectorXd rho = Eigen::VectorXd::LinSpaced(mesh.num_tets(), 800, 11300);
  const auto S = moment_operator(mesh);
  const MomentVector direct = compute_moments(mesh, rho).as_vector();
  EXPECT_LT((S * rho - direct).norm(), 1e-12 * direct.norm());
  // Two halves add up.
  Eigen::VectorXd a = rho, b = rho;
  a.tail(mesh.num_tets() / 2).setZero();
  b.head(mesh.num_tets() - mesh.num_tets() / 2).setZero();
  EXPECT_LT((compute_moments(mesh, a).as_vector() + compute_moments(mesh, b).as_vector() - direct).norm(),
            1e-12 * direct.norm());
}

TEST(Moments, MeshedSphereWithinMeshingError) {
  const double r = 0.121, rho = 2500;
  const TetMesh mesh = mesh_shape("sphere", 3000);
  const Moments m = compute_moments(mesh, rho);
  const double m0 = rho * 4.0 / 3.0 * M_PI * r * r * r;
  // Inscribed polyhedra lose volume as (edge / r)^2; at 3000 tets that is below 2 %.
  EXPECT_NEAR(m.m0 / m0, 1.0, 0.02);
  const double I = 0.4 * m0 * r * r;
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(m.m2[i] / I, 1.0, 0.035);
  EXPECT_LT(m.m1.norm() / (m.m0 * r), 1e-2);
  for (int i = 3; i < 6; ++i) EXPECT_LT(std::abs(m.m2[i]) / I, 1e-2);
}

TEST(Moments, TranslationAndRotationAreConsistent) {
  TetMesh mesh = box_tet_mesh({-0.2, 0.1, 0.0}, {0.5, 0.4, 0.9}, 2, 3, 2);
  Eigen::VectorXd rho = Eigen::VectorXd::LinSpaced(mesh.num_tets(), 800, 11300);
  const Moments before = compute_moments(mesh, rho);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  const Eigen::Vector3d t(1.5, -0.3, 2.0);
  for (int i = 0; i < mesh.num_vertices(); ++i) {
    mesh.V.row(i) = (R * mesh.V.row(i).transpose() + t).transpose();
  }
  const Moments after = compute_moments(mesh, rho);
  EXPECT_NEAR(after.m0, before.m0, 1e-12 * before.m0);
  EXPECT_LT((after.m1 - (R * before.m1 + before.m0 * t)).norm(), 1e-10 * after.m1.norm());
  const Eigen::Matrix3d expected = R * before.inertia_about_centre() * R.transpose();
  EXPECT_LT((after.inertia_about_centre() - expected).norm(), 1e-10 * expected.norm());
  EXPECT_NEAR(radius_of_gyration(after), radius_of_gyration(before), 1e-12);
}

TEST(Moments, NormalisationUsesRadiusOfGyration) {
  const TetMesh mesh = box_tet_mesh({-1, -1, -1}, {1, 1, 1}, 1, 1, 1);
  const Moments m = compute_moments(mesh, 1.0);  // m0 = 8, I = 8 * 8 / 12 per axis
  const double L = std::sqrt(3 * (8.0 * 8.0 / 12.0) / (2 * 8.0));
  EXPECT_NEAR(radius_of_gyration(m), L, 1e-12);
  const MomentVector s = moment_normalisation(m);
  EXPECT_NEAR(s[0], 8.0, 1e-12);
  EXPECT_NEAR(s[1], 8.0 * L, 1e-12);
  EXPECT_NEAR(s[9], 8.0 * L * L, 1e-12);
}

}  // namespace
}  // namespace rbaa
