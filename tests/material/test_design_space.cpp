#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "rbaa/error.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/material/design_space.hpp"
#include "rbaa/material/tanh_box_map.hpp"
#include "rbaa/mesh/grid_mesh.hpp"
#include "rbaa/mesh/topology.hpp"
#include "rbaa/scene/scene.hpp"
#include "rbaa/scene/scene_world.hpp"

namespace rbaa {
namespace {

TetMesh test_mesh() { return box_tet_mesh({0.3, -0.2, 0.5}, {1.1, 0.4, 1.4}, 4, 3, 4); }

TEST(TanhBoxMap, ValueDerivativeInverse) {
  const TanhBoxMap map(800.0, 11300.0, "density range");
  EXPECT_DOUBLE_EQ(map.value(0.0), 6050.0);
  double worst = 0.0;
  for (double theta : {-3.0, -1.2, -0.3, 0.0, 0.4, 1.7, 2.9}) {
    const double x = map.value(theta);
    EXPECT_GT(x, 800.0);
    EXPECT_LT(x, 11300.0);
    EXPECT_NEAR(map.inverse(x), theta, 1e-12 * (1 + std::abs(theta)) * std::cosh(theta) * std::cosh(theta));
    const double eps = 1e-5;
    const double fd = (map.value(theta + eps) - map.value(theta - eps)) / (2 * eps);
    worst = std::max(worst, std::abs(fd - map.derivative(theta)) / map.derivative(theta));
  }
  std::printf("tanh map: max relative error of dx/dtheta against central differences %.2e\n", worst);
  EXPECT_LT(worst, 1e-8);
  // Deep in saturation dx/dtheta = (hi - lo) / (2 cosh^2) = 2 (hi - lo) e^(-2 |theta|) (1 + O(e^-34))
  // at |theta| = 17; 1 - tanh^2 there has lost all but two or three digits (4e-3 off).
  for (double theta : {-17.0, 17.0}) {
    EXPECT_NEAR(map.derivative(theta) / (2 * (11300.0 - 800.0) * std::exp(-34.0)), 1.0, 1e-13)
        << theta;
  }
  EXPECT_THROW(map.inverse(800.0), InputError);
  EXPECT_THROW(map.inverse(11300.0), InputError);
  EXPECT_THROW(map.inverse(std::nan("")), InputError);
  EXPECT_THROW(TanhBoxMap(1.0, 1.0, "empty"), InputError);
}

TEST(DesignSpace, LayoutFollowsFieldsAndBoundary) {
  const TetMesh mesh = test_mesh();
  const int nt = mesh.num_tets();
  const std::vector<char> boundary = boundary_elements(mesh, false);
  const int interior = nt - static_cast<int>(std::count(boundary.begin(), boundary.end(), 1));
  ASSERT_GT(interior, 0);

  const DesignSpace all(mesh, DesignSpaceOptions{});
  EXPECT_EQ(all.size(), 3 * nt + interior);
  EXPECT_EQ(all.offset(DesignField::kY), 0);
  EXPECT_EQ(all.offset(DesignField::kNu), nt);
  EXPECT_EQ(all.offset(DesignField::kRho), 2 * nt);
  EXPECT_EQ(all.offset(DesignField::kAlpha), 3 * nt);
  EXPECT_EQ(all.num_interior(), interior);
  for (int e : all.interior()) EXPECT_FALSE(boundary[e]);

  // Field order in the options does not change the layout.
  DesignSpaceOptions o;
  o.fields = {DesignField::kAlpha, DesignField::kNu};
  const DesignSpace two(mesh, o);
  EXPECT_EQ(two.size(), nt + interior);
  EXPECT_EQ(two.offset(DesignField::kNu), 0);
  EXPECT_EQ(two.offset(DesignField::kAlpha), nt);
  EXPECT_FALSE(two.optimises(DesignField::kY));
  EXPECT_EQ(two.offset(DesignField::kY), -1);

  // Boundary by vertex fixes more elements.
  DesignSpaceOptions v;
  v.boundary_by_vertex = true;
  const DesignSpace by_vertex(mesh, v);
  EXPECT_LT(by_vertex.num_interior(), interior);
}

TEST(DesignSpace, InitialMaterialMatchesTheReferenceMoments) {
  const TetMesh mesh = test_mesh();
  DesignSpaceOptions o;
  const DesignSpace design(mesh, o);
  const MaterialField& m0 = design.initial_material();
  for (int e = 0; e < mesh.num_tets(); ++e) {
    EXPECT_EQ(m0.alpha[e], design.boundary()[e] ? 1.0 : 0.99);
    EXPECT_NEAR(m0.rho[e] * m0.alpha[e], 2500.0, 1e-12 * 2500.0);
    EXPECT_DOUBLE_EQ(m0.Y[e], 0.5 * (2.5e9 + 6.5e11));
    EXPECT_DOUBLE_EQ(m0.nu[e], 0.3);
  }
  // The unperturbed theta maps back to it, and its moments are the reference's.
  const MaterialField back = design.to_material(design.initial_theta(false));
  EXPECT_LT((back.rho - m0.rho).cwiseAbs().maxCoeff(), 1e-12 * 2500);
  EXPECT_LT((back.alpha - m0.alpha).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((back.Y - m0.Y).cwiseAbs().maxCoeff(), 1e-12 * 6.5e11);
  const MomentVector scale = moment_normalisation(compute_moments(mesh, 2500.0));
  const MomentVector r = (compute_moments(mesh, back.effective_density()).as_vector() -
                          compute_moments(mesh, 2500.0).as_vector())
                             .cwiseQuotient(scale);
  EXPECT_LT(r.cwiseAbs().maxCoeff(), 1e-12);

  // Without alpha (the star): alpha = 1 and rho = 2500 everywhere.
  o.fields = {DesignField::kY, DesignField::kNu, DesignField::kRho};
  const DesignSpace star(mesh, o);
  EXPECT_EQ(star.size(), 3 * mesh.num_tets());
  const MaterialField ms = star.to_material(star.initial_theta(true));
  EXPECT_EQ(ms.alpha.minCoeff(), 1.0);
  EXPECT_EQ(star.initial_material().rho.maxCoeff(), 2500.0);
  EXPECT_EQ(star.initial_material().rho.minCoeff(), 2500.0);
}

TEST(DesignSpace, FixedFieldsKeepTheirInitialValues) {
  const TetMesh mesh = test_mesh();
  DesignSpaceOptions o;
  o.fields = {DesignField::kNu};
  o.Y0 = 1e10;
  const DesignSpace design(mesh, o);
  Eigen::VectorXd theta = design.initial_theta(true);
  theta.array() += 0.7;
  const MaterialField m = design.to_material(theta);
  EXPECT_EQ(m.Y.minCoeff(), 1e10);
  EXPECT_EQ(m.Y.maxCoeff(), 1e10);
  EXPECT_EQ(m.rho.minCoeff(), 2500.0);
  EXPECT_EQ(m.alpha.minCoeff(), 1.0);
  EXPECT_GT(m.nu.minCoeff(), 0.3);
}

TEST(DesignSpace, PerturbationIsSeededAndReproducible) {
  const TetMesh mesh = test_mesh();
  DesignSpaceOptions o;
  o.seed = 7;
  const DesignSpace a(mesh, o), b(mesh, o);
  const Eigen::VectorXd ta = a.initial_theta(), tb = b.initial_theta();
  EXPECT_EQ(ta, tb);
  o.seed = 8;
  const DesignSpace c(mesh, o);
  EXPECT_GT((c.initial_theta() - ta).norm(), 1.0);

  const Eigen::VectorXd d = ta - a.initial_theta(false);
  const double mean = d.mean();
  const double sd = std::sqrt((d.array() - mean).square().sum() / (d.size() - 1));
  std::printf("perturbation of %d entries: mean %.4f, standard deviation %.4f (asked 0.1)\n",
              static_cast<int>(d.size()), mean, sd);
  // n ~ 1400: the sample standard deviation is within 3 % of 0.1 and the mean within 0.01 with
  // overwhelming probability; a wrong transform (uniform, or std 1) is far outside.
  EXPECT_NEAR(sd, 0.1, 0.005);
  EXPECT_NEAR(mean, 0.0, 0.01);
  // The same draws on every platform and run: the first values of the Box-Muller stream of
  // std::mt19937_64(7), pinned.
  std::printf("first perturbations (seed 7): %.17g %.17g %.17g\n", d[0], d[1], d[2]);
  // theta_0 is exactly representable around these (the Y block's mid-range theta is 0).
  EXPECT_NEAR(d[0], 0.071302983388758095, 1e-15);
  EXPECT_NEAR(d[1], -0.023514359878547865, 1e-15);
  EXPECT_NEAR(d[2], 0.16105563141402485, 1e-15);
  // And recomputed here from the generator (Box-Muller on the top 53 bits of two raw
  // mt19937_64(7) draws, cosine then sine), for the first 200 entries.
  std::mt19937_64 engine(7);
  for (int i = 0; i < 200; i += 2) {
    const double u1 = (static_cast<double>(engine() >> 11) + 1.0) * 0x1.0p-53;
    const double u2 = static_cast<double>(engine() >> 11) * 0x1.0p-53;
    const double r = std::sqrt(-2.0 * std::log(u1)), angle = 2.0 * M_PI * u2;
    EXPECT_NEAR(d[i], 0.1 * r * std::cos(angle), 1e-15) << i;
    EXPECT_NEAR(d[i + 1], 0.1 * r * std::sin(angle), 1e-15) << i + 1;
  }
}

TEST(DesignSpace, ChainRuleMatchesFiniteDifferences) {
  const TetMesh mesh = test_mesh();
  const int nt = mesh.num_tets();
  DesignSpaceOptions o;
  o.seed = 3;
  o.perturbation = 0.5;
  const DesignSpace design(mesh, o);
  const Eigen::VectorXd theta = design.initial_theta();

  // A nonlinear objective of the material, with its material-space gradient.
  Eigen::VectorXd w = Eigen::VectorXd::LinSpaced(nt, -1.0, 2.0);
  auto C = [&](const MaterialField& m) {
    double c = 0.0;
    for (int e = 0; e < nt; ++e) {
      c += w[e] * (m.Y[e] / 1e11) * (m.Y[e] / 1e11) + std::sin(3 * m.nu[e] + w[e]) +
           std::sqrt(m.rho[e]) * 0.01 + w[e] * m.alpha[e] * m.alpha[e] * m.alpha[e];
    }
    return c;
  };
  const MaterialField m = design.to_material(theta);
  MaterialGradient g;
  g.Y = (2 * w.array() * m.Y.array() / 1e22).matrix();
  g.nu = (3 * (3 * m.nu.array() + w.array()).cos()).matrix();
  g.rho = (0.005 / m.rho.array().sqrt()).matrix();
  g.alpha = (3 * w.array() * m.alpha.array().square()).matrix();
  const Eigen::VectorXd analytic = design.chain_gradient(theta, g);

  // |C| ~ 300 sums #T terms, so its round-off (~1e-13) over 2 eps must stay below the bar: with
  // eps = 1e-4 round-off and truncation (eps^2 C''' / 6) are both ~1e-9 of the gradient.
  const double eps = 1e-4;
  Eigen::VectorXd fd(design.size());
  for (int i = 0; i < design.size(); ++i) {
    Eigen::VectorXd tp = theta, tm = theta;
    tp[i] += eps;
    tm[i] -= eps;
    fd[i] = (C(design.to_material(tp)) - C(design.to_material(tm))) / (2 * eps);
  }
  for (DesignField f : {DesignField::kY, DesignField::kNu, DesignField::kRho, DesignField::kAlpha}) {
    const auto a = analytic.segment(design.offset(f), design.block_size(f));
    const auto n = fd.segment(design.offset(f), design.block_size(f));
    const double err = (a - n).norm() / n.norm();
    std::printf("chain rule, field %-5s: relative error against central differences %.2e\n",
                design_field_name(f), err);
    EXPECT_LT(err, 1e-7) << design_field_name(f);
  }
  // The boundary elements' alpha gradient is dropped, not folded in anywhere.
  MaterialGradient only_boundary;
  only_boundary.alpha = Eigen::VectorXd::Zero(nt);
  for (int e = 0; e < nt; ++e) {
    if (design.boundary()[e]) only_boundary.alpha[e] = 1.0;
  }
  EXPECT_EQ(design.chain_gradient(theta, only_boundary).norm(), 0.0);
}

TEST(DesignSpace, RejectsBadOptions) {
  const TetMesh mesh = test_mesh();
  DesignSpaceOptions o;
  o.alpha0 = 1.0;
  EXPECT_THROW(DesignSpace(mesh, o), InputError);
  o = {};
  o.Y0 = 1e12;  // outside [2.5e9, 6.5e11]
  EXPECT_THROW(DesignSpace(mesh, o), InputError);
  o = {};
  o.alpha0 = 0.2;  // rho0 = 12500 > rho_max
  EXPECT_THROW(DesignSpace(mesh, o), InputError);
  o = {};
  o.fields = {DesignField::kRho, DesignField::kRho};
  EXPECT_THROW(DesignSpace(mesh, o), InputError);
  EXPECT_THROW(parse_design_field("density"), InputError);
  const DesignSpace ok(mesh, DesignSpaceOptions{});
  EXPECT_THROW(ok.to_material(Eigen::VectorXd::Zero(3)), InputError);
}

TEST(DesignSpace, OptionsFromScene) {
  Scene scene;
  scene.fields = {"Y", "nu", "rho"};
  scene.Y_range = {5e9, 6.5e11};
  scene.alpha0 = 0.95;
  scene.seed = 11;
  scene.boundary_by_vertex = true;
  const DesignSpaceOptions o = design_space_options(scene);
  ASSERT_EQ(o.fields.size(), 3u);
  EXPECT_EQ(o.fields[2], DesignField::kRho);
  EXPECT_EQ(o.Y_min, 5e9);
  EXPECT_EQ(o.alpha0, 0.95);
  EXPECT_EQ(o.seed, 11u);
  EXPECT_TRUE(o.boundary_by_vertex);
  EXPECT_TRUE(std::isnan(o.Y0));  // the middle of the range unless the config says otherwise
  scene.Y0 = 6e9;
  scene.nu0 = 0.25;
  const DesignSpaceOptions soft = design_space_options(scene);
  EXPECT_EQ(soft.Y0, 6e9);
  EXPECT_EQ(soft.nu0, 0.25);
}

}  // namespace
}  // namespace rbaa
