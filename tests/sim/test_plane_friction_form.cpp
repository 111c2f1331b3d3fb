// Lagged smoothed friction against planes: value, gradient and Hessian against central differences
// while sliding (|u| > eps) and sticking (|u| < eps); the force never exceeds Coulomb's mu lambda;
// the history terms the adjoint and the tangent use against differences of G in q_n and q_{n-1}.

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "form_checks.hpp"
#include "mesh_fixtures.hpp"
#include "rbaa/error.hpp"
#include "rbaa/mesh/topology.hpp"
#include "rbaa/sim/plane_friction_form.hpp"
#include "rbaa/sim/sparse_hessian.hpp"

namespace rbaa {
namespace {

struct Contact {
  TetMesh mesh;
  std::vector<Plane> planes;
  Eigen::VectorXd q_n, q_prev;
};

// A box resting within d_hat of a tilted plane (and, for two planes, of a wall): its bottom
// vertices are lagged pairs.
Contact box_on_planes(bool wall) {
  Contact s;
  s.mesh = test::box_mesh(2, 2, 1, 0.05);
  Plane floor;
  floor.normal = Eigen::Vector3d(0.01, 0.005, 1).normalized();
  floor.offset = -1e-3;
  floor.friction = 0.4;
  s.planes = {floor};
  if (wall) {
    Plane w;
    w.normal = Eigen::Vector3d(1, 0, 0);
    w.offset = -0.0015;
    w.friction = 0.7;
    s.planes.push_back(w);
  }
  s.q_n = test::positions(s.mesh);
  s.q_prev = s.q_n;
  for (int v = 0; v < s.mesh.num_vertices(); ++v) s.q_prev.segment<3>(3 * v) -= Eigen::Vector3d(2e-3, -1e-3, 0);
  return s;
}

PlaneFrictionForm make_form(const Contact& s, double eps_v) {
  std::vector<double> mu;
  for (const Plane& p : s.planes) mu.push_back(p.friction);
  PlaneFrictionForm f(boundary_vertices(s.mesh), s.planes, mu, 3e-3, 50.0, eps_v, Integrator::kBdf2, 1e-2);
  f.lag(s.q_n, s.q_prev);
  return f;
}

TEST(PlaneFriction, DerivativesMatchFiniteDifferencesSlidingAndSticking) {
  for (bool wall : {false, true}) {
    const Contact s = box_on_planes(wall);
    // eps = eps_v 2h/3: sliding 1e-3 m/s (eps 6.7e-6 m) against steps of ~1e-3 m; sticking 10 m/s.
    for (double eps_v : {1e-3, 10.0}) {
      PlaneFrictionForm f = make_form(s, eps_v);
      ASSERT_GE(f.num_lagged_pairs(), 4);
      SparseHessian H(s.mesh.T, s.mesh.num_vertices());
      const Eigen::VectorXd x = test::deformed(s.mesh, 1e-4, 3) +
                                (s.q_n - s.q_prev) * 1.0;  // moving on
      const test::FdErrors e = test::check_form(f, x, 1e-8, H);
      EXPECT_LT(e.gradient, 1e-6) << "wall " << wall << " eps_v " << eps_v;
      EXPECT_LT(e.hessian, 1e-5) << "wall " << wall << " eps_v " << eps_v;
      // Convex: the exact Hessian is PSD.
      const Eigen::MatrixXd Hx = test::form_hessian(f, x, HessianKind::kExact, H);
      EXPECT_GE(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Hx).eigenvalues().minCoeff(),
                -1e-12 * Hx.norm());
    }
  }
}

TEST(PlaneFriction, TheForceIsCoulombsWhileSlidingAndNeverMore) {
  const Contact s = box_on_planes(false);
  PlaneFrictionForm f = make_form(s, 1e-3);
  const contact::Barrier barrier(3e-3);
  // Sliding fast: |force| = mu lambda at every lagged vertex, opposite the tangential motion.
  const Eigen::VectorXd x = s.q_n + (s.q_n - s.q_prev);
  const Eigen::VectorXd g = test::form_gradient(f, x);
  const Eigen::Vector3d n = s.planes[0].normal;
  int checked = 0;
  for (int v = 0; v < s.mesh.num_vertices(); ++v) {
    const double d = n.dot(s.q_n.segment<3>(3 * v)) - s.planes[0].offset;
    if (!(d < 3e-3)) {
      EXPECT_EQ(g.segment<3>(3 * v).norm(), 0.0);
      continue;
    }
    const double lambda = -50.0 * barrier.first_derivative(d);
    EXPECT_NEAR(g.segment<3>(3 * v).norm(), 0.4 * lambda, 1e-12 * lambda);
    const Eigen::Vector3d step = x.segment<3>(3 * v) - s.q_n.segment<3>(3 * v);
    EXPECT_GT(g.segment<3>(3 * v).dot(step - n * n.dot(step)), 0);  // D grows along the slip
    EXPECT_NEAR(g.segment<3>(3 * v).dot(n), 0.0, 1e-15 * lambda);
    ++checked;
  }
  EXPECT_GE(checked, 4);
}

TEST(PlaneFriction, HistoryTermsMatchDifferencesOfTheStepEquation) {
  const Contact s = box_on_planes(true);
  const double w = 4.0 / 9.0 * 1e-4;
  for (double eps_v : {1e-3, 10.0}) {
    const Eigen::VectorXd x = test::deformed(s.mesh, 1e-4, 5) + 0.8 * (s.q_n - s.q_prev);
    // G_f(q_n, q_prev) = w grad D at x, lagged from (q_n, q_prev).
    auto G = [&](const Eigen::VectorXd& q_n, const Eigen::VectorXd& q_prev) {
      Contact t = s;
      t.q_n = q_n;
      t.q_prev = q_prev;
      PlaneFrictionForm f = make_form(t, eps_v);
      Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size());
      f.add_gradient(x, w, g);
      return g;
    };
    const Eigen::MatrixXd J_n = test::fd_jacobian([&](const Eigen::VectorXd& q) { return G(q, s.q_prev); }, s.q_n, 1e-9);
    const Eigen::MatrixXd J_p = test::fd_jacobian([&](const Eigen::VectorXd& q) { return G(s.q_n, q); }, s.q_prev, 1e-9);
    ASSERT_GT(J_n.norm(), 0);
    ASSERT_GT(J_p.norm(), 0);
    PlaneFrictionForm f = make_form(s, eps_v);
    // Adjoint: bar += -J^T a, for a random a.
    const Eigen::VectorXd a = Eigen::VectorXd::Random(x.size());
    Eigen::VectorXd bar_n = Eigen::VectorXd::Zero(x.size()), bar_p = bar_n;
    f.add_history_adjoint(x, a, w, bar_n, bar_p);
    EXPECT_LT((bar_n + J_n.transpose() * a).norm(), 1e-6 * (J_n.transpose() * a).norm()) << eps_v;
    EXPECT_LT((bar_p + J_p.transpose() * a).norm(), 1e-6 * (J_p.transpose() * a).norm()) << eps_v;
    // Tangent: J_n dn + J_p dp.
    const Eigen::VectorXd dn = Eigen::VectorXd::Random(x.size()), dp = Eigen::VectorXd::Random(x.size());
    const Eigen::VectorXd t = f.history_tangent(x, dn, dp, w);
    EXPECT_LT((t - J_n * dn - J_p * dp).norm(), 1e-6 * (J_n * dn + J_p * dp).norm()) << eps_v;
  }
}

TEST(PlaneFriction, BadCoefficientsAreRefused) {
  const Contact s = box_on_planes(false);
  EXPECT_THROW(PlaneFrictionForm(boundary_vertices(s.mesh), s.planes, {-0.1}, 3e-3, 1.0, 1e-3,
                                 Integrator::kBdf2, 1e-2),
               InputError);
  EXPECT_THROW(PlaneFrictionForm(boundary_vertices(s.mesh), s.planes, {0.3}, 3e-3, 1.0, 0.0,
                                 Integrator::kBdf2, 1e-2),
               InputError);
}

}  // namespace
}  // namespace rbaa
