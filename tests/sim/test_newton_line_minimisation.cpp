// Newton's line minimisation after backtracking (newton_solver.cpp): an energy that is V-shaped
// along the Newton step, as lagged friction's is along a sliding body's slip (linear in the slip,
// curved only within eps_v h of zero). The Newton step from the sliding side sees only the
// quadratic term's curvature and overshoots the valley by its whole length; the first halving that
// lowers the energy lands across the valley, and plain backtracking crossed it back and forth (the
// cube stack's striker at the paper's 10164 tets a cube: 100 iterations at 1/512 of each step).
// Minimising along the step lands near the valley's floor.
// The later tests run the search (Brent's: parabolas, golden-section steps, a minimum step, the
// stop on a foretold gain or a narrow bracket) on given functions along the step.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <utility>
#include <vector>

#include "rbaa/error.hpp"
#include "rbaa/sim/form.hpp"
#include "rbaa/sim/incremental_potential.hpp"
#include "rbaa/sim/newton_solver.hpp"
#include "rbaa/sim/sparse_hessian.hpp"

namespace rbaa {
namespace {

// E(q) = m/2 |q - target|^2 + c sqrt((q_0 - a)^2 + eps^2): a smoothed |q_0 - a| with weight c
// (the friction force) far above m |target_0 - a| (what the quadratic term pulls with).
class ValleyForm : public Form {
 public:
  ValleyForm(Eigen::VectorXd target, double m, double c, double a, double eps)
      : target_(std::move(target)), m_(m), c_(c), a_(a), eps_(eps) {}
  const char* name() const override { return "valley"; }
  double value(const Eigen::VectorXd& q) const override {
    const double u = q[0] - a_;
    return 0.5 * m_ * (q - target_).squaredNorm() + c_ * std::sqrt(u * u + eps_ * eps_);
  }
  void add_gradient(const Eigen::VectorXd& q, double scale, Eigen::VectorXd& grad) const override {
    grad += scale * m_ * (q - target_);
    const double u = q[0] - a_;
    grad[0] += scale * c_ * u / std::sqrt(u * u + eps_ * eps_);
  }
  void add_hessian(const Eigen::VectorXd& q, double scale, HessianKind, SparseHessian& H) const override {
    for (int v = 0; v < q.size() / 3; ++v) H.vertex_block(v) += scale * m_ * Eigen::Matrix3d::Identity();
    const double u = q[0] - a_;
    H.vertex_block(0)(0, 0) += scale * c_ * eps_ * eps_ / std::pow(u * u + eps_ * eps_, 1.5);
  }

 private:
  Eigen::VectorXd target_;
  double m_, c_, a_, eps_;
};

// The valley's minimum along q_0 (the other coordinates at their target, 0): m (q_0 - 1) +
// c q_0 / sqrt(q_0^2 + eps^2) = 0, by bisection.
double valley_minimum(double m, double c, double eps) {
  double lo = -1, hi = 1;
  for (int k = 0; k < 200; ++k) {
    const double u = 0.5 * (lo + hi);
    (m * (u - 1) + c * u / std::sqrt(u * u + eps * eps) > 0 ? hi : lo) = u;
  }
  return lo;
}

// The valley over one tet's 12 coordinates, the quadratic term pulling q_0 towards +1 (the
// valley holds it near 0); Newton starts on the sliding side, q_0 = 1, where the valley's
// curvature is c eps^2.
struct Valley {
  Valley(double m, double c, double eps)
      : T((Tets(1, 4) << 0, 1, 2, 3).finished()), hessian(T, 4),
        form(Eigen::VectorXd::Unit(12, 0), m, c, 0, eps), E(hessian) {
    E.add(form, 1.0);
  }
  static Eigen::VectorXd start() { return Eigen::VectorXd::Unit(12, 0); }
  Tets T;
  SparseHessian hessian;
  ValleyForm form;
  IncrementalPotential E;
};

NewtonSettings unit_step_settings() {
  NewtonSettings settings;
  settings.time_step = 1;
  return settings;
}

// One Newton iteration from q_0 = 1 (the solver then reports no convergence and leaves x at its
// first iterate): the step moves q_0 alone, so the minimum along it is the valley's minimum.
double after_one_iteration(double m, double c, double eps) {
  Valley valley(m, c, eps);
  NewtonSettings settings = unit_step_settings();
  settings.max_iterations = 1;
  NewtonSolver newton(settings);
  Eigen::VectorXd x = Valley::start();
  EXPECT_THROW(newton.minimize(valley.E, x, "valley"), SolverError);
  return x[0];
}

// The first iterate lies within 2 % of the first step's length of the minimum along it (the
// search's bracket is narrowed to 1 % of the fraction taken). c = 1.5 m: the full step (to
// q_0 = -0.5) raises the energy and its half (0.25) lowers it, so one halving, where plain
// backtracking stops at 0.25; c = 1000 m: nine halvings, plain backtracking stops at -0.95.
TEST(NewtonLineMinimisation, TheFirstIterateIsTheMinimumAlongTheStep) {
  const double m = 1, eps = 1e-6;
  for (double c : {1.5, 1e3}) {
    const double x = after_one_iteration(m, c, eps), best = valley_minimum(m, c, eps);
    std::printf("c = %g: first iterate %.6f, minimum %.3e\n", c, x, best);
    EXPECT_LE(std::abs(x - best), 0.02 * std::abs(1 - best)) << "c = " << c;
  }
}

TEST(NewtonLineMinimisation, CrossesAFrictionLikeValleyInFewIterations) {
  const double m = 1, c = 1e3, eps = 1e-6;
  Valley valley(m, c, eps);
  NewtonSettings settings = unit_step_settings();
  settings.velocity_tolerance = 1e-12;
  NewtonSolver newton(settings);
  Eigen::VectorXd x = Valley::start();
  const NewtonResult r = newton.minimize(valley.E, x, "valley");
  std::printf("%d Newton iterations, %d halvings, %d line-minimisation probes, q_0 = %.3e\n", r.iterations,
              r.line_search_halvings, r.line_search_probes, x[0]);
  // The minimum, q_0 ~ m eps / c = 1e-9; the other coordinates stay at their target, 0.
  EXPECT_NEAR(x[0], valley_minimum(m, c, eps), 1e-12);
  EXPECT_LE(x.tail(11).lpNorm<Eigen::Infinity>(), 1e-12);
  EXPECT_GT(r.line_search_probes, 0);
  // Plain backtracking: 23 iterations here (256 halvings); with the line minimisation 6 (27
  // halvings, 24 probes; measured 2026-11-27).
  EXPECT_LE(r.iterations, 10);
}

// E(q) = k/2 |q - target|^2 whose Hessian reads k/3: the Newton step overshoots the minimum
// threefold, its full length raises the energy and its half lowers it, and the minimum along it
// lies at a third. The energy is quadratic along the step, so the parabola through 0, 1/2 and 1
// (the first probe) is the minimum itself.
class UnderestimatedQuadraticForm : public Form {
 public:
  UnderestimatedQuadraticForm(Eigen::VectorXd target, double k) : target_(std::move(target)), k_(k) {}
  const char* name() const override { return "underestimated quadratic"; }
  double value(const Eigen::VectorXd& q) const override {
    return 0.5 * k_ * (q - target_).squaredNorm();
  }
  void add_gradient(const Eigen::VectorXd& q, double scale, Eigen::VectorXd& grad) const override {
    grad += scale * k_ * (q - target_);
  }
  void add_hessian(const Eigen::VectorXd& q, double scale, HessianKind, SparseHessian& H) const override {
    for (int v = 0; v < q.size() / 3; ++v) H.vertex_block(v) += scale * k_ / 3 * Eigen::Matrix3d::Identity();
  }

 private:
  Eigen::VectorXd target_;
  double k_;
};

// Golden-section search took 12 probes here (to narrow its bracket to 1 % of the best point's
// fraction) and landed 5e-4 of the step from the minimum; Brent's first probe is the minimum, and
// the energy it finds is the one the parabola foretold, which ends the search (without that stop,
// Brent narrowed the bracket in 3 more probes).
TEST(NewtonLineMinimisation, AQuadraticAlongTheStepTakesOneProbe) {
  const Tets T = (Tets(1, 4) << 0, 1, 2, 3).finished();
  SparseHessian hessian(T, 4);
  const Eigen::VectorXd target = Eigen::VectorXd::LinSpaced(12, -1.0, 2.0);
  UnderestimatedQuadraticForm form(target, 5.0);
  IncrementalPotential E(hessian);
  E.add(form, 1.0);
  NewtonSettings settings = unit_step_settings();
  settings.velocity_tolerance = 1e-12;
  NewtonSolver newton(settings);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(12);
  const NewtonResult r = newton.minimize(E, x, "quadratic");
  std::printf("%d Newton iterations, %d halvings, %d probes, |x - minimum| = %.3e\n", r.iterations,
              r.line_search_halvings, r.line_search_probes, (x - target).norm());
  EXPECT_LE((x - target).norm(), 1e-12 * target.norm());
  EXPECT_EQ(r.line_search_halvings, 1);  // one search: the next step is zero
  EXPECT_EQ(r.line_search_probes, 1);
}

// The search on given functions along the step. E(q) = phi(q_0) + |q_1..11|^2 / 2 from q = 0, with
// a Hessian that reads -phi'(0) in q_0: the Newton step moves q_0 alone, by 1, so the fraction a of
// the step is q_0 = a and the energy along it is phi(a) - phi(0). The form records every fraction
// the line search asks about; max_fraction stands for CCD's bound (the first fraction tried).
class AlongStepForm : public Form {
 public:
  AlongStepForm(std::function<double(double)> phi, std::function<double(double)> slope,
                double max_fraction, std::vector<std::pair<double, double>>& asked)
      : phi_(std::move(phi)),
        slope_(std::move(slope)),
        max_fraction_(max_fraction),
        asked_(asked) {}
  const char* name() const override { return "along the step"; }
  double value(const Eigen::VectorXd& q) const override {
    return phi_(q[0]) + 0.5 * q.tail(q.size() - 1).squaredNorm();
  }
  double value_difference(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const override {
    const double d = value(q1) - value(q0);
    asked_.emplace_back(q1[0], d);
    return d;
  }
  void add_gradient(const Eigen::VectorXd& q, double scale, Eigen::VectorXd& grad) const override {
    grad.tail(q.size() - 1) += scale * q.tail(q.size() - 1);
    grad[0] += scale * slope_(q[0]);
  }
  void add_hessian(const Eigen::VectorXd& q, double scale, HessianKind,
                   SparseHessian& H) const override {
    for (int v = 0; v < q.size() / 3; ++v) H.vertex_block(v) += scale * Eigen::Matrix3d::Identity();
    H.vertex_block(0)(0, 0) += scale * (-slope_(0) - 1);
  }
  double max_step_size(const Eigen::VectorXd&, const Eigen::VectorXd&) const override {
    return max_fraction_;
  }

 private:
  std::function<double(double)> phi_, slope_;
  double max_fraction_;
  std::vector<std::pair<double, double>>& asked_;
};

// One Newton iteration along phi: the fractions and energies the backtracking tried (the last
// one lowers the energy: alpha), the line minimisation's probes, and the fraction taken.
struct LineSearch {
  std::vector<std::pair<double, double>> backtracking, probes;
  double taken = 0;
  double alpha() const { return backtracking.back().first; }
};

LineSearch search_along(std::function<double(double)> phi, std::function<double(double)> slope,
                        double max_fraction = 1.0) {
  const Tets T = (Tets(1, 4) << 0, 1, 2, 3).finished();
  SparseHessian hessian(T, 4);
  std::vector<std::pair<double, double>> asked;
  AlongStepForm form(std::move(phi), std::move(slope), max_fraction, asked);
  IncrementalPotential E(hessian);
  E.add(form, 1.0);
  NewtonSettings settings = unit_step_settings();
  settings.max_iterations = 1;
  NewtonSolver newton(settings);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(12);
  EXPECT_THROW(newton.minimize(E, x, "along the step"), SolverError);
  LineSearch s;
  std::size_t k = 0;
  while (k < asked.size() && !(asked[k].second <= 0)) s.backtracking.push_back(asked[k++]);
  if (k < asked.size()) s.backtracking.push_back(asked[k++]);
  s.probes.assign(asked.begin() + k, asked.end());
  s.taken = x[0];
  EXPECT_LE(x.tail(11).lpNorm<Eigen::Infinity>(), 0.0);
  return s;
}

// newton_solver.cpp's kLineTolerance: the search ends once its bracket is this narrow relative to
// the best fraction, and no probe comes nearer than a quarter of that to a point already known.
constexpr double kLineTolerance = 1e-2;
constexpr double kGolden = 0.3819660112501051;  // (3 - sqrt 5) / 2

// Brent's bracket, replayed from the probes: it starts as [0, 2 alpha] around alpha; the best
// point so far lies inside, every other point known lies on or outside it (so the bracket runs
// from the nearest known point below the best to the nearest above). Each probe lies strictly
// inside the bracket and at least the minimum step, kLineTolerance / 4 of the best fraction, from
// every known point (Brent's minimum step); the fraction taken is the lowest energy found.
void expect_brent_invariants(const LineSearch& s) {
  const double alpha = s.alpha();
  std::vector<double> known = {0.0, 2 * alpha, alpha};
  double best = alpha, f_best = s.backtracking.back().second;
  for (std::size_t k = 0; k < s.probes.size(); ++k) {
    const auto [a, phi] = s.probes[k];
    double lo = 0, hi = 2 * alpha, nearest = std::numeric_limits<double>::infinity();
    for (double p : known) {
      if (p < best) lo = std::max(lo, p);
      if (p > best) hi = std::min(hi, p);
      nearest = std::min(nearest, std::abs(a - p));
    }
    EXPECT_GT(a, lo) << "probe " << k;
    EXPECT_LT(a, hi) << "probe " << k;
    EXPECT_GE(nearest, (1 - 1e-12) * 0.25 * kLineTolerance * best)
        << "probe " << k << " at " << a << ", best " << best << " (bracket " << lo << " .. " << hi
        << ")";
    known.push_back(a);
    if (phi < f_best) {
      best = a;
      f_best = phi;
    }
  }
  EXPECT_EQ(s.taken, best);
}

// A continuous piecewise-linear function through the knots (x_i, y_i), x increasing: a valley
// with kinks. The slope at a knot is the next segment's.
struct PiecewiseLinear {
  std::vector<double> x, y;
  std::size_t segment(double s) const {
    std::size_t i = 0;
    while (i + 2 < x.size() && s >= x[i + 1]) ++i;
    return i;
  }
  double slope(double s) const {
    const std::size_t i = segment(s);
    return (y[i + 1] - y[i]) / (x[i + 1] - x[i]);
  }
  double operator()(double s) const {
    const std::size_t i = segment(s);
    return s == x[i] ? y[i] : y[i] + (s - x[i]) * slope(s);
  }
};

// Linear up to c, quadratic (s - m)^2 / 2 beyond (continuous slope): the step's full length raises
// the energy, its half lowers it. The first probe, the parabola through 0, 1/2 and 1, misses the
// minimum (0 lies on the linear stretch) and lands past c, lowering the energy by other than its
// parabola foretold; then the three best points (that probe, 1/2 and 1) lie where the energy is
// quadratic, so the next parabolic probe is the minimum itself, and the gain it finds is the one
// its parabola foretold, which ends the search: two probes. A parabola foretold wrongly (a term of
// Lagrange's form in x3 or f3, which vanish where the third point is 0 with value 0 as in the first
// probe) takes two more.
TEST(NewtonLineMinimisation, AQuadraticPastALinearStretchEndsAtItsMinimum) {
  const double c = 0.25, m = 0.45;
  const auto phi = [=](double s) {
    return s >= c ? 0.5 * (s - m) * (s - m) : 0.5 * (c - m) * (c - m) + (c - m) * (s - c);
  };
  const auto slope = [=](double s) { return s >= c ? s - m : c - m; };
  const LineSearch s = search_along(phi, slope);
  ASSERT_EQ(s.backtracking.size(), 2u);  // 1 raises the energy, 1/2 lowers it
  ASSERT_EQ(s.probes.size(), 2u);
  EXPECT_GT(s.probes[0].first, c);
  EXPECT_GT(std::abs(s.probes[0].first - m), 0.01);
  EXPECT_NEAR(s.probes[1].first, m, 1e-12);
  EXPECT_NEAR(s.taken, m, 1e-12);
  expect_brent_invariants(s);
}

// A quartic (s - m)^4: no parabola through three of its points is its own, so the search narrows
// the bracket to kLineTolerance of the best fraction, which then holds the minimum; on the way the
// parabola's vertex falls within twice the minimum step of the bracket's lower end (0.68 of one
// step from it), and the probe goes the minimum step from the best point instead. Moving the probe
// to the vertex (the end test read from 0 rather than the bracket's end, or the test made on the
// point mirrored about the best one) or dropping the minimum step (tol of the wrong sign) probes
// within the minimum step of a known point.
TEST(NewtonLineMinimisation, AQuarticsProbesKeepTheMinimumStepApart) {
  const double m = 0.4635;
  const LineSearch s = search_along([=](double x) { return std::pow(x - m, 4); },
                                    [=](double x) { return 4 * std::pow(x - m, 3); });
  ASSERT_EQ(s.backtracking.size(), 2u);
  EXPECT_GE(s.probes.size(), 2u);
  expect_brent_invariants(s);
  EXPECT_LE(std::abs(s.taken - m), kLineTolerance * s.taken);
}

// An asymmetric valley, steep on the near side and flattening on the far one (its far branch
// concave, slopes 22.5 then 3.6), its floor at 1/4: the first probe (the parabola through 0, 1/2
// and 1) lands on the far branch, on the line through 1/2 and 1; the three best points are
// collinear, so the next probe is a golden-section step into the larger side, which lands on the
// near branch. The parabola through the three best points is then concave: its vertex, a maximum,
// lies beyond the bracket, and the search takes a golden-section step into the larger side again,
// not the minimum step towards the middle (as it would if vertices beyond the bracket's upper end
// were admitted).
TEST(NewtonLineMinimisation, AParabolaBeyondTheBracketGivesWayToAGoldenStep) {
  const PiecewiseLinear valley{{0, 0.25, 0.45, 1}, {0, -6, -1.5, 0.5}};
  const LineSearch s = search_along(valley, [&](double x) { return valley.slope(x); });
  ASSERT_EQ(s.backtracking.size(), 2u);
  ASSERT_GE(s.probes.size(), 3u);
  // The parabola through (0, 0), (1/2, f(1/2)) and (1, f(1)): its vertex at
  // 1/2 - f(1) / (4 (f(1) - 2 f(1/2))).
  const double f_one = s.backtracking.front().second, f_half = s.backtracking.back().second;
  EXPECT_NEAR(s.probes[0].first, 0.5 - f_one / (4 * (f_one - 2 * f_half)), 1e-12);
  EXPECT_NEAR(s.probes[1].first, (1 - kGolden) * s.probes[0].first, 1e-12);
  // The parabola through the three best points, (a1, f1), (a0, f0) and (1/2, f(1/2)): concave.
  const double a1 = s.probes[1].first, f1 = s.probes[1].second, a0 = s.probes[0].first,
               f0 = s.probes[0].second;
  const double s10 = (f0 - f1) / (a0 - a1), s0h = (f_half - f0) / (0.5 - a0);
  ASSERT_LT(s0h, s10);
  // Its vertex lies where its slope, s10 at (a1 + a0) / 2 falling linearly to s0h at
  // (a0 + 1/2) / 2, is 0:
  const double u = 0.5 * (a1 + a0), v = 0.5 * (a0 + 0.5);
  ASSERT_GT(u + s10 * (v - u) / (s10 - s0h), a0);  // beyond the bracket [0, a0]
  EXPECT_NEAR(s.probes[2].first, (1 - kGolden) * a1, 1e-12);
  expect_brent_invariants(s);
  EXPECT_LE(std::abs(s.taken - 0.25), kLineTolerance * s.taken);
}

// The stop at a bracket exactly kLineTolerance of the best fraction wide, where every number the
// search computes is exact in binary: the valley's floor is alpha = 25/64 (CCD's bound 2 alpha
// raises the energy); the parabola through 0, alpha and 2 alpha (energies 0, -99 w, 2 w) sends the
// first probe to alpha - alpha / 200 = alpha - 1/512, and the parabola through the three best
// points (the energy there is 101 w / 13200 above the floor, w = 13200 / 2^14) the second to
// alpha + 1/512; both raise the energy, and the bracket between them is 4/1024 = kLineTolerance
// alpha wide, which ends the search at alpha (at "<": a third probe). The near side's slope, -256,
// makes the Newton step exactly 1 (its Cholesky factor is 16).
TEST(NewtonLineMinimisation, ABracketOnePercentOfTheBestFractionWideEndsTheSearch) {
  const double alpha = 25.0 / 64, d = alpha / 200, w = 825.0 / 1024, floor = -99 * w;
  const PiecewiseLinear valley{{0, 0.25, alpha - d, alpha, alpha + d, 2 * alpha},
                               {0, -64, floor + 101.0 / 16384, floor, floor + 0.125, 2 * w}};
  ASSERT_EQ(d, 1.0 / 512);
  ASSERT_EQ((alpha + d) - (alpha - d), kLineTolerance * alpha);
  const LineSearch s = search_along(
      valley, [&](double x) { return valley.slope(x); }, 2 * alpha);
  ASSERT_EQ(s.backtracking.size(), 2u);
  EXPECT_EQ(s.alpha(), alpha);
  ASSERT_EQ(s.probes.size(), 2u);
  EXPECT_EQ(s.probes[0].first, alpha - d);
  EXPECT_EQ(s.probes[1].first, alpha + d);
  EXPECT_EQ(s.taken, alpha);
  expect_brent_invariants(s);
}

}  // namespace
}  // namespace rbaa
