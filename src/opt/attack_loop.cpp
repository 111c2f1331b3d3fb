#include "rbaa/opt/attack_loop.hpp"

#include <nlohmann/json.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include "rbaa/error.hpp"
#include "rbaa/io/atomic_file.hpp"
#include "rbaa/io/number_text.hpp"
#include "rbaa/opt/smoothed_gradient.hpp"

namespace rbaa {
namespace {

nlohmann::json to_json(const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); }

Eigen::VectorXd vector_from(const nlohmann::json& j) {
  const std::vector<double> v = j.get<std::vector<double>>();
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

// `seconds` stays last: it is the one column that differs between equal runs.
const char* kProgressColumns[] = {
    "iteration",  "objective",           "trajectory_term",  "moment_term",       "gap_m",
    "com_gap_m",  "max_moment_residual", "occupancy_weight", "occupancy_penalty", "repair_share",
    "components", "grey_fraction",       "seconds"};

}  // namespace

void save_checkpoint(const std::string& path, const AttackCheckpoint& c) {
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& r : c.progress) {
    rows.push_back({r.iteration, r.objective, r.trajectory_term, r.moment_term, r.gap, r.com_gap,
                    r.max_moment_residual, r.seconds, r.occupancy_weight, r.occupancy_penalty,
                    r.repair_share, r.components, r.grey_fraction});
  }
  const nlohmann::json j = {{"format", "rbaa-attack-checkpoint-1"},
                            {"fingerprint", c.fingerprint},
                            {"iteration", c.iteration},
                            {"theta", to_json(c.theta)},
                            {"evaluated_theta", to_json(c.evaluated_theta)},
                            {"adam", {{"m", to_json(c.adam.m)}, {"v", to_json(c.adam.v)}, {"steps", c.adam.steps}}},
                            {"progress", rows},
                            {"forward_seconds", c.forward_seconds},
                            {"adjoint_seconds", c.adjoint_seconds},
                            {"elapsed_seconds", c.elapsed_seconds},
                            {"best_iteration", c.best_iteration},
                            {"best_theta", to_json(c.best_theta)}};
  // nlohmann writes the shortest decimal that reads back to the same double.
  write_file_atomically(path, [&](std::ostream& out) { out << j.dump() << "\n"; });
}

namespace {

// The checkpoint as written, not yet checked against a run.
AttackCheckpoint read_checkpoint(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open checkpoint");
  AttackCheckpoint c;
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    if (j.at("format") != "rbaa-attack-checkpoint-1") throw InputError(path + ": not an rbaa attack checkpoint");
    c.fingerprint = j.at("fingerprint").get<std::string>();
    c.iteration = j.at("iteration").get<int>();
    c.theta = vector_from(j.at("theta"));
    c.evaluated_theta = j.contains("evaluated_theta") ? vector_from(j.at("evaluated_theta")) : Eigen::VectorXd();
    c.adam.m = vector_from(j.at("adam").at("m"));
    c.adam.v = vector_from(j.at("adam").at("v"));
    c.adam.steps = j.at("adam").at("steps").get<std::int64_t>();
    for (const auto& r : j.at("progress")) {
      ProgressRow row{r.at(0).get<int>(),    r.at(1).get<double>(), r.at(2).get<double>(),
                      r.at(3).get<double>(), r.at(4).get<double>(), r.at(5).get<double>(),
                      r.at(6).get<double>(), r.at(7).get<double>()};
      // Rows of older checkpoints end at `seconds`.
      if (r.size() >= 13) {
        row.occupancy_weight = r.at(8).get<double>();
        row.occupancy_penalty = r.at(9).get<double>();
        row.repair_share = r.at(10).get<double>();
        row.components = r.at(11).get<int>();
        row.grey_fraction = r.at(12).get<double>();
      }
      c.progress.push_back(row);
    }
    c.forward_seconds = j.at("forward_seconds").get<double>();
    c.adjoint_seconds = j.at("adjoint_seconds").get<double>();
    c.elapsed_seconds = j.at("elapsed_seconds").get<double>();
    // Older checkpoints did not keep the best design: then none is known.
    if (j.contains("best_iteration") && j.contains("best_theta")) {
      c.best_iteration = j.at("best_iteration").get<int>();
      c.best_theta = vector_from(j.at("best_theta"));
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path + ": malformed checkpoint (" + e.what() + ")");
  }
  return c;
}

void check_checkpoint(const AttackCheckpoint& c, const std::string& path,
                      const std::string& expected_fingerprint, int expected_size) {
  if (c.fingerprint != expected_fingerprint) {
    throw InputError(path + ": checkpoint belongs to another scene or other settings (fingerprint " +
                     c.fingerprint + ", expected " + expected_fingerprint + "); remove it or drop --resume");
  }
  if (c.theta.size() != expected_size || (c.adam.m.size() != 0 && c.adam.m.size() != expected_size) ||
      c.adam.v.size() != c.adam.m.size() || static_cast<int>(c.progress.size()) != c.iteration ||
      c.best_iteration >= c.iteration ||
      (c.best_iteration >= 0 && c.best_theta.size() != expected_size)) {
    throw InputError(path + ": checkpoint does not fit this design (sizes differ)");
  }
}

}  // namespace

AttackCheckpoint load_checkpoint(const std::string& path, const std::string& expected_fingerprint,
                                 int expected_size) {
  AttackCheckpoint c = read_checkpoint(path);
  check_checkpoint(c, path, expected_fingerprint, expected_size);
  return c;
}

void write_progress_csv(const std::string& path, const std::vector<ProgressRow>& rows) {
  write_file_atomically(path, [&](std::ostream& out) {
    for (size_t i = 0; i < std::size(kProgressColumns); ++i) out << (i ? "," : "") << kProgressColumns[i];
    out << "\n";
    for (const auto& r : rows) {
      out << r.iteration << ',' << exact(r.objective) << ',' << exact(r.trajectory_term) << ','
          << exact(r.moment_term) << ',' << exact(r.gap) << ',' << exact(r.com_gap) << ','
          << exact(r.max_moment_residual) << ',' << exact(r.occupancy_weight) << ','
          << exact(r.occupancy_penalty) << ',' << exact(r.repair_share) << ',' << r.components
          << ',' << exact(r.grey_fraction) << ',' << exact(r.seconds) << "\n";
    }
  });
}

MetricTangentProjector::MetricTangentProjector(
    const Eigen::Matrix<double, 10, Eigen::Dynamic>& J,
    const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& precondition)
    : J_(J), W_(J.cols(), 10) {
  for (int r = 0; r < 10; ++r) W_.col(r) = precondition(J.row(r).transpose());
  JW_.compute(J_ * W_);
}

Eigen::VectorXd MetricTangentProjector::project(const Eigen::VectorXd& v) const {
  return v - W_ * JW_.solve(J_ * v);
}

double retract_onto_moments(const MomentCostFunction& moments, Eigen::VectorXd& theta, int max_steps) {
  // Gauss-Newton steps theta -= J^T (J J^T)^-1 r: the smallest change of theta that zeroes the
  // linearised residuals, in the span of J^T, which a projected step (orthogonal to it) never
  // touches. Two or three steps reach round-off from a 1e-2 residual.
  for (int k = 0; k < max_steps; ++k) {
    const MomentVector r = moments.residuals(theta);
    if (r.cwiseAbs().maxCoeff() < 1e-12) return r.cwiseAbs().maxCoeff();
    const Eigen::Matrix<double, 10, Eigen::Dynamic> J = moments.jacobian(theta);
    const Eigen::Matrix<double, 10, 10> JJt = J * J.transpose();
    theta -= J.transpose() * JJt.ldlt().solve(r);
  }
  return moments.residuals(theta).cwiseAbs().maxCoeff();
}

bool retract_move_onto_moments(const MomentCostFunction& moments, const Eigen::VectorXd& from,
                               const Eigen::VectorXd& to, double tolerance, Eigen::VectorXd& theta,
                               int max_halvings) {
  double scale = 1.0;
  for (int halving = 0; halving <= max_halvings; ++halving, scale *= 0.5) {
    theta = halving == 0 ? to : Eigen::VectorXd(from + scale * (to - from));
    if (retract_onto_moments(moments, theta) <= tolerance) return true;
  }
  theta = from;
  return false;
}

AttackLoopResult run_attack_loop(const DesignSpace& design, const MomentCostFunction& moments,
                                 const GradientSmoother* smoother, const TrajectoryTerm& trajectory,
                                 const Eigen::VectorXd& theta0, const AttackLoopOptions& options) {
  AttackLoopResult result;
  Adam adam(options.adam);
  Eigen::VectorXd theta = theta0;
  Eigen::VectorXd evaluated;  // the last design whose simulation succeeded
  // That design's trajectory term and gradient in this process (not across a resume).
  std::optional<std::pair<TrajectoryTermValue, Eigen::VectorXd>> last;
  int start = 0;
  std::optional<AttackCheckpoint> saved;
  if (options.resume && !options.checkpoint_path.empty() && std::filesystem::exists(options.checkpoint_path)) {
    saved = read_checkpoint(options.checkpoint_path);
    if (options.restart_on_other_fingerprint && saved->fingerprint != options.fingerprint) {
      saved.reset();  // another start's: overwritten by this run's first checkpoint
    } else {
      check_checkpoint(*saved, options.checkpoint_path, options.fingerprint, design.size());
    }
  }
  if (saved) {
    AttackCheckpoint& c = *saved;
    theta = c.theta;
    if (c.adam.steps > 0) adam.restore(c.adam);
    result.progress = c.progress;
    result.forward_seconds = c.forward_seconds;
    result.adjoint_seconds = c.adjoint_seconds;
    result.elapsed_seconds = c.elapsed_seconds;
    start = result.resumed_from = c.iteration;
    evaluated = c.evaluated_theta;
    result.best_iteration = c.best_iteration;
    result.best_theta = c.best_theta;
  } else if (options.project_moments) {
    // The seeded perturbation of theta_0 breaks the moments (1e-2 on the ball); start from the
    // nearest matched design instead, so that the first gap measures dynamics, not mass shift.
    // A retraction that ends farther off than theta_0 itself (it diverged) is not taken.
    const double start_residual = moments.residuals(theta).cwiseAbs().maxCoeff();
    retract_move_onto_moments(moments, theta0, theta0, std::max(1e-6, start_residual), theta, 0);
  }
  for (int k = start; k < options.iterations; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    Eigen::VectorXd grad_traj, grad_moment;
    TrajectoryTermValue traj;
    if (last.has_value() && theta == evaluated) {
      // The last step was refused (theta did not move): its simulation and adjoint stand.
      traj = last->first;
      traj.forward_seconds = traj.adjoint_seconds = 0;
      grad_traj = last->second;
    } else {
      try {
        traj = trajectory(theta, &grad_traj);
        // A NaN or an infinity is a failed design too: in a progress row it would reach the
        // checkpoint (JSON writes it as null, which no resume reads back), in the gradient it
        // stops Adam, and neither leaves the run's outputs behind.
        const Eigen::Index bad = (!grad_traj.array().isFinite()).count();
        if (!std::isfinite(traj.value) || !std::isfinite(traj.gap) ||
            !std::isfinite(traj.com_gap) || bad > 0) {
          std::ostringstream what;
          what << "the trajectory term is not finite (value " << traj.value << ", gap " << traj.gap
               << " m, centre-of-mass gap " << traj.com_gap << " m, " << bad << " of "
               << grad_traj.size() << " gradient entries non-finite)";
          throw SolverError(what.str());
        }
      } catch (const SolverError& e) {
        // Keep what the run has: stop at the last design whose simulation succeeded.
        if (evaluated.size() == 0) throw;
        result.stopped_early = e.what();
        result.failed_theta = theta;
        theta = evaluated;
        break;
      }
    }
    evaluated = theta;
    last.emplace(traj, grad_traj);
    const double moment_term = moments.penalty(theta, options.beta, &grad_moment);
    Eigen::VectorXd gradient = grad_traj + grad_moment;
    // The occupancy penalty's continuation: w_k (weight P + connectivity_weight R) joins the
    // gradient before the smoothing and the tangent projection, so pushing alpha to its ends moves
    // rho with it (rho alpha is the mass density) and the moments stay matched.
    double occupancy_weight = 0, occupancy_penalty = 0, repair_share = 0, grey_fraction = 0;
    int components = 0;
    if (options.occupancy) {
      const OccupancyPenaltyOptions& po = options.occupancy->options();
      // Scaled by the largest trajectory term so far (occupancy_penalty.hpp): the rows hold it,
      // so a resumed run weighs exactly as an uninterrupted one.
      double scale = std::abs(traj.value);
      for (const ProgressRow& r : result.progress)
        scale = std::max(scale, std::abs(r.trajectory_term));
      occupancy_weight = scale * occupancy_penalty_ramp(po, k, options.iterations);
      const bool grey_on = occupancy_weight > 0 && po.weight > 0;
      const bool repair_on = occupancy_weight > 0 && po.connectivity_weight > 0;
      Eigen::VectorXd g;
      occupancy_penalty = options.occupancy->value(theta, grey_on ? &g : nullptr);
      if (grey_on) gradient += (occupancy_weight * po.weight) * g;
      // The repair's search only where it is used; the components alone otherwise (R reads 0).
      if (po.connectivity_weight > 0 || po.repair_in_loop) {
        repair_share =
            options.occupancy->repair_share(theta, repair_on ? &g : nullptr, &components);
        if (repair_on) gradient += (occupancy_weight * po.connectivity_weight) * g;
      } else {
        components = options.occupancy->components(theta);
      }
      grey_fraction = options.occupancy->grey_fraction(theta);
    }
    // The smoothing acts on the whole occupancy gradient (SPEC section 4): a symmetric positive
    // definite preconditioner M on the alpha block.
    const bool smooth = smoother && design.optimises(DesignField::kAlpha);
    auto precondition = [&](const Eigen::VectorXd& v) {
      Eigen::VectorXd out = v;
      if (smooth) smooth_alpha_gradient(design, *smoother, out);
      return out;
    };
    ProgressRow row;
    row.iteration = k;
    row.trajectory_term = traj.value;
    row.moment_term = moment_term;
    row.objective = traj.value + moment_term;
    row.gap = traj.gap;
    row.com_gap = traj.com_gap;
    row.max_moment_residual = moments.residuals(theta).cwiseAbs().maxCoeff();
    row.occupancy_weight = occupancy_weight;
    row.occupancy_penalty = occupancy_penalty;
    row.repair_share = repair_share;
    row.components = components;
    row.grey_fraction = grey_fraction;
    if (result.best_iteration < 0 || row.objective < result.progress[result.best_iteration].objective) {
      result.best_iteration = k;
      result.best_theta = theta;
    }
    const Eigen::VectorXd before = theta;
    if (options.project_moments) {
      // Descend along the moments' tangent in M's metric: with W = M J^T, the direction
      // z = M g - W (J W)^-1 J M g has J z = 0 and g . z = |M^1/2 g|^2 - |projection of it| >= 0.
      // Projecting M g orthogonally instead (or projecting only Adam's step) does not keep
      // g . z >= 0 once M rescales a block: the occupancy smoothing scales by about 1 / element
      // volume (1e7 on the cube), the Euclidean projection then mixed those components with the
      // others and the cube's attack climbed, its gap shrinking every iteration at any rate.
      const MetricTangentProjector tangent(moments.jacobian(before), precondition);
      adam.step(theta, tangent.project(precondition(gradient)));
      // Adam's per-component scaling leaves the tangent again: take the step back onto it in the
      // same metric, then retract onto the moments' manifold.
      const Eigen::VectorXd step = tangent.project(theta - before);
      // Where the design saturates (the tanh map flat near its bounds, J J^T nearly singular) the
      // retraction can lose its grip on a long step and leave the design off the moments, never
      // to return: the stack's cube attack (configs/cube_strike.yaml at 1500 tets, half the cube
      // void) ended 1e-1 off after its 45th step. Such a step is halved until its retraction
      // reaches the moments to 1e-6 (far below what moves a trajectory, far above the 1e-9 that
      // four Gauss-Newton steps leave of a long but good step; or, from a design already off the
      // moments, gets no farther off), and not taken after ten halvings. Any other step is taken
      // unchanged.
      retract_move_onto_moments(moments, before, Eigen::VectorXd(before + step),
                                std::max(1e-6, row.max_moment_residual), theta);
    } else {
      adam.step(theta, precondition(gradient));
    }
    // The repair's paths, filled after the step (occupancy_penalty.hpp): the next design's
    // rounding is one body. The retraction that restores the moments moves alpha too and can
    // take an element back below the threshold when much was filled at once: fill again, a few
    // passes at most. A fill whose retraction does not reach the moments (within the step's
    // bound) is halved as a step is, and the passes stop where one is not taken.
    if (options.occupancy && options.occupancy->options().repair_in_loop) {
      const double accept = options.project_moments
                                ? std::max(1e-6, moments.residuals(theta).cwiseAbs().maxCoeff())
                                : 0.0;
      for (int pass = 0; pass < 4; ++pass) {
        const Eigen::VectorXd unfilled = theta;
        if (options.occupancy->fill_repair_paths(theta) == 0) break;
        if (options.project_moments &&
            !retract_move_onto_moments(moments, unfilled, Eigen::VectorXd(theta), accept, theta)) {
          break;
        }
      }
    }
    row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    result.progress.push_back(row);
    result.forward_seconds += traj.forward_seconds;
    result.adjoint_seconds += traj.adjoint_seconds;
    result.elapsed_seconds += row.seconds;
    if (!options.checkpoint_path.empty()) {
      save_checkpoint(options.checkpoint_path,
                      {options.fingerprint, k + 1, theta, evaluated, adam.state(), result.progress,
                       result.forward_seconds, result.adjoint_seconds, result.elapsed_seconds,
                       result.best_iteration, result.best_theta});
    }
    if (!options.progress_path.empty()) write_progress_csv(options.progress_path, result.progress);
    if (options.on_iteration) options.on_iteration(row, options.iterations);
  }
  result.theta = theta;
  result.evaluated_theta = evaluated;
  return result;
}

}  // namespace rbaa
