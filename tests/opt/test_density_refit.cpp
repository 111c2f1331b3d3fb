#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "rbaa/error.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/mesh/grid_mesh.hpp"
#include "rbaa/mesh/tetrahedralize.hpp"
#include "rbaa/mesh/topology.hpp"
#include "rbaa/opt/density_refit.hpp"
#include "rbaa/opt/occupancy.hpp"

namespace rbaa {
namespace {

struct RoundedObject {
  Eigen::VectorXd alpha, rho;
};

// A random "optimised" object: interior alpha uniform in (0, 1) rounded at `threshold`,
// connectivity repaired, densities uniform in [rho_lo, rho_hi].
RoundedObject random_rounded_object(const TetMesh& mesh, unsigned seed, double threshold,
                                    double rho_lo, double rho_hi) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const std::vector<char> boundary = boundary_elements(mesh);
  RoundedObject o;
  o.alpha.resize(mesh.num_tets());
  o.rho.resize(mesh.num_tets());
  for (int e = 0; e < mesh.num_tets(); ++e) {
    o.alpha[e] = unit(rng);
    o.rho[e] = rho_lo + (rho_hi - rho_lo) * unit(rng);
  }
  o.alpha = round_occupancy(o.alpha, boundary, threshold);
  repair_connectivity(mesh, boundary, o.alpha);
  return o;
}

void check_refit(const TetMesh& mesh, const RoundedObject& o, const Moments& reference,
                 const char* label) {
  const TanhBoxMap rho_map(800.0, 11300.0, "density range");
  const DensityRefitResult fit = refit_density(mesh, o.alpha, o.rho, reference, rho_map);
  const double void_fraction = 1.0 - o.alpha.dot(tet_volumes(mesh)) / tet_volumes(mesh).sum();
  std::printf("%s: %d tets, void fraction %.1f %%, max normalised residual %.3e -> %.3e in %d "
              "Ceres iterations\n",
              label, mesh.num_tets(), 100 * void_fraction, fit.initial_max_residual,
              fit.max_residual, fit.iterations);
  EXPECT_GT(fit.initial_max_residual, 1e-2);  // there was something to fix
  EXPECT_LE(fit.max_residual, 1e-10);
  // Independent recomputation of the moments.
  const MomentVector r = (compute_moments(mesh, fit.rho.cwiseProduct(o.alpha)).as_vector() -
                          reference.as_vector())
                             .cwiseQuotient(moment_normalisation(reference));
  EXPECT_LE(r.cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_LE(fit.iterations, 10);
  // Inside the bounds, void elements untouched, and the change of theta lies in the span of the
  // 10 element-averaged quadratic moment integrands.
  EXPECT_GT(fit.rho.minCoeff(), 800.0);
  EXPECT_LT(fit.rho.maxCoeff(), 11300.0);
  Eigen::MatrixXd phi(mesh.num_tets(), 10);
  const auto S = moment_operator(mesh);
  Eigen::VectorXd dtheta(mesh.num_tets());
  int occupied = 0;
  for (int e = 0; e < mesh.num_tets(); ++e) {
    if (o.alpha[e] == 0.0) {
      EXPECT_EQ(fit.rho[e], o.rho[e]);
      continue;
    }
    phi.row(occupied) = S.col(e).transpose() / S(0, e);
    dtheta[occupied] = rho_map.inverse(fit.rho[e]) - rho_map.inverse(o.rho[e]);
    ++occupied;
  }
  const Eigen::MatrixXd P = phi.topRows(occupied);
  const Eigen::VectorXd d = dtheta.head(occupied);
  const Eigen::VectorXd coeff = P.colPivHouseholderQr().solve(d);
  EXPECT_LT((P * coeff - d).norm(), 1e-8 * d.norm());
  EXPECT_GT(d.norm(), 1e-3);
}

TEST(DensityRefit, RandomRoundedBoxOffTheOrigin) {
  const TetMesh mesh = box_tet_mesh({0.3, -0.2, 0.5}, {1.1, 0.4, 1.4}, 6, 5, 7);
  const Moments reference = compute_moments(mesh, 2500.0);
  check_refit(mesh, random_rounded_object(mesh, 1, 0.5, 2000.0, 4500.0), reference, "box");
}

TEST(DensityRefit, RandomRoundedSphereAtTheBallsPosition) {
  TetMesh mesh = mesh_shape("sphere", 3000);
  mesh.V.rowwise() += Eigen::RowVector3d(0.341, -0.228, 3.447);
  const Moments reference = compute_moments(mesh, 2500.0);
  check_refit(mesh, random_rounded_object(mesh, 2, 0.4, 1500.0, 5000.0), reference, "sphere");
}

// The iteration count must not depend on the last bits of the input: the sphere at the ball's
// position (|c| / L ~ 45, so the residuals about the origin amplify round-off by ~2000) with its
// vertices moved by a few ulps and with several random objects.
TEST(DensityRefit, IterationCountIsRobustToUlpPerturbationsAndSeeds) {
  TetMesh base = mesh_shape("sphere", 3000);
  base.V.rowwise() += Eigen::RowVector3d(0.341, -0.228, 3.447);
  const TanhBoxMap rho_map(800.0, 11300.0, "density range");
  int worst = 0;
  for (int ulps = 0; ulps <= 4; ++ulps) {
    TetMesh mesh = base;
    std::mt19937_64 rng(100 + ulps);
    for (Eigen::Index i = 0; i < mesh.V.size(); ++i) {
      double& x = mesh.V.data()[i];
      const int k = static_cast<int>(rng() % (2 * ulps + 1)) - ulps;  // -ulps .. ulps
      for (int j = 0; j < std::abs(k); ++j) x = std::nextafter(x, k > 0 ? 1e300 : -1e300);
    }
    const Moments reference = compute_moments(mesh, 2500.0);
    for (unsigned seed = 2; seed <= 5; ++seed) {
      const RoundedObject o = random_rounded_object(mesh, seed, 0.4, 1500.0, 5000.0);
      const DensityRefitResult fit = refit_density(mesh, o.alpha, o.rho, reference, rho_map);
      std::printf("ulps %d seed %u: %.3e -> %.3e in %d Ceres iterations\n", ulps, seed,
                  fit.initial_max_residual, fit.max_residual, fit.iterations);
      EXPECT_LE(fit.max_residual, 1e-10);
      worst = std::max(worst, fit.iterations);
    }
  }
  EXPECT_LE(worst, 10);
}

// The re-fit's analytic Jacobian against central differences of its residuals (normwise, at the
// start, where preconditioning makes it the identity, and at a point where the tanh map bends),
// on an object with densities near both bounds.
TEST(DensityRefit, JacobianMatchesCentralDifferences) {
  const TetMesh mesh = box_tet_mesh({0.3, -0.2, 0.5}, {1.1, 0.4, 1.4}, 4, 3, 5);
  const Moments reference = compute_moments(mesh, 2500.0);
  const RoundedObject o = random_rounded_object(mesh, 9, 0.5, 900.0, 11000.0);
  DensityRefitOptions options;
  options.check_jacobian = true;
  const TanhBoxMap rho_map(800.0, 11300.0, "density range");
  const DensityRefitResult fit = refit_density(mesh, o.alpha, o.rho, reference, rho_map, options);
  std::printf("re-fit Jacobian vs central differences: %.2e\n", fit.jacobian_check_error);
  EXPECT_GT(fit.jacobian_check_error, 0.0);  // it ran
  EXPECT_LE(fit.jacobian_check_error, 1e-7);
  EXPECT_LE(fit.max_residual, 1e-10);
}

// A random occupancy of the given volume fraction (boundary kept), so that the occupied elements
// are spread over the whole object and the centre of mass stays reachable.
Eigen::VectorXd random_occupancy(const TetMesh& mesh, double fraction, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const std::vector<char> boundary = boundary_elements(mesh, false);
  Eigen::VectorXd alpha(mesh.num_tets());
  for (int e = 0; e < mesh.num_tets(); ++e) alpha[e] = (boundary[e] || unit(rng) < fraction) ? 1.0 : 0.0;
  return alpha;
}

double void_fraction(const TetMesh& mesh, const Eigen::VectorXd& alpha) {
  const Eigen::VectorXd vol = tet_volumes(mesh);
  return 1.0 - alpha.dot(vol) / vol.sum();
}

TEST(DensityRefit, FailsClearlyWhenTheVoidFractionIsTooLarge) {
  // A finer grid, so that the boundary elements are a small part of the volume.
  const TetMesh mesh = box_tet_mesh({0, 0, 0}, {1, 1, 1}, 10, 10, 10);
  const Moments reference = compute_moments(mesh, 2500.0);
  const Eigen::VectorXd rho = Eigen::VectorXd::Constant(mesh.num_tets(), 5000.0);
  const TanhBoxMap rho_map(800.0, 11300.0, "density range");

  // Above 1 - 2500 / 11300 = 77.9 % void even rho_max everywhere cannot carry m0.
  Eigen::VectorXd alpha = random_occupancy(mesh, 0.0, 3);
  ASSERT_GT(void_fraction(mesh, alpha), 0.80);
  try {
    refit_density(mesh, alpha, rho, reference, rho_map);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    std::printf("infeasible re-fit (%.1f %% void): %s\n", 100 * void_fraction(mesh, alpha),
                msg.c_str());
    EXPECT_NE(msg.find("void fraction"), std::string::npos);
    EXPECT_NE(msg.find("11300"), std::string::npos);
  }
  // Too heavy the other way: densities bounded below by 3000 cannot give 2500 on a full object.
  alpha.setOnes();
  EXPECT_THROW(refit_density(mesh, alpha, rho, reference, TanhBoxMap(3000.0, 11300.0)),
               InputError);
  // At about 65 % void the same object is feasible and fits.
  alpha = random_occupancy(mesh, 0.2, 4);
  const double vf = void_fraction(mesh, alpha);
  ASSERT_GT(vf, 0.5);
  ASSERT_LT(vf, 0.75);
  const DensityRefitResult fit = refit_density(mesh, alpha, rho, reference, rho_map);
  std::printf("feasible re-fit at %.1f %% void: max normalised residual %.3e -> %.3e in %d "
              "iterations\n", 100 * vf, fit.initial_max_residual, fit.max_residual, fit.iterations);
  EXPECT_LE(fit.max_residual, 1e-10);
}

}  // namespace
}  // namespace rbaa
