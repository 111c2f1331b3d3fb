#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "rbaa/error.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/geometry/smoothing.hpp"
#include "rbaa/material/design_space.hpp"
#include "rbaa/mesh/grid_mesh.hpp"
#include "rbaa/opt/attack_loop.hpp"
#include "rbaa/opt/moment_cost.hpp"
#include "rbaa/opt/occupancy.hpp"
#include "rbaa/opt/occupancy_penalty.hpp"

namespace rbaa {
namespace {

TetMesh test_mesh() { return box_tet_mesh({0.3, -0.2, 0.5}, {1.1, 0.4, 1.4}, 5, 4, 5); }

// theta with the alpha block spread over (alpha_min, 1) on both sides of any threshold, the
// other blocks perturbed.
Eigen::VectorXd spread_theta(const DesignSpace& design, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  Eigen::VectorXd theta = design.initial_theta(true);
  const int o = design.offset(DesignField::kAlpha);
  for (int i = 0; i < design.block_size(DesignField::kAlpha); ++i) theta[o + i] = u(rng);
  return theta;
}

TEST(OccupancyPenalty, GreynessIsZeroAtTheEndsAndOneAtTheThreshold) {
  const TetMesh mesh = test_mesh();
  DesignSpaceOptions o;
  o.alpha_min = 1e-3;
  const DesignSpace design(mesh, o);
  for (double t : {0.5, 0.3, 0.8}) {
    const OccupancyPenalty penalty(mesh, design, t);
    double d = 0;
    EXPECT_NEAR(penalty.greyness(1e-3, &d), 0.0, 1e-15) << t;
    EXPECT_GT(d, 0.0);  // rising from alpha_min: descent pushes alpha down to it
    EXPECT_NEAR(penalty.greyness(1.0, &d), 0.0, 1e-15) << t;
    EXPECT_LT(d, 0.0);  // falling to 1: descent pushes alpha up to it
    EXPECT_NEAR(penalty.greyness(t, &d), 1.0, 1e-15) << t;
    EXPECT_NEAR(d, 0.0, 1e-12) << t;  // C^1 at the peak
    // Descent moves alpha away from t towards the side that rounding keeps.
    penalty.greyness(t - 0.01, &d);
    EXPECT_GT(d, 0.0);
    penalty.greyness(t + 0.01, &d);
    EXPECT_LT(d, 0.0);
  }
  // t = 0.5 and alpha_min = 0 give 4 alpha (1 - alpha).
  DesignSpaceOptions zero;
  zero.alpha_min = 1e-12;
  const DesignSpace d0(mesh, zero);
  const OccupancyPenalty classic(mesh, d0, 0.5);
  for (double a : {0.1, 0.37, 0.5, 0.72, 0.99})
    EXPECT_NEAR(classic.greyness(a), 4 * a * (1 - a), 1e-10);
  EXPECT_THROW(OccupancyPenalty(mesh, design, 1e-3), InputError);
  EXPECT_THROW(OccupancyPenalty(mesh, design, 1.0), InputError);
}

// P's analytic gradient in theta against central differences, for several thresholds.
TEST(OccupancyPenalty, GradientMatchesFiniteDifferences) {
  const TetMesh mesh = test_mesh();
  const DesignSpace design(mesh, DesignSpaceOptions{});
  ASSERT_GT(design.num_interior(), 10);
  for (double t : {0.5, 0.3}) {
    const OccupancyPenalty penalty(mesh, design, t);
    const Eigen::VectorXd theta = spread_theta(design, 7);
    Eigen::VectorXd g;
    const double P = penalty.value(theta, &g);
    EXPECT_GT(P, 0.0);
    EXPECT_LT(P, 1.0);
    ASSERT_EQ(g.size(), design.size());
    const double eps = 1e-6;
    double worst = 0;
    for (Eigen::Index i = 0; i < theta.size(); ++i) {
      Eigen::VectorXd tp = theta, tm = theta;
      tp[i] += eps;
      tm[i] -= eps;
      const double fd = (penalty.value(tp) - penalty.value(tm)) / (2 * eps);
      worst = std::max(worst, std::abs(fd - g[i]));
    }
    // Round-off of P (~0.5) over 2 eps is ~1e-10; a wrong term would be off by O(max |g|).
    EXPECT_LT(worst, 1e-6 * g.cwiseAbs().maxCoeff()) << "threshold " << t;
    // Zero outside the alpha block.
    const int o = design.offset(DesignField::kAlpha);
    EXPECT_EQ(g.head(o).cwiseAbs().maxCoeff(), 0.0);
  }
}

TEST(OccupancyPenalty, GreyFractionIsTheVolumeShareStrictlyBetweenFivePercentAndNinetyFive) {
  const TetMesh mesh = test_mesh();
  const DesignSpace design(mesh, DesignSpaceOptions{});
  const OccupancyPenalty penalty(mesh, design, 0.5);
  const Eigen::VectorXd volume = tet_volumes(mesh);
  const Eigen::VectorXd theta = spread_theta(design, 3);
  const MaterialField m = design.to_material(theta);
  double grey = 0, all = 0;
  for (int e : design.interior()) {
    all += volume[e];
    if (m.alpha[e] > 0.05 && m.alpha[e] < 0.95) grey += volume[e];
  }
  EXPECT_NEAR(penalty.grey_fraction(theta), grey / all, 1e-14);
  EXPECT_GT(grey, 0.0);
  EXPECT_LT(grey, all);
  EXPECT_EQ(penalty.grey_fraction(design.initial_theta(false)), 0.0);  // alpha0 = 0.99
}

TEST(OccupancyPenalty, RampIsLinearBetweenTheFractions) {
  OccupancyPenaltyOptions o;
  o.ramp_start = 0.2;
  o.ramp_end = 0.6;
  EXPECT_EQ(occupancy_penalty_ramp(o, 0, 10), 0.0);
  EXPECT_EQ(occupancy_penalty_ramp(o, 2, 10), 0.0);
  EXPECT_NEAR(occupancy_penalty_ramp(o, 3, 10), 0.25, 1e-15);
  EXPECT_NEAR(occupancy_penalty_ramp(o, 4, 10), 0.5, 1e-15);
  EXPECT_EQ(occupancy_penalty_ramp(o, 6, 10), 1.0);
  EXPECT_EQ(occupancy_penalty_ramp(o, 9, 10), 1.0);
  o.ramp_start = o.ramp_end = 0.5;  // a step
  EXPECT_EQ(occupancy_penalty_ramp(o, 4, 10), 0.0);
  EXPECT_EQ(occupancy_penalty_ramp(o, 5, 10), 1.0);
}

// R weighs the emptiness of exactly the elements the connectivity repair fills, and its gradient
// (the repair's set held) matches central differences that cross no threshold.
TEST(OccupancyPenalty, RepairShareFillsThePathsTheRepairWouldFill) {
  const TetMesh mesh = box_tet_mesh({0, 0, 0}, {0.6, 0.6, 0.6}, 6, 6, 6);
  const DesignSpace design(mesh, DesignSpaceOptions{});
  const OccupancyPenalty penalty(mesh, design, 0.5);
  const Eigen::VectorXd volume = tet_volumes(mesh);
  const Eigen::Vector3d centre(0.3, 0.3, 0.3);
  // Interior void (alpha 0.02 to 0.1) but for an occupied ball around the centre, away from the
  // shell: an island the repair must join to it.
  Eigen::VectorXd theta = design.initial_theta(false);
  const int o = design.offset(DesignField::kAlpha);
  const TanhBoxMap& map = design.map(DesignField::kAlpha);
  double interior_volume = 0;
  for (int i = 0; i < design.num_interior(); ++i) {
    const int e = design.interior()[i];
    const Eigen::Vector3d c = 0.25 * (mesh.V.row(mesh.T(e, 0)) + mesh.V.row(mesh.T(e, 1)) +
                                      mesh.V.row(mesh.T(e, 2)) + mesh.V.row(mesh.T(e, 3)))
                                         .transpose();
    theta[o + i] = map.inverse((c - centre).norm() < 0.1 ? 0.9 : 0.02 + 0.08 * (i % 7) / 7.0);
    interior_volume += volume[e];
  }
  const MaterialField m = design.to_material(theta);
  const Eigen::VectorXd rounded = round_occupancy(m.alpha, design.boundary(), 0.5);
  Eigen::VectorXd repaired = rounded;
  const ConnectivityReport report = repair_connectivity(mesh, design.boundary(), repaired);
  ASSERT_GT(report.components_before, 1);
  ASSERT_GT(report.elements_added, 0);
  double expected = 0;
  for (int e = 0; e < mesh.num_tets(); ++e) {
    if (repaired[e] != rounded[e]) expected += volume[e] * (1 - m.alpha[e]) / (1 - 1e-3);
  }
  Eigen::VectorXd g;
  int components = 0;
  const double R = penalty.repair_share(theta, &g, &components);
  EXPECT_EQ(components, report.components_before);
  EXPECT_EQ(penalty.components(theta), report.components_before);  // the same count, no search
  EXPECT_NEAR(R, expected / interior_volume, 1e-12);
  int pushed = 0;
  for (int i = 0; i < design.num_interior(); ++i) pushed += g[o + i] < 0;
  EXPECT_EQ(pushed, report.elements_added);  // descent raises exactly the filled elements' alpha
  EXPECT_EQ((g.array() > 0).count(), 0);
  // Every repair costs a Steiner search: difference the filled elements and every 200th other
  // entry (the other fields' blocks included).
  const double eps = 1e-6;
  double worst = 0;
  for (Eigen::Index i = 0; i < theta.size(); ++i) {
    if (g[i] == 0 && i % 200 != 0) continue;
    Eigen::VectorXd tp = theta, tm = theta;
    tp[i] += eps;
    tm[i] -= eps;
    worst = std::max(
        worst, std::abs((penalty.repair_share(tp) - penalty.repair_share(tm)) / (2 * eps) - g[i]));
  }
  EXPECT_LT(worst, 1e-6 * g.cwiseAbs().maxCoeff());
  // All interior occupied: one component, nothing to fill.
  EXPECT_EQ(penalty.repair_share(design.initial_theta(false), &g, &components), 0.0);
  EXPECT_EQ(components, 1);
  EXPECT_EQ(g.cwiseAbs().maxCoeff(), 0.0);
}

// In the loop the penalty goes through the same smoothing, tangent projection and retraction as
// the rest: with a trajectory term blind to alpha, it drives the grey occupancy to its ends while
// rho follows, and the moments stay matched.
TEST(OccupancyPenalty, LoopDrivesOccupancyToItsEndsWithTheMomentsMatched) {
  const TetMesh mesh = box_tet_mesh({0, 0, 0}, {0.3, 0.2, 0.25}, 5, 4, 4);
  DesignSpaceOptions o;
  o.alpha0 = 0.6;
  o.perturbation = 0.5;
  const DesignSpace design(mesh, o);
  const MomentCostFunction moments(mesh, design, compute_moments(mesh, 2500.0));
  const GradientSmoother smoother(mesh, 1.0);
  const TrajectoryTerm blind = [](const Eigen::VectorXd& theta, Eigen::VectorXd* gradient) {
    if (gradient) gradient->setZero(theta.size());
    return TrajectoryTermValue{-1.0, 0.0, 0.0, 0.0, 0.0};  // the scale: w_k = ramp
  };
  AttackLoopOptions loop;
  loop.iterations = 40;
  loop.adam.learning_rate = 0.1;
  OccupancyPenaltyOptions po;
  po.weight = 1.0;
  po.ramp_start = 0.0;
  po.ramp_end = 0.25;
  const OccupancyPenalty penalty(mesh, design, 0.5, po);
  loop.occupancy = &penalty;
  const AttackLoopResult r =
      run_attack_loop(design, moments, &smoother, blind, design.initial_theta(true), loop);
  ASSERT_EQ(r.progress.size(), 40u);
  EXPECT_EQ(r.progress.front().occupancy_weight, 0.0);
  EXPECT_EQ(r.progress.back().occupancy_weight, 1.0);  // ramp 1 times max |C_traj| = 1
  const double grey0 = r.progress.front().grey_fraction, grey1 = penalty.grey_fraction(r.theta);
  const double P0 = r.progress.front().occupancy_penalty, P1 = penalty.value(r.theta);
  EXPECT_GT(grey0, 0.5);
  EXPECT_LT(grey1, 0.5 * grey0) << "grey fraction " << grey0 << " -> " << grey1;
  EXPECT_LT(P1, 0.5 * P0) << "greyness " << P0 << " -> " << P1;
  EXPECT_LT(moments.residuals(r.theta).cwiseAbs().maxCoeff(), 1e-10);
  // Without the penalty the blind term leaves the occupancy where it started.
  loop.occupancy = nullptr;
  const AttackLoopResult still =
      run_attack_loop(design, moments, &smoother, blind, design.initial_theta(true), loop);
  EXPECT_EQ(still.progress.back().grey_fraction, 0.0);  // not measured without a penalty
  EXPECT_NEAR(penalty.grey_fraction(still.theta), grey0, 0.05);
}

// The repair_in_loop scenes: a 6 x 6 x 6 box whose interior starts at alpha 0.3, which rounds to
// void, so the interior falls apart from the shell and the repair has paths to fill.
struct RepairScene {
  TetMesh mesh = box_tet_mesh({0, 0, 0}, {0.3, 0.3, 0.3}, 6, 6, 6);
  DesignSpace design{mesh, [] {
                       DesignSpaceOptions o;
                       o.alpha0 = 0.3;
                       o.perturbation = 0.3;
                       return o;
                     }()};
  MomentCostFunction moments{mesh, design, compute_moments(mesh, 2500.0)};
  GradientSmoother smoother{mesh, 1.0};
  OccupancyPenalty penalty{mesh, design, 0.5, [] {
                             OccupancyPenaltyOptions po;
                             po.repair_in_loop = true;
                             return po;
                           }()};
  // A term that likes low occupancy: it keeps carving what the fill joins.
  TrajectoryTerm carve() const {
    return [this](const Eigen::VectorXd& theta, Eigen::VectorXd* gradient) {
      if (gradient) {
        gradient->setZero(theta.size());
        gradient->segment(design.offset(DesignField::kAlpha), design.num_interior()).setConstant(1e-3);
      }
      return TrajectoryTermValue{-1.0, 0.0, 0.0, 0.0, 0.0};
    };
  }
};

// repair_in_loop: after every step the repair's paths are filled and the moments retracted, so
// every design the loop simulates after its first rounds to one body with the shell.
TEST(OccupancyPenalty, RepairInLoopLeavesOneBodyWithTheMomentsMatched) {
  const RepairScene scene;
  const DesignSpace& design = scene.design;
  const OccupancyPenalty& penalty = scene.penalty;
  int components = 0;
  penalty.repair_share(design.initial_theta(true), nullptr, &components);
  ASSERT_GT(components, 1);
  AttackLoopOptions loop;
  loop.iterations = 6;
  loop.occupancy = &penalty;
  const AttackLoopResult r =
      run_attack_loop(design, scene.moments, &scene.smoother, scene.carve(), design.initial_theta(true), loop);
  ASSERT_EQ(r.progress.size(), 6u);
  EXPECT_GT(r.progress[0].components, 1);  // the start: not filled
  for (size_t k = 1; k < r.progress.size(); ++k) EXPECT_EQ(r.progress[k].components, 1) << k;
  EXPECT_EQ(penalty.repair_share(r.theta, nullptr, &components), 0.0);
  EXPECT_EQ(components, 1);
  EXPECT_LT(scene.moments.residuals(r.theta).cwiseAbs().maxCoeff(), 1e-10);
}

// The fill's retraction is guarded as a step's is: from a saturated design (the tanh map flat,
// J J^T nearly singular) filling a path moves alpha far, and a retraction that diverged there left
// the design off the moments for good. No design the loop simulates gets farther off the moments
// than 1e-6 or the design before it.
TEST(OccupancyPenalty, RepairInLoopNeverLeavesTheMomentsWhereTheDesignSaturates) {
  const RepairScene scene;
  // (Before the guard: 1.25 off after 0.71 at saturation 20 and rate 0.3, 0.91 after 0.17 at rate 1.)
  for (double saturation : {20.0, 40.0}) {
    for (double learning_rate : {0.3, 1.0}) {
      AttackLoopOptions loop;
      loop.iterations = 8;
      loop.occupancy = &scene.penalty;
      loop.adam.learning_rate = learning_rate;
      const Eigen::VectorXd theta0 = saturation * scene.design.initial_theta(true);
      const AttackLoopResult r = run_attack_loop(scene.design, scene.moments, &scene.smoother, scene.carve(), theta0, loop);
      ASSERT_EQ(r.progress.size(), 8u);
      for (size_t k = 1; k < r.progress.size(); ++k) {
        const double bound = std::max(1e-6, r.progress[k - 1].max_moment_residual);
        EXPECT_LE(r.progress[k].max_moment_residual, bound)
            << "saturation " << saturation << ", learning rate " << learning_rate << ", iteration " << k;
      }
    }
  }
}

}  // namespace
}  // namespace rbaa
