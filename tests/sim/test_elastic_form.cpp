// The elastic form on small meshes: gradient and Hessian against finite differences at rest and
// in random deformed states for extreme materials, the projected Hessian, and a uniaxial stretch
// that must recover Y and nu.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "form_checks.hpp"
#include "mesh_fixtures.hpp"
#include "rbaa/material/lame.hpp"
#include "rbaa/sim/elastic_form.hpp"
#include "rbaa/sim/stable_neo_hookean.hpp"

namespace rbaa {
namespace {

// Alternating elements: Y = 6.5e11 with alpha = 1e-3 (a void next to a stiff neighbour) and the
// reference Y = 1e13, alpha = 1.
MaterialField extreme_field(int num_tets, double nu) {
  MaterialField f = MaterialField::uniform(num_tets, 1e13, nu, 2500.0);
  for (int e = 0; e < num_tets; e += 2) {
    f.Y[e] = 6.5e11;
    f.alpha[e] = 1e-3;
  }
  return f;
}

TEST(ElasticForm, DerivativesMatchFiniteDifferencesForExtremeMaterials) {
  const TetMesh mesh = test::ball_mesh(0.1, 2);
  SparseHessian H(mesh.T, mesh.num_vertices());
  Eigen::Matrix3d stretch;
  stretch << 1.05, 0.02, 0, -0.01, 0.97, 0.03, 0.0, 0.01, 1.02;
  for (double nu : {0.2, 0.4}) {
    const ElasticForm form(mesh, extreme_field(mesh.num_tets(), nu));
    const std::vector<Eigen::VectorXd> states = {test::positions(mesh),
                                                 test::deformed(mesh, 0.02, 1),
                                                 test::deformed(mesh, 0.05, 2, stretch)};
    for (std::size_t s = 0; s < states.size(); ++s) {
      const test::FdErrors e = test::check_form(form, states[s], 1e-6, H);
      std::printf("elastic nu=%.1f state %zu: gradient rel err %.2e, Hessian rel err %.2e\n", nu,
                  s, e.gradient, e.hessian);
      EXPECT_LE(e.gradient, 1e-6);
      EXPECT_LE(e.hessian, 1e-6);
    }
  }
}

// Frame invariance: a deformed state rotated (and translated) rigidly keeps its energy, and its
// forces rotate with it, per vertex, for the extreme alternating materials.
TEST(ElasticForm, EnergyAndForcesAreFrameInvariant) {
  const TetMesh mesh = test::ball_mesh(0.1, 2);
  Eigen::Matrix3d stretch;
  stretch << 1.05, 0.02, 0, -0.01, 0.97, 0.03, 0.0, 0.01, 1.02;
  const ElasticForm form(mesh, extreme_field(mesh.num_tets(), 0.3));
  const Eigen::VectorXd q = test::deformed(mesh, 0.03, 5, stretch);
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
  const Eigen::Vector3d t(0.4, -1.3, 3.4);
  Eigen::VectorXd q_rot(q.size());
  for (Eigen::Index v = 0; v < q.size() / 3; ++v) q_rot.segment<3>(3 * v) = R * q.segment<3>(3 * v) + t;
  const double E = form.value(q), E_rot = form.value(q_rot);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(q.size()), g_rot = Eigen::VectorXd::Zero(q.size());
  form.add_gradient(q, 1.0, g);
  form.add_gradient(q_rot, 1.0, g_rot);
  double force_error = 0;
  for (Eigen::Index v = 0; v < q.size() / 3; ++v) {
    force_error = std::max(force_error, (g_rot.segment<3>(3 * v) - R * g.segment<3>(3 * v)).norm());
  }
  std::printf("frame invariance: E %.6e, |E_rot - E| / E %.2e, max force error / |g| %.2e\n", E,
              std::abs(E_rot - E) / E, force_error / g.lpNorm<Eigen::Infinity>());
  EXPECT_GT(E, 0);
  EXPECT_NEAR(E_rot, E, 1e-10 * E);
  EXPECT_LE(force_error, 1e-9 * g.lpNorm<Eigen::Infinity>());
}

TEST(ElasticForm, EverySingleElementMaterialPassesOnItsOwn) {
  // One tet per material, so that a soft element's error cannot hide under a stiff one's.
  TetMesh tet;
  tet.V.resize(4, 3);
  tet.V << 0, 0, 0, 0.02, 0, 0, 0.003, 0.018, 0, 0.004, 0.005, 0.021;
  tet.T.resize(1, 4);
  tet.T << 0, 1, 2, 3;
  SparseHessian H(tet.T, 4);
  for (double Y : {2.5e9, 6.5e11, 1e13}) {
    for (double nu : {0.2, 0.4}) {
      for (double alpha : {1e-3, 1.0}) {
        const ElasticForm form(tet, MaterialField::uniform(1, Y, nu, 2500.0, alpha));
        for (unsigned seed : {1u, 2u, 3u}) {
          const test::FdErrors e = test::check_form(form, test::deformed(tet, 0.03, seed), 1e-7, H);
          EXPECT_LE(e.gradient, 1e-6) << Y << " " << nu << " " << alpha;
          EXPECT_LE(e.hessian, 1e-6) << Y << " " << nu << " " << alpha;
        }
      }
    }
  }
}

TEST(ElasticForm, ValueDifferenceMatchesValues) {
  const TetMesh mesh = test::ball_mesh(0.1, 2);
  const ElasticForm form(mesh, extreme_field(mesh.num_tets(), 0.3));
  const Eigen::VectorXd q0 = test::deformed(mesh, 0.03, 4), q1 = test::deformed(mesh, 0.03, 5);
  const double d = form.value_difference(q0, q1);
  EXPECT_NEAR(d, form.value(q1) - form.value(q0), 1e-12 * form.value(q1));
}

TEST(ElasticForm, ProjectedHessianIsPsdAndExactWhereExactIsPsd) {
  const TetMesh mesh = test::ball_mesh(0.1, 2);
  SparseHessian H(mesh.T, mesh.num_vertices());
  const ElasticForm form(mesh, MaterialField::uniform(mesh.num_tets(), 1e9, 0.3, 1000.0));
  const Eigen::VectorXd q = test::deformed(mesh, 0.0, 0, 0.95 * Eigen::Matrix3d::Identity());
  const Eigen::MatrixXd Hp = test::form_hessian(form, q, HessianKind::kProjected, H);
  const Eigen::MatrixXd Hx = test::form_hessian(form, q, HessianKind::kExact, H);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> ep(Hp), ex(Hx);
  EXPECT_LT(ex.eigenvalues().minCoeff(), -1e-6 * Hx.norm());  // compression: indefinite
  EXPECT_GT(ep.eigenvalues().minCoeff(), -1e-12 * Hp.norm());
  // At a stretched state every element Hessian is PSD... up to the rotation modes (zero).
  const Eigen::VectorXd q2 = test::deformed(mesh, 0.0, 0, 1.01 * Eigen::Matrix3d::Identity());
  const Eigen::MatrixXd Hp2 = test::form_hessian(form, q2, HessianKind::kProjected, H);
  const Eigen::MatrixXd Hx2 = test::form_hessian(form, q2, HessianKind::kExact, H);
  EXPECT_LT((Hp2 - Hx2).norm(), 1e-12 * Hx2.norm());
}

// The exact Hessian is assembled in closed form per vertex pair (elastic_form.cpp,
// add_exact_block): it must be D^T H9 D with H9 the 9x9 Hessian in F (snh::hessian) and D = dF/dx,
// to round-off, at compressed, stretched, sheared and inverted states and a near-incompressible
// material, where finite differences would only check it to 1e-6.
TEST(ElasticForm, ExactHessianIsThePulledBackHessianInF) {
  const TetMesh mesh = test::tet({0.1, -0.2, 0.05}, {1.3, 0.1, -0.1}, {0.2, 0.9, 0.3}, {-0.1, 0.3, 1.1});
  const double Y = 3e9, nu = 0.45, alpha = 0.7;
  MaterialField field = MaterialField::uniform(1, Y, nu, 2500.0);
  field.alpha[0] = alpha;
  const ElasticForm form(mesh, field);
  const LameParameters lame = lame_from_young_poisson(Y, nu);
  const Eigen::Matrix3d rest_edges =
      (Eigen::Matrix3d() << (mesh.V.row(1) - mesh.V.row(0)).transpose(),
       (mesh.V.row(2) - mesh.V.row(0)).transpose(), (mesh.V.row(3) - mesh.V.row(0)).transpose())
          .finished();
  const double weight = alpha * alpha * alpha * std::abs(rest_edges.determinant()) / 6.0;
  SparseHessian H(mesh.T, mesh.num_vertices());
  Eigen::Matrix3d inverting = Eigen::Matrix3d::Identity();
  inverting(2, 2) = -0.3;
  const Eigen::Matrix3d shear = (Eigen::Matrix3d() << 1, 0.8, 0, 0, 1, 0.2, 0.1, 0, 1).finished();
  unsigned seed = 0;
  for (const Eigen::Matrix3d& A : {Eigen::Matrix3d(0.6 * Eigen::Matrix3d::Identity()),
                                   Eigen::Matrix3d(1.7 * Eigen::Matrix3d::Identity()), shear, inverting}) {
    const Eigen::VectorXd q = test::deformed(mesh, 0.05, ++seed, A);
    // F is linear in q: its columns of D are exact differences.
    Eigen::Matrix<double, 9, 12> D;
    const Eigen::Matrix3d F = form.deformation_gradient(q, 0);
    for (int j = 0; j < 12; ++j) {
      Eigen::VectorXd qj = q;
      qj[j] += 1.0;
      const Eigen::Matrix3d dF = form.deformation_gradient(qj, 0) - F;
      D.col(j) = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(dF.data());
    }
    const Eigen::MatrixXd expected =
        weight * D.transpose() * snh::hessian(F, lame.mu, lame.lambda) * D;
    const Eigen::MatrixXd Hx = test::form_hessian(form, q, HessianKind::kExact, H);
    EXPECT_LT((Hx - expected).norm(), 1e-13 * expected.norm()) << "F =\n" << F;
  }
}

// Uniaxial stretch of a block: impose x -> (1 + eps) x, let the lateral strain delta relax
// (the homogeneous state is an equilibrium of the free block), then Y = P_xx / eps and
// nu = -delta / eps to O(eps).
TEST(ElasticForm, UniaxialStretchRecoversYoungAndPoisson) {
  const TetMesh mesh = test::box_mesh(3, 2, 2, 0.05);
  const Eigen::VectorXd X = test::positions(mesh);
  const double volume = 0.15 * 0.1 * 0.1;
  const double eps = 1e-5;
  for (double Y : {2.5e9, 1e13}) {
    for (double nu : {0.2, 0.28, 0.4}) {
      const ElasticForm form(mesh, MaterialField::uniform(mesh.num_tets(), Y, nu, 2500.0));
      auto state = [&](double delta) {
        Eigen::VectorXd q = X;
        for (int v = 0; v < mesh.num_vertices(); ++v) {
          q[3 * v] *= 1 + eps;
          q[3 * v + 1] *= 1 + delta;
          q[3 * v + 2] *= 1 + delta;
        }
        return q;
      };
      // dE/d delta = sum_v g_v . (0, y_v, z_v): zero at the relaxed lateral strain (linear in delta
      // to O(eps), so a secant iteration converges in a few steps).
      auto lateral = [&](double delta) {
        const Eigen::VectorXd g = test::form_gradient(form, state(delta));
        double s = 0;
        for (int v = 0; v < mesh.num_vertices(); ++v) s += g[3 * v + 1] * X[3 * v + 1] + g[3 * v + 2] * X[3 * v + 2];
        return s;
      };
      double d0 = 0, d1 = -0.3 * eps, f0 = lateral(d0), f1 = lateral(d1);
      for (int it = 0; it < 20 && f1 != f0; ++it) {
        const double d2 = d1 - f1 * (d1 - d0) / (f1 - f0);
        d0 = d1;
        f0 = f1;
        d1 = d2;
        f1 = lateral(d1);
      }
      const Eigen::VectorXd g = test::form_gradient(form, state(d1));
      double dE_deps = 0;  // = V P_xx
      for (int v = 0; v < mesh.num_vertices(); ++v) dE_deps += g[3 * v] * X[3 * v];
      const double Y_measured = dE_deps / volume / eps;
      const double nu_measured = -d1 / eps;
      std::printf("uniaxial Y=%.3g nu=%.2f: Y rel err %.2e, nu rel err %.2e\n", Y, nu,
                  Y_measured / Y - 1, nu_measured / nu - 1);
      EXPECT_NEAR(Y_measured / Y, 1.0, 1e-3);
      EXPECT_NEAR(nu_measured / nu, 1.0, 1e-3);
    }
  }
}

TEST(ElasticForm, ParameterSplitIsLinearInMuAndLambda) {
  const TetMesh mesh = test::ball_mesh(0.1, 2);
  const MaterialField field = extreme_field(mesh.num_tets(), 0.3);
  const ElasticForm form(mesh, field);
  const Eigen::VectorXd q = test::deformed(mesh, 0.03, 9);
  const Eigen::VectorXd g = test::form_gradient(form, q);
  Eigen::VectorXd g_sum = Eigen::VectorXd::Zero(q.size());
  for (int e = 0; e < mesh.num_tets(); ++e) {
    Eigen::Matrix<double, 12, 1> gm, gl;
    form.element_gradient_parts(q, e, gm, gl);
    for (int a = 0; a < 4; ++a) {
      g_sum.segment<3>(3 * mesh.T(e, a)) +=
          form.mu(e) * gm.segment<3>(3 * a) + form.lambda(e) * gl.segment<3>(3 * a);
    }
  }
  EXPECT_LT((g - g_sum).norm(), 1e-12 * g.norm());
}

// Elastic forces are internal: their sum and their torque vanish. On a Y = 1e13 ball moved
// rigidly far from the origin (3.4 m, as the ball's scene), the forces are round-off only (F = R
// to ~1e-14), a random field. Its sum cancels already (each element's b_0 = -(b_1 + b_2 + b_3)),
// but its torque was 1.8e-5 of sum |r||f| (measured with the removal disabled), and only the mass
// resists it in Newton's step: the rotational drift that set the ball's round-off floor. The form
// removes the net force and torque, leaving round-off of round-off (~1e-17).
TEST(ElasticForm, ForcesHaveNoNetForceOrTorque) {
  const TetMesh mesh = test::ball_mesh(0.121, 5);
  const ElasticForm form(mesh, MaterialField::uniform(mesh.num_tets(), 1e13, 0.28, 2500.0));
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.9, Eigen::Vector3d(0.2, 0.7, -0.4).normalized()).toRotationMatrix();
  const Eigen::Vector3d t(0.34, -0.23, 3.45);
  for (double strain : {0.0, 1e-6}) {
    Eigen::VectorXd q = test::deformed(mesh, strain, 7);
    for (Eigen::Index v = 0; v < q.size() / 3; ++v) q.segment<3>(3 * v) = R * q.segment<3>(3 * v) + t;
    Eigen::VectorXd g = Eigen::VectorXd::Zero(q.size());
    form.add_gradient(q, 1.0, g);
    Eigen::Vector3d c = Eigen::Vector3d::Zero(), net = Eigen::Vector3d::Zero(), torque = Eigen::Vector3d::Zero();
    const Eigen::Index nv = q.size() / 3;
    for (Eigen::Index v = 0; v < nv; ++v) c += q.segment<3>(3 * v) / double(nv);
    double size = 0, moment = 0;
    for (Eigen::Index v = 0; v < nv; ++v) {
      const Eigen::Vector3d r = q.segment<3>(3 * v) - c, f = g.segment<3>(3 * v);
      net += f;
      torque += r.cross(f);
      size += f.norm();
      moment += r.norm() * f.norm();
    }
    std::printf("strain %.0e: sum |f_i| %.3e N, |net force| / sum %.2e, |net torque| / sum |r||f| %.2e\n",
                strain, size, net.norm() / size, torque.norm() / moment);
    EXPECT_GT(size, 0.0);  // round-off forces exist even at rest
    EXPECT_LE(net.norm(), 1e-12 * size);
    EXPECT_LE(torque.norm(), 1e-12 * moment);
  }
}

}  // namespace
}  // namespace rbaa
