#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <filesystem>
#include <fstream>
#include <vector>

#include <unistd.h>

#include "rbaa/error.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/mesh/grid_mesh.hpp"
#include "rbaa/mesh/topology.hpp"
#include "rbaa/opt/attack_loop.hpp"
#include "rbaa/opt/post_process.hpp"

namespace rbaa {
namespace {

class AttackLoop : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = ::testing::TempDir() + "/rbaa_attack_loop_" + std::to_string(::getpid());
    std::filesystem::create_directories(dir_);
    mesh_ = box_tet_mesh({0, 0, 0}, {0.3, 0.2, 0.25}, 4, 3, 3);
    design_ = std::make_unique<DesignSpace>(mesh_, DesignSpaceOptions{});
    reference_ = compute_moments(mesh_, 2500.0);
    moments_ = std::make_unique<MomentCostFunction>(mesh_, *design_, reference_);
    smoother_ = std::make_unique<GradientSmoother>(mesh_, 1.0);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // A stand-in for the simulation: a smooth function of the material field that prefers
  // stiffness contrast and low occupancy, with an exact gradient.
  TrajectoryTerm fake_term() const {
    return [this](const Eigen::VectorXd& theta, Eigen::VectorXd* gradient) {
      const Eigen::VectorXd d = theta - Eigen::VectorXd::LinSpaced(theta.size(), -1, 1);
      if (gradient) *gradient = -2e-3 * d;
      return TrajectoryTermValue{-1e-3 * d.squaredNorm(), std::sqrt(1e-3 * d.squaredNorm()), 0.0, 0.0, 0.0};
    };
  }

  AttackLoopOptions options(int iterations) const {
    AttackLoopOptions o;
    o.iterations = iterations;
    o.checkpoint_path = dir_ + "/checkpoint.json";
    o.progress_path = dir_ + "/progress.csv";
    o.fingerprint = "test-1";
    return o;
  }

  std::string dir_;
  TetMesh mesh_;
  std::unique_ptr<DesignSpace> design_;
  Moments reference_;
  std::unique_ptr<MomentCostFunction> moments_;
  std::unique_ptr<GradientSmoother> smoother_;
};

TEST_F(AttackLoop, ResumedRunEqualsUninterruptedRun) {
  const Eigen::VectorXd theta0 = design_->initial_theta();
  const AttackLoopResult straight = run_attack_loop(*design_, *moments_, smoother_.get(), fake_term(), theta0, options(8));
  std::filesystem::remove(dir_ + "/checkpoint.json");

  run_attack_loop(*design_, *moments_, smoother_.get(), fake_term(), theta0, options(3));  // "killed" after 3
  AttackLoopOptions resume = options(8);
  resume.resume = true;
  const AttackLoopResult resumed = run_attack_loop(*design_, *moments_, smoother_.get(), fake_term(), theta0, resume);
  EXPECT_EQ(resumed.resumed_from, 3);
  ASSERT_EQ(resumed.progress.size(), 8u);
  EXPECT_TRUE(resumed.theta == straight.theta);  // bit for bit
  for (size_t i = 0; i < 8; ++i) EXPECT_EQ(resumed.progress[i].objective, straight.progress[i].objective);
  // Adam did move theta (the comparison above is not between two untouched vectors).
  EXPECT_GT((straight.theta - theta0).norm(), 0.1);
  std::ifstream csv(dir_ + "/progress.csv");
  int lines = 0;
  for (std::string line; std::getline(csv, line);) ++lines;
  EXPECT_EQ(lines, 9);
}

// The loop keeps its best evaluated design (issue 20 item 3): on an oscillating term that a large
// learning rate overshoots, best_iteration is the row with the lowest objective and best_theta the
// design it was measured at; a resumed run keeps them bit for bit through the checkpoint. (At
// learning rate 1.0, which this test used until 2026-11-28, the "overshoot" was the design
// leaving the moments, 0.3 - 0.6 off from the first step, which the loop no longer allows; at 0.5
// every design keeps them and the objective rises after its best, the third design's.)
TEST_F(AttackLoop, KeepsItsBestDesignAcrossAResume) {
  std::vector<Eigen::VectorXd> evaluated;
  const TrajectoryTerm wavy = [&evaluated](const Eigen::VectorXd& theta, Eigen::VectorXd* gradient) {
    evaluated.push_back(theta);
    if (gradient) *gradient = 3e-3 * (3 * theta).array().cos().matrix();
    const double v = 1e-3 * (3 * theta).array().sin().sum();
    return TrajectoryTermValue{v, std::abs(v), 0.0, 0.0, 0.0};
  };
  const Eigen::VectorXd theta0 = design_->initial_theta();
  AttackLoopOptions o = options(8);
  o.adam.learning_rate = 0.5;
  const AttackLoopResult straight = run_attack_loop(*design_, *moments_, smoother_.get(), wavy, theta0, o);
  ASSERT_EQ(straight.progress.size(), 8u);
  ASSERT_EQ(evaluated.size(), 8u);
  int lowest = 0;
  for (int k = 1; k < 8; ++k) {
    if (straight.progress[k].objective < straight.progress[lowest].objective) lowest = k;
  }
  EXPECT_EQ(straight.best_iteration, lowest);
  EXPECT_TRUE(straight.best_theta == evaluated[lowest]);
  // The overshoot is real: the last row is worse than the best.
  EXPECT_LT(straight.progress[lowest].objective, straight.progress.back().objective);

  std::filesystem::remove(dir_ + "/checkpoint.json");
  AttackLoopOptions killed = options(3);
  killed.adam.learning_rate = 0.5;
  run_attack_loop(*design_, *moments_, smoother_.get(), wavy, theta0, killed);
  AttackLoopOptions resume = o;
  resume.resume = true;
  const AttackLoopResult resumed = run_attack_loop(*design_, *moments_, smoother_.get(), wavy, theta0, resume);
  EXPECT_EQ(resumed.resumed_from, 3);
  EXPECT_EQ(resumed.best_iteration, straight.best_iteration);
  EXPECT_TRUE(resumed.best_theta == straight.best_theta);
  EXPECT_TRUE(resumed.theta == straight.theta);
}

TEST_F(AttackLoop, IncompatibleCheckpointIsAClearError) {
  const Eigen::VectorXd theta0 = design_->initial_theta();
  run_attack_loop(*design_, *moments_, smoother_.get(), fake_term(), theta0, options(2));
  AttackLoopOptions other = options(4);
  other.resume = true;
  other.fingerprint = "another scene";
  try {
    run_attack_loop(*design_, *moments_, smoother_.get(), fake_term(), theta0, other);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("checkpoint.json"), std::string::npos) << e.what();
  }
  std::ofstream(dir_ + "/checkpoint.json") << "{\"format\": 3";
  AttackLoopOptions broken = options(4);
  broken.resume = true;
  EXPECT_THROW(run_attack_loop(*design_, *moments_, smoother_.get(), fake_term(), theta0, broken), InputError);
}

// A simulation that fails (Newton did not converge) keeps what the run has: the loop stops at the
// last design whose simulation succeeded, also when the failure comes first after a resume.
TEST_F(AttackLoop, FailedSimulationStopsAtTheLastGoodDesign) {
  const Eigen::VectorXd theta0 = design_->initial_theta();
  std::vector<Eigen::VectorXd> seen;
  int calls = 0, fail_at = 3;
  const TrajectoryTerm base = fake_term();
  Eigen::VectorXd failed;
  const TrajectoryTerm failing = [&](const Eigen::VectorXd& theta, Eigen::VectorXd* g) {
    if (calls++ == fail_at) {
      failed = theta;
      throw SolverError("step 5: Newton did not converge");
    }
    seen.push_back(theta);
    return base(theta, g);
  };
  const AttackLoopResult r = run_attack_loop(*design_, *moments_, smoother_.get(), failing, theta0, options(6));
  EXPECT_NE(r.stopped_early.find("Newton"), std::string::npos);
  EXPECT_EQ(r.progress.size(), 3u);
  EXPECT_TRUE(r.theta == seen.back());  // the last design that was simulated
  EXPECT_TRUE(r.failed_theta == failed);  // kept for reproducing the failure
  EXPECT_FALSE(r.failed_theta == r.theta);

  // Resume: the checkpoint's next design fails at once; the run falls back to the one before.
  calls = 0;
  fail_at = 0;
  seen.clear();
  AttackLoopOptions resume = options(6);
  resume.resume = true;
  const AttackLoopResult again = run_attack_loop(*design_, *moments_, smoother_.get(), failing, theta0, resume);
  EXPECT_FALSE(again.stopped_early.empty());
  EXPECT_TRUE(again.theta == r.theta);
  // Resumed with no iterations left, the loop simulates nothing and returns the checkpoint's next
  // design (the failed one) with the last good one beside it, for run_attack to fall back to.
  calls = 0;
  AttackLoopOptions finished = options(3);
  finished.resume = true;
  const AttackLoopResult idle = run_attack_loop(*design_, *moments_, smoother_.get(), failing, theta0, finished);
  EXPECT_EQ(calls, 0);
  EXPECT_TRUE(idle.theta == failed);
  EXPECT_TRUE(idle.evaluated_theta == r.theta);
  // Without any simulated design there is nothing to keep: the error propagates.
  std::filesystem::remove(dir_ + "/checkpoint.json");
  calls = 0;
  EXPECT_THROW(run_attack_loop(*design_, *moments_, smoother_.get(), failing, theta0, options(6)), SolverError);
}

// A trajectory term that comes back non-finite (a NaN value, or a NaN in its gradient) is a
// failed design like one whose simulation threw: the loop stops at the last finite design, says
// why, and its checkpoint (no NaN in it, which JSON would write as null) resumes.
TEST_F(AttackLoop, NonFiniteTrajectoryTermStopsAtTheLastGoodDesign) {
  const Eigen::VectorXd theta0 = design_->initial_theta();
  const TrajectoryTerm base = fake_term();
  for (const bool in_gradient : {false, true}) {
    std::filesystem::remove(dir_ + "/checkpoint.json");
    int calls = 0;
    std::vector<Eigen::VectorXd> seen;
    const TrajectoryTerm term = [&](const Eigen::VectorXd& theta, Eigen::VectorXd* g) {
      TrajectoryTermValue v = base(theta, g);
      if (calls++ == 2) {
        if (in_gradient && g) (*g)[0] = std::numeric_limits<double>::quiet_NaN();
        if (!in_gradient) v.value = std::numeric_limits<double>::quiet_NaN();
        return v;
      }
      seen.push_back(theta);
      return v;
    };
    AttackLoopResult r;
    try {
      r = run_attack_loop(*design_, *moments_, smoother_.get(), term, theta0, options(5));
    } catch (const std::exception& e) {
      ADD_FAILURE() << (in_gradient ? "gradient" : "value") << ": the loop threw: " << e.what();
      continue;
    }
    std::printf("non-finite %s: %zu rows, stopped early: '%s'\n",
                in_gradient ? "gradient" : "value", r.progress.size(), r.stopped_early.c_str());
    EXPECT_EQ(r.progress.size(), 2u) << in_gradient;
    EXPECT_NE(r.stopped_early.find("not finite"), std::string::npos) << r.stopped_early;
    EXPECT_TRUE(r.theta == seen.back());
    EXPECT_EQ(r.failed_theta.size(), theta0.size());
    for (const ProgressRow& row : r.progress)
      EXPECT_TRUE(std::isfinite(row.objective)) << row.iteration;
    try {
      EXPECT_EQ(load_checkpoint(dir_ + "/checkpoint.json", "test-1", design_->size()).iteration, 2);
    } catch (const InputError& e) {
      ADD_FAILURE() << "the checkpoint does not load: " << e.what();
    }
  }
}

// Every design the loop evaluates has the reference's moments, also where the design saturates
// (the tanh map flat near the bounds, J J^T nearly singular, where four Gauss-Newton steps from
// a long step lose their grip). Seen 2026-11-28 on `rbaa attack --config=configs/cube_strike.yaml
// --set=mesh.target_tets=1500` (the stack's cube, half of it void): its last five designs were
// 1e-2 .. 1e-1 off the moments, undone only by the post-process's re-fit. Here the fixture's term
// at learning rates that saturate the design: before the loop shortened such steps, 8e-6 off at
// 1.0 and 3.5 off at 2.0 (theta 5e9, the objective -3e16 from a design no longer the object's).
TEST_F(AttackLoop, EveryDesignKeepsTheMomentsWhereTheDesignSaturates) {
  const Eigen::VectorXd theta0 = design_->initial_theta();
  for (double learning_rate : {1.0, 2.0}) {
    AttackLoopOptions o = options(30);
    o.adam.learning_rate = learning_rate;
    std::filesystem::remove(dir_ + "/checkpoint.json");
    const AttackLoopResult r = run_attack_loop(*design_, *moments_, smoother_.get(), fake_term(), theta0, o);
    ASSERT_EQ(r.progress.size(), 30u);
    for (const ProgressRow& row : r.progress) {
      EXPECT_LT(row.max_moment_residual, 1e-6) << "learning rate " << learning_rate << ", iteration " << row.iteration;
    }
    EXPECT_LT(moments_->residuals(r.theta).cwiseAbs().maxCoeff(), 1e-6) << learning_rate;
    // The design does saturate (tanh'(20) = 2e-17), and the loop descends all the same.
    EXPECT_GT(r.theta.cwiseAbs().maxCoeff(), 20.0) << learning_rate;
    EXPECT_LT(r.progress.back().objective, 100 * r.progress.front().objective) << learning_rate;
  }
}

// A step refused outright (its retraction never reaches the moments, halved ten times) leaves the
// design where it was; the next iteration takes that design's simulation and gradient as they
// were instead of running them again. Rows of a repeated design read the same.
TEST_F(AttackLoop, ARefusedStepIsNotSimulatedAgain) {
  std::srand(11);
  int reused = 0;
  for (int trial = 0; trial < 6; ++trial) {
    const Eigen::VectorXd theta0 = design_->initial_theta() + 30.0 * Eigen::VectorXd::Random(design_->size());
    std::vector<Eigen::VectorXd> calls;
    const TrajectoryTerm inner = fake_term();
    const TrajectoryTerm counted = [&](const Eigen::VectorXd& theta, Eigen::VectorXd* gradient) {
      calls.push_back(theta);
      return inner(theta, gradient);
    };
    AttackLoopOptions o = options(12);
    o.adam.learning_rate = 2.0;
    std::filesystem::remove(dir_ + "/checkpoint.json");
    const AttackLoopResult r = run_attack_loop(*design_, *moments_, smoother_.get(), counted, theta0, o);
    ASSERT_EQ(r.progress.size(), 12u);
    for (size_t i = 1; i < calls.size(); ++i) EXPECT_FALSE(calls[i] == calls[i - 1]) << "trial " << trial << ", call " << i;
    // Each iteration without a call repeats its predecessor's row.
    int repeated_rows = 0;
    for (size_t k = 1; k < r.progress.size(); ++k) {
      repeated_rows += r.progress[k].objective == r.progress[k - 1].objective && r.progress[k].gap == r.progress[k - 1].gap;
    }
    const int without_call = static_cast<int>(r.progress.size() - calls.size());
    EXPECT_GE(repeated_rows, without_call) << trial;
    reused += without_call;
  }
  EXPECT_GT(reused, 0);  // the scenario refuses steps (3 in these six runs)
}

// The start's retraction, from a design saturated and far off the moments (the retraction can
// diverge there as a long step's does), never leaves the loop's first design farther off than the
// start itself; and a retraction that reaches the moments is still taken.
TEST_F(AttackLoop, TheStartsRetractionNeverEndsFartherOffThanTheStart) {
  std::srand(11);
  int diverged = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::VectorXd theta0 = design_->initial_theta() + 30.0 * Eigen::VectorXd::Random(design_->size());
    const double start = moments_->residuals(theta0).cwiseAbs().maxCoeff();
    Eigen::VectorXd plain = theta0;
    if (retract_onto_moments(*moments_, plain) > std::max(1e-6, start)) ++diverged;
    std::filesystem::remove(dir_ + "/checkpoint.json");
    const AttackLoopResult r = run_attack_loop(*design_, *moments_, smoother_.get(), fake_term(), theta0, options(1));
    ASSERT_EQ(r.progress.size(), 1u);
    EXPECT_LE(r.progress[0].max_moment_residual, std::max(1e-6, start)) << "trial " << trial;
  }
  EXPECT_GT(diverged, 0);  // the scenario does what it is for
  // From the ordinary start the retraction is taken: the first design is on the moments.
  const AttackLoopResult r = run_attack_loop(*design_, *moments_, smoother_.get(), fake_term(), design_->initial_theta(), options(1));
  EXPECT_LT(r.progress[0].max_moment_residual, 1e-9);
}

// The loop's step direction: tangent to the moments and downhill for gradients that lie mostly
// across the tangent, in the metric of a preconditioner that scales one block by 1e7 (the
// occupancy smoothing scales by about 1 / element volume). The Euclidean projection of the
// preconditioned gradient, which the loop used before, goes uphill for some of them.
TEST(MetricTangentProjector, PreconditionedProjectionIsTangentAndDescends) {
  const int n = 60;
  std::srand(7);
  const Eigen::Matrix<double, 10, Eigen::Dynamic> J = Eigen::MatrixXd::Random(10, n);
  Eigen::VectorXd scale = Eigen::VectorXd::Ones(n);
  scale.tail(n / 2).setConstant(1e7);
  auto precondition = [&](const Eigen::VectorXd& v) { return Eigen::VectorXd(scale.cwiseProduct(v)); };
  const MetricTangentProjector tangent(J, precondition);
  const Eigen::Matrix<double, 10, 10> JJt = J * J.transpose();
  int euclidean_uphill = 0;
  for (int trial = 0; trial < 200; ++trial) {
    // Mostly across the tangent, as the cube's gradient is (moving mass changes its rigid
    // motion; little else does).
    const Eigen::VectorXd g = J.transpose() * Eigen::VectorXd::Random(10) + 1e-2 * Eigen::VectorXd::Random(n);
    const Eigen::VectorXd z = tangent.project(precondition(g));
    EXPECT_LT((J * z).norm(), 1e-9 * (J.norm() * z.norm())) << trial;
    EXPECT_GE(g.dot(z), 0.0) << trial;
    const Eigen::VectorXd Mg = precondition(g);
    const Eigen::VectorXd euclidean = Mg - J.transpose() * JJt.ldlt().solve(J * Mg);
    if (g.dot(euclidean) < 0) ++euclidean_uphill;
  }
  EXPECT_GT(euclidean_uphill, 0);
  // Without a preconditioner it is the orthogonal projection.
  const MetricTangentProjector plain(J, [](const Eigen::VectorXd& v) { return v; });
  const Eigen::VectorXd v = Eigen::VectorXd::Random(n);
  EXPECT_LT((plain.project(v) - (v - J.transpose() * JJt.ldlt().solve(J * v))).norm(), 1e-12 * v.norm());
}

TEST(PostProcess, RoundsRepairsRefitsAndRemovesVoids) {
  const TetMesh mesh = box_tet_mesh({-0.2, -0.1, 0.3}, {0.2, 0.1, 0.6}, 6, 4, 5);
  DesignSpaceOptions o;
  o.boundary_by_vertex = true;
  const DesignSpace design(mesh, o);
  const Moments reference = compute_moments(mesh, 2500.0);
  MaterialField field = design.to_material(design.initial_theta());
  // A random occupancy and density: rounding and connectivity repair have work to do.
  std::srand(5);
  for (int e : design.interior()) field.alpha[e] = 0.5 + 0.5 * Eigen::VectorXd::Random(1)[0];
  field.rho = (Eigen::ArrayXd::Random(mesh.num_tets()) * 2000 + 4000).matrix();
  const PostProcessResult r = post_process(mesh, design, field, reference, 0.5);
  EXPECT_EQ(r.connectivity.components_after, 1);
  EXPECT_GT(r.void_fraction, 0.0);
  EXPECT_LE(r.refit.max_residual, 1e-10);
  const MomentVector scale = moment_normalisation(reference);
  const MomentVector m = compute_moments(mesh, r.rounded.effective_density()).as_vector();
  EXPECT_LE(((m - reference.as_vector()).array() / scale.array()).abs().maxCoeff(), 1e-10);
  // The solid keeps exactly the occupied elements, and its moments are the same.
  int occupied = 0;
  for (int e = 0; e < mesh.num_tets(); ++e) occupied += r.rounded.alpha[e] > 0;
  EXPECT_EQ(r.solid.mesh.num_tets(), occupied);
  EXPECT_NO_THROW(validate_tet_mesh(r.solid.mesh, "solid"));
  const MomentVector ms = compute_moments(r.solid.mesh, r.solid.materials.effective_density()).as_vector();
  EXPECT_LE(((ms - reference.as_vector()).array() / scale.array()).abs().maxCoeff(), 1e-10);
  EXPECT_EQ(count_components(r.solid.mesh), 1);
}

// A driven body is held by its driven vertices: the design holds the elements touching them solid
// (DesignSpaceOptions::solid_vertices), and rounding keeps them even where the continuous field
// voided them, so every driven vertex stays in the final object (AttackProblem::with_body maps
// driven vertices through the solid's vertex_origin and refuses a lost one).
TEST(PostProcess, KeepsTheElementsOfTheDesignsSolidVertices) {
  const TetMesh mesh = box_tet_mesh({-0.2, -0.1, 0.3}, {0.2, 0.1, 0.6}, 6, 4, 5);
  const DesignSpace plain(mesh, DesignSpaceOptions{});
  const Moments reference = compute_moments(mesh, 2500.0);
  MaterialField field = plain.to_material(plain.initial_theta());
  // An interior vertex whose every element the continuous field voids.
  std::vector<char> on_boundary_element(mesh.num_vertices(), 0);
  for (int e = 0; e < mesh.num_tets(); ++e) {
    if (plain.boundary()[e]) {
      for (int a = 0; a < 4; ++a) on_boundary_element[mesh.T(e, a)] = 1;
    }
  }
  int v = -1;
  for (int i = 0; i < mesh.num_vertices() && v < 0; ++i) {
    if (!on_boundary_element[i]) v = i;
  }
  ASSERT_GE(v, 0);
  std::vector<int> around;
  for (int e = 0; e < mesh.num_tets(); ++e) {
    for (int a = 0; a < 4; ++a) {
      if (mesh.T(e, a) == v) around.push_back(e);
    }
  }
  for (int e : around) field.alpha[e] = 0.1;
  auto keeps_vertex = [&](const PostProcessResult& r) {
    return std::find(r.solid.vertex_origin.begin(), r.solid.vertex_origin.end(), v) !=
           r.solid.vertex_origin.end();
  };
  const PostProcessResult lost = post_process(mesh, plain, field, reference, 0.5);
  EXPECT_FALSE(keeps_vertex(lost));  // the field's voids remove it
  DesignSpaceOptions o;
  o.solid_vertices = {v};
  const DesignSpace held(mesh, o);
  const PostProcessResult kept = post_process(mesh, held, field, reference, 0.5);
  EXPECT_TRUE(keeps_vertex(kept));
  for (int e : around) EXPECT_EQ(kept.rounded.alpha[e], 1.0) << e;
  EXPECT_LE(kept.refit.max_residual, 1e-10);
}

}  // namespace
}  // namespace rbaa
