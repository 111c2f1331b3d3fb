#include "rbaa/sim/newton_solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "rbaa/error.hpp"

namespace rbaa {

namespace {

using Clock = std::chrono::steady_clock;

// The round-off floor (NewtonResult::roundoff_limited): this many non-improving steps in a row,
// each below kFloorFactor x the tolerance. Quadratic convergence and even slow linear convergence
// keep setting new minima; steps whose size is noise do not. Measured on configs/star.yaml at
// newton.tolerance 1e-12 (2.6e-12 m/s): step 7 wandered between 2.8e-12 and 2.5e-10 m/s for 100
// iterations.
// Steps count towards it below max(kFloorFactor x tolerance, kFloorRelative |x|_inf / h): the
// second term is 5e5 eps of the positions' own resolution per step (the star's floor sat at
// 1e4 eps), far below any real creep (a hinged vertex creeping at 1e-2 m/s is 1e-3 of it).
constexpr int kFloorWindow = 10;
constexpr double kFloorFactor = 1e4;
constexpr double kFloorRelative = 1e-10;

// Extrapolation (below): tried when a full step gained more than this fraction of its linear
// prediction (0.5 on a quadratic), doubling up to this factor.
constexpr double kExtrapolationRatio = 0.8;
constexpr double kMaxExtrapolation = 64.0;

// Line minimisation (minimise_along): probes until the bracket is this narrow relative to its
// best point, at most kMaxLineProbes energies.
constexpr double kLineTolerance = 1e-2;
constexpr int kMaxLineProbes = 20;
// ... or until a parabolic probe lowers the energy by what the parabola foretold, to this fraction.
constexpr double kParabolaAgreement = 1e-2;

// The parabola through (x1, f1), (x2, f2), (x3, f3) at u (Lagrange's form).
double parabola(double u, double x1, double f1, double x2, double f2, double x3, double f3) {
  return f1 * (u - x2) * (u - x3) / ((x1 - x2) * (x1 - x3)) +
         f2 * (u - x1) * (u - x3) / ((x2 - x1) * (x2 - x3)) +
         f3 * (u - x1) * (u - x2) / ((x3 - x1) * (x3 - x2));
}

// The minimum of phi(a) = E(step_at(a)) - E(x) in the bracket (0, 2 alpha), where phi(0) = 0,
// phi(alpha) = dE <= 0 and phi(2 alpha) = dE_far > dE (+inf for an invalid iterate, or NaN): Brent's
// method, a parabola through the three best points where it falls well inside the bracket and a
// golden-section step into the larger side where it does not. Where dE_far is finite the first
// probe is the parabola through 0, alpha and 2 alpha, the minimum itself where the energy is
// quadratic along the step (else a golden-section step); where it is V-shaped (lagged friction,
// below) the golden steps narrow the bracket. A parabolic
// probe that lowers the energy by what its parabola foretold ends the search. Returns the
// best fraction found and sets dE and trial to it; an invalid probe counts as no decrease. Every
// probe lies below 2 alpha, within the CCD bound.
template <class StepAt>
double minimise_along(IncrementalPotential& E, const Eigen::VectorXd& x, const StepAt& step_at,
                      double alpha, double dE_far, double& dE, Eigen::VectorXd& trial,
                      NewtonResult& result) {
  constexpr double kGolden = 0.3819660112501051;  // (3 - sqrt 5) / 2
  double lo = 0, hi = 2 * alpha;
  // The best point, the second best and the one before it, with their values; the far end is
  // used only if its energy is known.
  double best = alpha, second = 0, third = 0;
  double f_best = dE, f_second = 0, f_third = 0;
  if (std::isfinite(dE_far)) {
    second = hi;
    f_second = dE_far;
  }
  // The last two moves of the best point: the backtracking's last halving (2 alpha to alpha) and,
  // before it, the bracket's width, so that the first two probes may both be parabolic.
  double step = -alpha, step_before = hi - lo;
  for (int k = 0; k < kMaxLineProbes; ++k) {
    const double mid = 0.5 * (lo + hi);
    const double tol = 0.25 * kLineTolerance * best;
    if (hi - lo <= kLineTolerance * best) break;
    bool golden = true;
    if (std::abs(step_before) > tol) {
      // The parabola through (best, second, third), its vertex best + p / q.
      const double r = (best - second) * (f_best - f_third);
      double q = (best - third) * (f_best - f_second);
      double p = (best - third) * q - (best - second) * r;
      q = 2 * (q - r);
      if (q > 0) p = -p;
      q = std::abs(q);
      const double previous = step_before;
      step_before = step;
      // Taken only if it moves less than half the move before last and stays inside the bracket.
      if (std::abs(p) < std::abs(0.5 * q * previous) && p > q * (lo - best) && p < q * (hi - best)) {
        step = p / q;
        const double a = best + step;
        if (a - lo < 2 * tol || hi - a < 2 * tol) step = mid > best ? tol : -tol;
        golden = false;
      }
    }
    if (golden) {
      step_before = best >= mid ? lo - best : hi - best;
      step = kGolden * step_before;
    }
    const double a = best + (std::abs(step) >= tol ? step : (step > 0 ? tol : -tol));
    // The parabola's value where it sends the probe (NaN for a golden-section probe).
    const double predicted = golden ? std::numeric_limits<double>::quiet_NaN()
                                    : parabola(a, best, f_best, second, f_second, third, f_third);
    Eigen::VectorXd probe = step_at(a);
    ++result.line_search_probes;
    double phi = std::numeric_limits<double>::infinity();
    if (E.is_step_valid(x, probe)) phi = E.value_difference(x, probe);
    if (phi < f_best) {
      // The parabola foretold this decrease: the energy is quadratic along the step here, and
      // narrowing the bracket further would find the same point.
      const bool foretold = std::abs(phi - predicted) <= kParabolaAgreement * (f_best - predicted);
      (a >= best ? lo : hi) = best;
      third = second;
      f_third = f_second;
      second = best;
      f_second = f_best;
      best = a;
      f_best = phi;
      trial = std::move(probe);
      if (foretold) break;
    } else {
      (a < best ? lo : hi) = a;
      if (phi <= f_second || second == best) {
        third = second;
        f_third = f_second;
        second = a;
        f_second = phi;
      } else if (phi <= f_third || third == best || third == second) {
        third = a;
        f_third = phi;
      }
    }
  }
  dE = f_best;
  return best;
}

// Adds the wall time since `t0` to `to` and restarts `t0`.
void lap(Clock::time_point& t0, double& to) {
  const Clock::time_point t1 = Clock::now();
  to += std::chrono::duration<double>(t1 - t0).count();
  t0 = t1;
}

}  // namespace

// The chord step costs one gradient, one solve pair and a line search of energy differences; it
// takes at most a dozen halvings (a stale factor far from this step's Hessian, e.g. across an
// impact, gives a poor direction: then the Newton iterations do the work as without it).
double NewtonSolver::chord_step(IncrementalPotential& E, Eigen::VectorXd& x, NewtonResult& result) {
  constexpr double kNone = std::numeric_limits<double>::infinity();
  constexpr int kMaxChordHalvings = 12;
  Clock::time_point t0 = Clock::now();
  const Eigen::VectorXd g = E.gradient(x);
  lap(t0, result.gradient_seconds);
  if (!g.allFinite()) return kNone;
  const ChordSolve solve = [this](const Eigen::VectorXd& b) -> Eigen::VectorXd {
    if (solver_.has_factor()) return solver_.solve(b);
    return chord_solve_ ? chord_solve_(b) : Eigen::VectorXd();
  };
  Eigen::VectorXd dq = chord_frame_ ? chord_frame_(x, g, solve) : solve(g);
  dq = -dq;
  lap(t0, result.solve_seconds);
  if (dq.size() != g.size()) return kNone;
  E.zero_fixed(dq);
  if (!dq.allFinite() || !(g.dot(dq) < 0)) return kNone;
  if (transform_) {
    Eigen::VectorXd corrected = transform_(x, dq);
    E.zero_fixed(corrected);
    if (g.dot(corrected) < 0) dq = std::move(corrected);
  }
  double alpha = std::min(1.0, E.max_step_size(x, x + dq));
  double velocity = kNone;
  for (int halvings = 0; halvings <= kMaxChordHalvings && alpha > 0; ++halvings, alpha *= 0.5) {
    const Eigen::VectorXd trial = x + alpha * dq;
    if (E.is_step_valid(x, trial) && E.value_difference(x, trial) < 0) {
      x = trial;
      E.solution_changed(x);
      ++result.chord_steps;
      result.line_search_halvings += halvings;
      if (alpha == 1.0) velocity = dq.lpNorm<Eigen::Infinity>() / settings_.time_step;
      break;
    }
  }
  lap(t0, result.line_search_seconds);
  return velocity;
}

void NewtonResult::append(const NewtonResult& later) {
  iterations += later.iterations;
  exact_factor = later.exact_factor;
  step_velocity = later.step_velocity;
  line_search_halvings += later.line_search_halvings;
  line_search_probes += later.line_search_probes;
  symbolic_analyses += later.symbolic_analyses;
  projected_fallbacks += later.projected_fallbacks;
  extrapolations += later.extrapolations;
  chord_steps += later.chord_steps;
  roundoff_limited = later.roundoff_limited;
  floor_velocity = later.floor_velocity;
  gradient_seconds += later.gradient_seconds;
  assembly_seconds += later.assembly_seconds;
  factorization_seconds += later.factorization_seconds;
  solve_seconds += later.solve_seconds;
  line_search_seconds += later.line_search_seconds;
}

NewtonResult NewtonSolver::minimize(IncrementalPotential& E, Eigen::VectorXd& x,
                                    const std::string& context) {
  const double h = settings_.time_step;
  const double tol = settings_.velocity_tolerance;
  NewtonResult result;
  const int analyses_before = solver_.num_analyses();
  E.solution_changed(x);
  const bool chord = settings_.chord_first_step && factor_from_last_call_;
  // Until this call returns converged, solver_ may hold a factor of a failed iterate.
  factor_from_last_call_ = false;
  const double chord_velocity =
      chord ? chord_step(E, x, result) : std::numeric_limits<double>::infinity();
  // A whole chord step counts as a full step: the first factorisation may be the exact Hessian.
  double last_velocity = chord_velocity;
  bool last_full = std::isfinite(chord_velocity);
  // Round-off floor bookkeeping: the slowest step before the current run of non-improving ones,
  // and the length of that run.
  double best_velocity = std::numeric_limits<double>::infinity();
  int stalled = 0;

  const Eigen::SparseMatrix<double>* H_last = nullptr;
  Eigen::VectorXd carried_gradient;  // the gradient at x when the last step computed it
  for (int it = 0; it < settings_.max_iterations; ++it) {
    Clock::time_point t0 = Clock::now();
    // A step taken for its gradient (below) brings that gradient along.
    Eigen::VectorXd g = carried_gradient.size() ? std::move(carried_gradient) : E.gradient(x);
    carried_gradient = Eigen::VectorXd();
    lap(t0, result.gradient_seconds);
    // The sub-step costs a few products with the last Hessian and one energy difference.
    if (subspace_ && H_last && g.allFinite()) {
      Eigen::VectorXd ds = subspace_(x, g, *H_last);
      if (ds.size() == x.size()) E.zero_fixed(ds);
      if (ds.size() == x.size() && ds.allFinite() && g.dot(ds) < 0) {
        const Eigen::VectorXd trial = x + ds;
        if (E.max_step_size(x, trial) >= 1.0 && E.is_step_valid(x, trial) && E.value_difference(x, trial) < 0) {
          x = trial;
          E.solution_changed(x);
          g = E.gradient(x);
        }
      }
      lap(t0, result.line_search_seconds);
    }
    if (!g.allFinite()) {
      throw SolverError(context + ": non-finite energy gradient at Newton iteration " +
                        std::to_string(it));
    }
    HessianKind kind = (last_full && last_velocity < settings_.exact_hessian_factor * tol)
                           ? HessianKind::kExact
                           : HessianKind::kProjected;
    const Eigen::SparseMatrix<double>* H = &E.hessian(x, kind);
    H_last = H;
    lap(t0, result.assembly_seconds);
    // Read after assembling: contact between bodies changes the pattern with the active pairs.
    bool ok = solver_.factorize(*H, E.hessian_pattern().pattern_version());
    lap(t0, result.factorization_seconds);
    if (!ok && kind == HessianKind::kExact) {
      ++result.projected_fallbacks;
      kind = HessianKind::kProjected;
      H = &E.hessian(x, kind);
      H_last = H;
      lap(t0, result.assembly_seconds);
      ok = solver_.factorize(*H, E.hessian_pattern().pattern_version());
      lap(t0, result.factorization_seconds);
    }
    if (!ok) {
      throw SolverError(context + ": the projected Hessian is not positive definite at Newton "
                        "iteration " + std::to_string(it));
    }
    // Exactly zero at fixed dofs already (identity rows, zero gradient there); kept so by
    // construction, like the transformed and subspace steps below.
    Eigen::VectorXd dq = -solver_.solve(g);
    E.zero_fixed(dq);
    lap(t0, result.solve_seconds);
    ++result.iterations;
    // A projected Hessian that the projection left unchanged is the exact one.
    result.exact_factor =
        kind == HessianKind::kExact || !E.hessian_pattern().projection_active();
    const double velocity = dq.lpNorm<Eigen::Infinity>() / h;
    result.step_velocity = velocity;
    if (!std::isfinite(velocity)) {
      throw SolverError(context + ": non-finite Newton step at iteration " + std::to_string(it));
    }
    if (velocity < tol) {
      factor_from_last_call_ = true;
      result.symbolic_analyses = solver_.num_analyses() - analyses_before;
      return result;
    }
    const bool floor_regime =
        velocity < std::max(kFloorFactor * tol, kFloorRelative * x.lpNorm<Eigen::Infinity>() / h);
    if (floor_regime) {
      if (velocity < best_velocity) {
        best_velocity = velocity;
        stalled = 0;
      } else if (++stalled >= kFloorWindow) {
        result.roundoff_limited = true;
        result.floor_velocity = best_velocity;
        factor_from_last_call_ = true;
        result.symbolic_analyses = solver_.num_analyses() - analyses_before;
        return result;
      }
    } else {
      stalled = 0;
    }

    // With a transform, the line search backtracks along the transformed path x + f(x, a dq)
    // rather than along the chord a f(x, dq): a fraction of a finite rotation's chord is no
    // rotation (it shrinks the body by (1 - a) a theta^2 / 2), and at Y = 1e13 that shrinkage
    // alone can cost more than the step gains, so halving the chord needed ~20 halvings per
    // iteration where a body spun hard during a point impact.
    Eigen::VectorXd raw;  // the untransformed step, kept only when the line search follows f
    auto transformed = [&](const Eigen::VectorXd& step) {
      Eigen::VectorXd t = transform_(x, step);
      E.zero_fixed(t);
      return t;
    };
    if (transform_) {
      Eigen::VectorXd corrected = transformed(dq);
      if (g.dot(corrected) < 0) {
        raw = std::move(dq);
        dq = std::move(corrected);
      }
    }
    auto step_at = [&](double a) -> Eigen::VectorXd {
      if (raw.size() == 0 || a == 1.0) return x + a * dq;
      return x + transformed(a * raw);
    };

    // Line search: start at the largest admissible fraction (CCD), halve until E decreases.
    double alpha = E.max_step_size(x, x + dq);
    const double alpha0 = alpha;
    Eigen::VectorXd trial;
    int halvings = 0;
    // Where the step is this small, the energy change of a stiff barrier's step (~1e-27 J for
    // 1e-14 m at d ~ 4e-6 m) lies far below the energy's rounding (~1e-21 J): value differences
    // are noise, the search halves at random and Newton stalled at ~1e-11 m/s, 1e3 x above its
    // usual floor. There a full admissible step that lowers the gradient's norm is taken instead.
    bool gradient_accepted = false;
    double dE = 0;  // E(trial) - E(x) of the step taken (for extrapolation and the callback)
    double dE_far = 0;  // after backtracking, E - E(x) at twice the fraction taken (+inf: invalid)
    if (floor_regime && alpha == 1.0) {
      trial = step_at(1.0);
      if (E.is_step_valid(x, trial) && !((dE = E.value_difference(x, trial)) <= 0)) {
        Eigen::VectorXd g_trial = E.gradient(trial);
        if (g_trial.norm() < g.norm()) {
          gradient_accepted = true;
          carried_gradient = std::move(g_trial);
        }
      }
    }
    for (; !gradient_accepted; ++halvings) {
      if (halvings > settings_.max_line_search_halvings) {
        std::ostringstream msg;
        msg << context << ": line search failed at Newton iteration " << it
            << " (no decrease of the incremental potential along a step of velocity " << velocity
            << " m/s; tolerance " << tol << " m/s)";
        throw SolverError(msg.str());
      }
      trial = step_at(alpha);
      double value = std::numeric_limits<double>::infinity();
      if (E.is_step_valid(x, trial) && (value = E.value_difference(x, trial)) <= 0) {
        dE = value;
        break;
      }
      dE_far = value;
      alpha *= 0.5;
    }
    result.line_search_halvings += halvings;
    // Line minimisation after backtracking: the first halving that lowers the energy lands
    // anywhere between the minimum along the step and twice it, and where the energy along the
    // step is V-shaped rather than quadratic it lands near the far end every time. Lagged
    // friction does that: a sliding contact's potential is linear in the slip, so the Newton
    // step of a sliding body sees only its inertia and overshoots the point where the slip
    // stops (within eps_v h) by its whole length. The cube stack's striker (10164 tets a cube,
    // friction 0.4) crossed that valley back and forth for 100 iterations at 1/512 of each
    // step (1.9 m/s, no progress). Brent's search of the bracket [0, 2 alpha] (alpha lowers the
    // energy, 2 alpha did not) keeps the lowest energy found, so it never loses what the
    // backtracking gained. It took 847 probes where golden-section search took 1316 (the stack
    // at 1500 tets the object, 0.3 s: 107 searches, the same 1479 Newton iterations).
    if (!gradient_accepted && halvings > 0) {
      alpha = minimise_along(E, x, step_at, alpha, dE_far, dE, trial, result);
    }
    // Extrapolation: a full step whose energy change is nearly its linear prediction g . dq (a
    // Newton step on a quadratic gains half of it) went where the energy is flatter than the
    // Hessian says: the PSD projection of contact pairs' Hessians adds curvature that the
    // energy does not have. Four cubes stacked on a floor crept at 1e-5 .. 1e-3 m/s for 30
    // iterations (47 in all) taking such steps; doubling the step while the energy keeps
    // falling and CCD admits it took 13. Only tried after a full, energy-decreasing step, and a
    // longer step is kept only if it lowers the energy further, so convergence is unchanged. Not
    // at the round-off floor, where energy differences are noise.
    if (!floor_regime && halvings == 0 && alpha0 == 1.0) {
      const double slope = g.dot(dq);
      while (alpha < kMaxExtrapolation && dE < 0 && dE / slope > kExtrapolationRatio) {
        Eigen::VectorXd longer = step_at(2 * alpha);
        if (E.max_step_size(x, longer) < 1.0 || !E.is_step_valid(x, longer)) break;
        const double dE_longer = E.value_difference(x, longer);
        if (!(dE_longer < dE)) break;
        alpha *= 2;
        dE = dE_longer;
        trial = std::move(longer);
        ++result.extrapolations;
      }
    }
    lap(t0, result.line_search_seconds);
    if (callback_) {
      NewtonIteration info;
      info.iteration = it;
      info.exact_hessian = kind == HessianKind::kExact;
      info.step_velocity = velocity;
      info.max_step_fraction = alpha0;
      info.step_fraction = alpha;
      info.energy_change = dE;
      info.directional_derivative = g.dot(dq);  // of the full (transformed) step
      dq.cwiseAbs().maxCoeff(&info.largest_dof);
      callback_(context, info);
    }
    x = trial;
    E.solution_changed(x);
    last_velocity = velocity;
    last_full = halvings == 0 && alpha0 == 1.0;
  }
  std::ostringstream msg;
  msg << context << ": Newton did not converge in " << settings_.max_iterations
      << " iterations (last step velocity " << result.step_velocity << " m/s, tolerance " << tol
      << " m/s)";
  throw SolverError(msg.str());
}

}  // namespace rbaa
