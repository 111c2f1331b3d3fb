// The barrier, the vertex-plane pair and the contact form: derivatives against finite
// differences, CCD, and the energy-rule kappa.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include "form_checks.hpp"
#include "mesh_fixtures.hpp"
#include "rbaa/mesh/topology.hpp"
#include "rbaa/sim/barrier.hpp"
#include "rbaa/sim/barrier_stiffness.hpp"
#include "rbaa/sim/contact_form.hpp"
#include "rbaa/sim/gravity_form.hpp"
#include "rbaa/sim/inertia_form.hpp"
#include "rbaa/sim/mass_matrix.hpp"
#include "rbaa/sim/vertex_plane.hpp"

namespace rbaa {
namespace {

// C2 at d_hat: with delta = d_hat - d, b ~ delta^3 / d_hat, b' ~ -3 delta^2 / d_hat and
// b'' ~ 6 delta / d_hat all vanish as d -> d_hat from below (so a pair entering the active set
// adds no jump to the energy, the forces or the Hessian), and all three are 0 at and beyond d_hat.
TEST(Barrier, TwiceContinuousAtDHat) {
  const double d_hat = 1e-3;
  const Barrier b(d_hat);
  for (double rel : {1e-2, 1e-3, 1e-4}) {
    const double delta = rel * d_hat, d = d_hat - delta;
    EXPECT_NEAR(b.value(d) / (std::pow(delta, 3) / d_hat), 1.0, 2 * rel) << rel;
    EXPECT_NEAR(b.first_derivative(d) / (-3 * delta * delta / d_hat), 1.0, 2 * rel) << rel;
    EXPECT_NEAR(b.second_derivative(d) / (6 * delta / d_hat), 1.0, 2 * rel) << rel;
  }
  for (double d : {d_hat, 1.5 * d_hat, 10 * d_hat}) {
    EXPECT_EQ(b.value(d), 0.0) << d;
    EXPECT_EQ(b.first_derivative(d), 0.0) << d;
    EXPECT_EQ(b.second_derivative(d), 0.0) << d;
  }
}

TEST(Barrier, DerivativesMatchFiniteDifferences) {
  const Barrier b(1e-3);
  for (double d : {1e-7, 1e-6, 1e-5, 1e-4, 5e-4, 9.9e-4}) {
    const double eps = 1e-4 * std::min(d, 1e-3 - d);
    const double fd1 = (b.value(d + eps) - b.value(d - eps)) / (2 * eps);
    const double fd2 = (b.first_derivative(d + eps) - b.first_derivative(d - eps)) / (2 * eps);
    EXPECT_NEAR(b.first_derivative(d), fd1, 1e-6 * std::abs(fd1)) << d;
    EXPECT_NEAR(b.second_derivative(d), fd2, 1e-6 * std::abs(fd2)) << d;
    EXPECT_GT(b.second_derivative(d), 0);
  }
  // The difference keeps its digits where subtracting values would not.
  for (double d : {1e-6, 4.6e-4, 9e-4}) {
    for (double delta : {1e-5 * d, -1e-5 * d}) {
      EXPECT_NEAR(b.difference(d, delta), b.value(d + delta) - b.value(d), 1e-9 * std::abs(b.value(d + delta) - b.value(d)));
    }
    const double tiny = 1e-9 * d;  // first order: b'(d) delta, second order 1e-18 relative
    EXPECT_NEAR(b.difference(d, tiny), b.first_derivative(d) * tiny, 1e-8 * std::abs(b.first_derivative(d) * tiny));
  }
  // C2 at d_hat, infinite at contact.
  EXPECT_EQ(b.value(1e-3), 0.0);
  EXPECT_NEAR(b.first_derivative(1e-3 * (1 - 1e-9)), 0.0, 1e-15);
  EXPECT_TRUE(std::isinf(b.value(0.0)));
}

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
}

}  // namespace
}  // namespace rbaa
