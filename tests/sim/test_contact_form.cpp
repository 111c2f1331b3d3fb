// The vertex-plane pair and the contact form: derivatives against finite differences, CCD, and
// the energy-rule kappa (the barrier itself: tests/contact/test_barrier.cpp).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include "form_checks.hpp"
#include "mesh_fixtures.hpp"
#include "rbaa/mesh/topology.hpp"
#include "rbaa/contact/barrier.hpp"
#include "rbaa/sim/barrier_stiffness.hpp"
#include "rbaa/sim/contact_form.hpp"
#include "rbaa/sim/gravity_form.hpp"
#include "rbaa/sim/inertia_form.hpp"
#include "rbaa/sim/mass_matrix.hpp"
#include "rbaa/sim/vertex_plane.hpp"

namespace rbaa {
namespace {

TEST(VertexPlane, CcdStopsShortOfThePlane) {
  Plane p;
  p.normal = Eigen::Vector3d(0, 1, 1).normalized();
  p.offset = 0.1;
  const Eigen::Vector3d x0 = Eigen::Vector3d(0, 1, 1), x1 = Eigen::Vector3d(0, -1, -2);
  const double t = vertex_plane_ccd(x0, x1, p);
  const double d0 = vertex_plane_distance(x0, p);
  EXPECT_NEAR(vertex_plane_distance(x0 + t * (x1 - x0), p), 0.1 * d0, 1e-14);
  EXPECT_EQ(vertex_plane_ccd(x0, Eigen::Vector3d(0, 2, 2), p), 1.0);
}

TEST(ContactForm, DerivativesMatchFiniteDifferences) {
  // A ball whose lowest vertices sit inside the barrier zone of two perpendicular planes.
  const TetMesh mesh = test::ball_mesh(0.1, 2, Eigen::Vector3d(0, 0.1004, 0.1003));
  Plane floor, wall;
  floor.normal = Eigen::Vector3d::UnitZ();
  wall.normal = Eigen::Vector3d::UnitY();
  const ContactForm form(ContactSet(boundary_vertices(mesh), {floor, wall}, 1e-3), 4e7);
  const Eigen::VectorXd q = test::positions(mesh);
  ASSERT_GT(form.num_active_pairs(q), 1);
  SparseHessian H(mesh.T, mesh.num_vertices());
  const test::FdErrors e = test::check_form(form, q, 1e-9, H);
  std::printf("contact: gradient rel err %.2e, Hessian rel err %.2e\n", e.gradient, e.hessian);
  EXPECT_LE(e.gradient, 1e-6);
  EXPECT_LE(e.hessian, 1e-6);
  EXPECT_NEAR(form.value_difference(q, q + Eigen::VectorXd::Constant(q.size(), 1e-4)),
              form.value(q + Eigen::VectorXd::Constant(q.size(), 1e-4)) - form.value(q),
              1e-10 * form.value(q));
  // The CCD-limited step never reaches a plane, and a crossing state is invalid.
  const Eigen::VectorXd down = q - Eigen::VectorXd::Constant(q.size(), 0.01);
  const double t = form.max_step_size(q, down);
  EXPECT_LT(t, 1.0);
  EXPECT_GT(form.min_distance(q + t * (down - q)), 0.0);
  EXPECT_FALSE(form.is_step_valid(q, down));
  // A vertex exactly on a plane (d = 0) is as inadmissible as one beyond it: infinite energy.
  Eigen::VectorXd touching = q;
  int lowest = 0;
  for (int v = 1; v < mesh.num_vertices(); ++v) {
    if (q[3 * v + 2] < q[3 * lowest + 2]) lowest = v;
  }
  touching[3 * lowest + 2] = 0.0;
  EXPECT_EQ(form.value_difference(q, touching), std::numeric_limits<double>::infinity());
}

TEST(InertiaAndGravityForms, DerivativesMatchFiniteDifferences) {
  const TetMesh mesh = test::ball_mesh(0.1, 2);
  SparseHessian H(mesh.T, mesh.num_vertices());
  const Eigen::VectorXd density = Eigen::VectorXd::LinSpaced(mesh.num_tets(), 800, 11300);
  for (MassModel model : {MassModel::kConsistent, MassModel::kLumped}) {
    InertiaForm inertia(mass_matrix(mesh, density, model, H), UnitElementMass(mesh, model));
    inertia.set_predictor(test::deformed(mesh, 0.01, 3));
    const test::FdErrors e = test::check_form(inertia, test::deformed(mesh, 0.02, 4), 1e-6, H);
    EXPECT_LE(e.gradient, 1e-6);
    EXPECT_LE(e.hessian, 1e-6);
    // Row sums are the vertex masses; the total is the mass.
    const Eigen::VectorXd ones = Eigen::VectorXd::Ones(3 * mesh.num_vertices());
    const Eigen::VectorXd Mones = inertia.multiply(ones);
    const Eigen::VectorXd mv = vertex_masses(mesh, density);
    for (int v = 0; v < mesh.num_vertices(); ++v) EXPECT_NEAR(Mones[3 * v], mv[v], 1e-12 * mv[v]);
  }
  const GravityForm gravity(vertex_masses(mesh, density), Eigen::Vector3d(0, 0, -9.8),
                            UnitElementMass(mesh, MassModel::kConsistent));
  const Eigen::VectorXd q = test::deformed(mesh, 0.02, 4);
  const Eigen::VectorXd g = test::form_gradient(gravity, q);
  const Eigen::VectorXd g_fd =
      test::fd_gradient([&](const Eigen::VectorXd& x) { return gravity.value(x); }, q, 1e-6);
  EXPECT_LE(test::relative_error(g, g_fd), 1e-6);
}

TEST(BarrierStiffness, EnergyRuleGivesAbout4e7ForTheBall) {
  // SPEC: m0 = 18.25 kg, |v0| = 5.5 m/s, d_hat = 1e-3 -> about 4e7.
  const double kappa = barrier_stiffness_from_energy(18.25, 5.53, 1e-3);
  EXPECT_NEAR(kappa, 4.05e7, 0.05e7);
  // Falling from 2 m onto the floor z = 0: v = sqrt(2 g H).
  EXPECT_NEAR(barrier_design_speed(0.0, Eigen::Vector3d(0, 0, -9.8), {Plane{}}, {},
                                   Eigen::Vector3d(0, 0, 2)),
              std::sqrt(2 * 9.8 * 2), 1e-12);
  // A floor raised to z = 0.5 (offset 0.5): the fall is 1.5 m. A slope (30 deg, offset 0.2):
  // its distance along the vertical, (n . c - offset) / (n . up). A ceiling does not end a fall,
  // and a faster throw keeps its own speed.
  Plane raised;
  raised.offset = 0.5;
  EXPECT_NEAR(barrier_design_speed(0.0, Eigen::Vector3d(0, 0, -9.8), {raised}, {}, Eigen::Vector3d(0, 0, 2)),
              std::sqrt(2 * 9.8 * 1.5), 1e-12);
  Plane slope;
  slope.normal = Eigen::Vector3d(0, 0.5, std::sqrt(3.0) / 2);
  slope.offset = 0.2;
  Plane ceiling;
  ceiling.normal = -Eigen::Vector3d::UnitZ();
  ceiling.offset = -3.0;
  const double fall = (std::sqrt(3.0) - 0.2) / (std::sqrt(3.0) / 2);
  EXPECT_NEAR(barrier_design_speed(0.0, Eigen::Vector3d(0, 0, -9.8), {ceiling, slope}, {}, Eigen::Vector3d(0, 0, 2)),
              std::sqrt(2 * 9.8 * fall), 1e-12);
  EXPECT_EQ(barrier_design_speed(20.0, Eigen::Vector3d(0, 0, -9.8), {raised}, {}, Eigen::Vector3d(0, 0, 2)), 20.0);
}

}  // namespace
}  // namespace rbaa
