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
