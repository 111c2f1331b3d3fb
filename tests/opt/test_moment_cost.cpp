#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "rbaa/geometry/moments.hpp"
#include "rbaa/material/design_space.hpp"
#include "rbaa/mesh/grid_mesh.hpp"
#include "rbaa/opt/moment_cost.hpp"

namespace rbaa {
namespace {

// Off the origin so that m1 and the off-diagonal m2 are not zero.
TetMesh test_mesh() { return box_tet_mesh({0.3, -0.2, 0.5}, {1.1, 0.4, 1.4}, 3, 3, 4); }

Eigen::MatrixXd fd_jacobian(const MomentCostFunction& cost, const Eigen::VectorXd& theta,
                            double eps) {
  Eigen::MatrixXd J(10, theta.size());
  for (Eigen::Index i = 0; i < theta.size(); ++i) {
    Eigen::VectorXd tp = theta, tm = theta;
    tp[i] += eps;
    tm[i] -= eps;
    J.col(i) = (cost.residuals(tp) - cost.residuals(tm)) / (2 * eps);
  }
  return J;
}

TEST(MomentCost, ZeroAtTheMatchedStartAndNormalisedPerRow) {
  const TetMesh mesh = test_mesh();
  const Moments reference = compute_moments(mesh, 2500.0);
  const DesignSpace design(mesh, DesignSpaceOptions{});
  const MomentCostFunction cost(mesh, design, reference);
  EXPECT_EQ(cost.num_residuals(), 10);
  ASSERT_EQ(cost.parameter_block_sizes().size(), 1u);
  EXPECT_EQ(cost.parameter_block_sizes()[0], design.size());

  const Eigen::VectorXd theta0 = design.initial_theta(false);
  EXPECT_LT(cost.residuals(theta0).cwiseAbs().maxCoeff(), 1e-12);

  // Adding mass dm at one element's centroid c moves the residuals by dm (1, c, ...) / scale.
  const MaterialField m = design.to_material(theta0);
  const int e = design.interior()[0];
  MaterialField heavier = m;
  heavier.rho[e] *= 1.5;
  Eigen::VectorXd theta1 = theta0;
  theta1[design.offset(DesignField::kRho) + e] =
      design.map(DesignField::kRho).inverse(heavier.rho[e]);
  const MomentVector r = cost.residuals(theta1);
  const double dm = 0.5 * m.rho[e] * m.alpha[e] * tet_volumes(mesh)[e];
  const double L = radius_of_gyration(reference);
  EXPECT_NEAR(r[0], dm / reference.m0, 1e-12);
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int k = 0; k < 4; ++k) c += mesh.V.row(mesh.T(e, k)).transpose() / 4;
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(r[1 + a], dm * c[a] / (reference.m0 * L), 1e-11);
  EXPECT_GT(std::abs(r[0]), 1e-4);
}

TEST(MomentCost, JacobianMatchesCentralDifferences) {
  const TetMesh mesh = test_mesh();
  const Moments reference = compute_moments(mesh, 2500.0);
  for (const auto& fields : std::vector<std::vector<DesignField>>{
           {DesignField::kY, DesignField::kNu, DesignField::kRho, DesignField::kAlpha},
           {DesignField::kRho},
           {DesignField::kAlpha},
           {DesignField::kNu, DesignField::kRho}}) {
    DesignSpaceOptions o;
    o.fields = fields;
    o.perturbation = 0.5;
    o.seed = 4;
    const DesignSpace design(mesh, o);
    const MomentCostFunction cost(mesh, design, reference);
    const Eigen::VectorXd theta = design.initial_theta();
    ASSERT_GT(cost.residuals(theta).norm(), 1e-3);  // away from the matched point

    const Eigen::MatrixXd J = cost.jacobian(theta);
    // Step: the residuals carry round-off ~1e-16 (sums of #T terms of size ~1), while the alpha
    // columns are ~1e-4 (one element's share times alpha' ~ 0.02 near alpha = 0.99); eps = 1e-4
    // keeps round-off (1e-12 / 1e-4) and truncation (eps^2 tanh''' / 6) both near 1e-8 relative.
    const Eigen::MatrixXd Jfd = fd_jacobian(cost, theta, 1e-4);
    std::string label;
    for (DesignField f : fields) label += std::string(design_field_name(f)) + " ";
    for (DesignField f : fields) {
      const auto a = J.middleCols(design.offset(f), design.block_size(f));
      const auto n = Jfd.middleCols(design.offset(f), design.block_size(f));
      if (f == DesignField::kY || f == DesignField::kNu) {
        EXPECT_EQ(a.norm(), 0.0);
        EXPECT_EQ(n.norm(), 0.0);
        continue;
      }
      const double err = (a - n).norm() / n.norm();
      std::printf("moment Jacobian, fields {%s}, block %s: relative error %.2e (|J| %.3g)\n",
                  label.c_str(), design_field_name(f), err, n.norm());
      EXPECT_LT(err, 1e-7);
    }

    // The penalty beta |r|^2 and its gradient 2 beta J^T r, in a random direction.
    const double beta = 1e4;
    Eigen::VectorXd grad;
    cost.penalty(theta, beta, &grad);
    const Eigen::VectorXd dir = Eigen::VectorXd::LinSpaced(theta.size(), -1, 1).array().sin();
    const double eps = 1e-6;
    const double fd = (cost.penalty(theta + eps * dir, beta, nullptr) -
                       cost.penalty(theta - eps * dir, beta, nullptr)) / (2 * eps);
    const double err = std::abs(grad.dot(dir) - fd) / std::abs(fd);
    std::printf("moment penalty, fields {%s}: directional derivative relative error %.2e\n",
                label.c_str(), err);
    EXPECT_LT(err, 1e-7);
  }
}

TEST(MomentCost, CeresInterfaceWithoutJacobian) {
  const TetMesh mesh = test_mesh();
  const Moments reference = compute_moments(mesh, 2500.0);
  const DesignSpace design(mesh, DesignSpaceOptions{});
  const MomentCostFunction cost(mesh, design, reference);
  const ceres::CostFunction& base = cost;
  const Eigen::VectorXd theta = design.initial_theta();
  MomentVector r;
  const double* p[1] = {theta.data()};
  double* no_block[1] = {nullptr};
  ASSERT_TRUE(base.Evaluate(p, r.data(), nullptr));
  // Against an independent evaluation of the moments of the mapped material.
  const MomentVector expected =
      (compute_moments(mesh, design.to_material(theta).effective_density()).as_vector() -
       reference.as_vector())
          .cwiseQuotient(moment_normalisation(reference));
  EXPECT_LT((r - expected).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_GT(r.cwiseAbs().maxCoeff(), 1e-3);
  ASSERT_TRUE(base.Evaluate(p, r.data(), no_block));
  EXPECT_EQ(r, cost.residuals(theta));
}

// With an element mask (two bodies stacked in one mesh, the design on the second), the moments
// are the designed body's alone: the same residuals and Jacobian as the body's own design space
// on its own mesh, zero at the matched start although the other body is heavy and far away.
TEST(MomentCost, AMaskedDesignMatchesOnlyTheDesignedBodysMoments) {
  const TetMesh body = test_mesh();
  const TetMesh other = box_tet_mesh({2.0, 0.0, 0.0}, {2.5, 0.5, 0.5}, 2, 2, 2);
  TetMesh world;
  world.V.resize(other.num_vertices() + body.num_vertices(), 3);
  world.V << other.V, body.V;
  world.T.resize(other.num_tets() + body.num_tets(), 4);
  world.T << other.T, (body.T.array() + other.num_vertices()).matrix();
  std::vector<char> mask(world.num_tets(), 0);
  std::fill(mask.begin() + other.num_tets(), mask.end(), 1);
  MaterialField fixed = MaterialField::uniform(world.num_tets(), 1e10, 0.3, 9000, 1.0);

  const Moments reference = compute_moments(body, 2500.0);
  DesignSpaceOptions o;
  o.perturbation = 0.5;
  o.seed = 4;
  DesignSpace masked(world, o, mask);
  masked.hold_fixed_elements(fixed);
  const DesignSpace own(body, o);
  const MomentCostFunction world_cost(world, masked, reference);
  const MomentCostFunction own_cost(body, own, reference);
  EXPECT_LT(world_cost.residuals(masked.initial_theta(false)).cwiseAbs().maxCoeff(), 1e-12);

  const Eigen::VectorXd theta = masked.initial_theta();
  ASSERT_GT(world_cost.residuals(theta).norm(), 1e-3);
  EXPECT_LT((world_cost.residuals(theta) - own_cost.residuals(theta)).cwiseAbs().maxCoeff(), 1e-13);
  const Eigen::MatrixXd J = world_cost.jacobian(theta);
  EXPECT_LT((J - own_cost.jacobian(theta)).cwiseAbs().maxCoeff(), 1e-13 * J.cwiseAbs().maxCoeff());
  const Eigen::MatrixXd Jfd = fd_jacobian(world_cost, theta, 1e-4);
  for (DesignField f : {DesignField::kRho, DesignField::kAlpha}) {
    const auto a = J.middleCols(masked.offset(f), masked.block_size(f));
    const auto n = Jfd.middleCols(masked.offset(f), masked.block_size(f));
    const double err = (a - n).norm() / n.norm();
    std::printf("masked moment Jacobian, block %s: relative error %.2e\n", design_field_name(f),
                err);
    EXPECT_LT(err, 1e-7);
  }
}

}  // namespace
}  // namespace rbaa
