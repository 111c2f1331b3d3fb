#include "rbaa/diff/gradient_check.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "rbaa/diff/tangent_linear.hpp"
#include "rbaa/error.hpp"

namespace rbaa {

namespace {

// Gaussian entries from mt19937_64 through Box-Muller (the same on every platform).
Eigen::VectorXd random_unit(int n, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Eigen::VectorXd d(n);
  for (int i = 0; i < n; ++i) {
    const double a = std::max(u(rng), 1e-300), b = u(rng);
    d[i] = std::sqrt(-2.0 * std::log(a)) * std::cos(2.0 * M_PI * b);
  }
  return d / d.norm();
}

// A material field as one vector in the design's fields: per field one entry per designed element
// (alpha: interior only), each scaled by its range so that one unit is the whole range.
struct MaterialCoordinates {
  const DesignSpace& ds;
  int size() const {
    int n = 0;
    for (int f = 0; f < 4; ++f) {
      const auto field = static_cast<DesignField>(f);
      if (ds.optimises(field)) n += static_cast<int>(ds.elements(field).size());
    }
    return n;
  }
  MaterialField moved(const MaterialField& base, const Eigen::VectorXd& d, double s) const {
    MaterialField m = base;
    int o = 0;
    auto field_move = [&](DesignField f, Eigen::VectorXd& x) {
      if (!ds.optimises(f)) return;
      const double range = ds.map(f).hi() - ds.map(f).lo();
      for (int e : ds.elements(f)) x[e] += s * range * d[o++];
    };
    field_move(DesignField::kY, m.Y);
    field_move(DesignField::kNu, m.nu);
    field_move(DesignField::kRho, m.rho);
    field_move(DesignField::kAlpha, m.alpha);
    return m;
  }
  /// The material change of moving by d (per field: range times d; alpha on interior elements).
  MaterialGradient direction(const Eigen::VectorXd& d) const {
    MaterialGradient m;
    int o = 0;
    auto field_direction = [&](DesignField f, Eigen::VectorXd& x) {
      if (!ds.optimises(f)) return;
      const double range = ds.map(f).hi() - ds.map(f).lo();
      x = Eigen::VectorXd::Zero(ds.num_tets());
      for (int e : ds.elements(f)) x[e] = range * d[o++];
    };
    field_direction(DesignField::kY, m.Y);
    field_direction(DesignField::kNu, m.nu);
    field_direction(DesignField::kRho, m.rho);
    field_direction(DesignField::kAlpha, m.alpha);
    return m;
  }
  /// |g| in these coordinates (each field scaled by its range).
  double norm(const MaterialGradient& g) const {
    double sum = 0;
    auto field_norm = [&](DesignField f, const Eigen::VectorXd& x) {
      if (!ds.optimises(f)) return;
      const double range = ds.map(f).hi() - ds.map(f).lo();
      if (f == DesignField::kAlpha) {
        for (int i : ds.interior()) sum += std::pow(range * x[i], 2);
      } else {
        // Gathered, so that without a mask the sum is x.squaredNorm()'s, bit for bit.
        Eigen::VectorXd designed(ds.num_designed());
        for (int i = 0; i < ds.num_designed(); ++i) designed[i] = x[ds.designed()[i]];
        sum += std::pow(range, 2) * designed.squaredNorm();
      }
    };
    field_norm(DesignField::kY, g.Y);
    field_norm(DesignField::kNu, g.nu);
    field_norm(DesignField::kRho, g.rho);
    field_norm(DesignField::kAlpha, g.alpha);
    return std::sqrt(sum);
  }
  double dot(const MaterialGradient& g, const Eigen::VectorXd& d) const {
    double sum = 0;
    int o = 0;
    auto field_dot = [&](DesignField f, const Eigen::VectorXd& x) {
      if (!ds.optimises(f)) return;
      const double range = ds.map(f).hi() - ds.map(f).lo();
      for (int e : ds.elements(f)) sum += range * x[e] * d[o++];
    };
    field_dot(DesignField::kY, g.Y);
    field_dot(DesignField::kNu, g.nu);
    field_dot(DesignField::kRho, g.rho);
    field_dot(DesignField::kAlpha, g.alpha);
    return sum;
  }
};

// The material change of moving theta by d: the box maps' diagonal Jacobian, field by field.
MaterialGradient theta_direction(const DesignSpace& ds, const Eigen::VectorXd& theta,
                                 const Eigen::VectorXd& d) {
  const Eigen::VectorXd dx = ds.map_derivative(theta).cwiseProduct(d);
  MaterialGradient m;
  auto field_direction = [&](DesignField f, Eigen::VectorXd& x) {
    if (!ds.optimises(f)) return;
    x = Eigen::VectorXd::Zero(ds.num_tets());
    const int o = ds.offset(f);
    const std::vector<int>& elements = ds.elements(f);
    for (std::size_t i = 0; i < elements.size(); ++i) x[elements[i]] = dx[o + i];
  };
  field_direction(DesignField::kY, m.Y);
  field_direction(DesignField::kNu, m.nu);
  field_direction(DesignField::kRho, m.rho);
  field_direction(DesignField::kAlpha, m.alpha);
  return m;
}

double relative_difference(double a, double b) {
  const double scale = std::max(std::abs(a), std::abs(b));
  return scale > 0 ? std::abs(a - b) / scale : 0.0;
}

}  // namespace

const char* gradient_check_method_name(GradientCheckMethod method) {
  switch (method) {
    case GradientCheckMethod::kFiniteDifference: return "fd";
    case GradientCheckMethod::kTangent: return "tangent";
    case GradientCheckMethod::kBoth: return "both";
  }
  return "?";
}

GradientCheckMethod parse_gradient_check_method(const std::string& name) {
  if (name == "fd") return GradientCheckMethod::kFiniteDifference;
  if (name == "tangent") return GradientCheckMethod::kTangent;
  if (name == "both") return GradientCheckMethod::kBoth;
  throw InputError("gradient check method '" + name + "' is not one of fd, tangent, both");
}

GradientCheckResult check_gradient(TrajectoryGradientFunction& f, const Eigen::VectorXd& theta,
                                   const GradientCheckOptions& options,
                                   const std::function<void(int, const DirectionCheck&)>& on_direction) {
  if (options.directions < 1) throw InputError("gradient check: need at least one direction");
  if (!(options.step > 0)) throw InputError("gradient check: the finite-difference step must be > 0");
  const DesignSpace& ds = f.design();
  const MaterialCoordinates mc{ds};
  const int n = options.material_space ? mc.size() : ds.size();
  if (n == 0) throw InputError("gradient check: no design variables");
  GradientCheckResult result;

  // The base point: value, adjoint gradient and the contact it saw.
  const MaterialField base = ds.to_material(theta);
  Eigen::VectorXd g_theta;
  MaterialGradient g_material;
  if (options.material_space) {
    result.value = f.evaluate_materials(base, &g_material);
    result.gradient_norm = mc.norm(g_material);
  } else {
    result.value = f.evaluate(theta, &g_theta);
    result.gradient_norm = g_theta.norm();
  }
  for (const StepStats& s : f.last().trajectory.steps) result.active_contact_steps += s.active_pairs > 0;

  auto value_at = [&](const Eigen::VectorXd& d, double s) {
    if (options.material_space) return f.evaluate_materials(mc.moved(base, d, s), nullptr);
    return f.evaluate(theta + s * d, nullptr);
  };
  auto central = [&](const Eigen::VectorXd& d, double s) {
    return (value_at(d, s) - value_at(d, -s)) / (2.0 * s);
  };

  const bool fd = options.method != GradientCheckMethod::kTangent;
  const bool tangent = options.method != GradientCheckMethod::kFiniteDifference;
  // Coordinates of elements outside [element_begin, element_end) stay out of the directions (the
  // same layout in theta and in material space: per field the designed elements, alpha interior
  // only).
  const int lo = std::max(options.element_begin, 0);
  const int hi = options.element_end < 0 ? ds.num_tets() : std::min(options.element_end, ds.num_tets());
  if (!(lo < hi)) throw InputError("gradient check: no element to move in the chosen range");
  Eigen::VectorXd in_range = Eigen::VectorXd::Zero(n);
  {
    int o = 0;
    for (int f = 0; f < 4; ++f) {
      const auto field = static_cast<DesignField>(f);
      if (!ds.optimises(field)) continue;
      for (int e : ds.elements(field)) in_range[o++] = e >= lo && e < hi;
    }
    if (!(in_range.sum() > 0)) throw InputError("gradient check: no design entry in the chosen elements");
  }
  auto restricted = [&](Eigen::VectorXd d) {
    if (lo == 0 && hi == ds.num_tets()) return d;
    d = d.cwiseProduct(in_range);
    return Eigen::VectorXd(d / d.norm());
  };
  std::mt19937_64 rng(options.seed);
  std::vector<Eigen::VectorXd> dirs;
  for (int i = 0; i < options.directions; ++i) dirs.push_back(restricted(random_unit(n, rng)));
  std::vector<DirectionCheck> checks(dirs.size());
  for (std::size_t i = 0; i < dirs.size(); ++i) {
    checks[i].adjoint = options.material_space ? mc.dot(g_material, dirs[i]) : g_theta.dot(dirs[i]);
  }

  // Tangent first: it needs the base run's trajectory and materials, still in the simulator.
  if (tangent) {
    const TrajectoryEvaluation& base_run = f.last();
    TrajectorySeed seed;
    f.objective().evaluate(base_run.trajectory, base_run.materials, &seed);
    // Each direction d goes with a random split d = s + (d - s): the tangent is linear, so
    // T(d) - T(s) - T(d - s) is its own round-off, measured rather than guessed (the forward
    // recurrence carries the elastic response of every step, which the objective barely sees).
    auto material_direction = [&](const Eigen::VectorXd& d) {
      return options.material_space ? mc.direction(d) : theta_direction(ds, theta, d);
    };
    std::mt19937_64 split_rng(options.seed + 0x9e3779b97f4a7c15ULL);
    std::vector<TangentDirection> td(3 * dirs.size());
    for (std::size_t i = 0; i < dirs.size(); ++i) {
      const Eigen::VectorXd split = restricted(random_unit(n, split_rng));
      td[3 * i].materials = material_direction(dirs[i]);
      td[3 * i + 1].materials = material_direction(split);
      td[3 * i + 2].materials = material_direction(dirs[i] - split);
    }
    const TangentResult t =
        tangent_linear(f.simulator(), base_run.materials, base_run.trajectory, seed, td);
    result.tangent_seconds = t.stats.seconds;
    result.tangent_pass = true;
    for (std::size_t i = 0; i < dirs.size(); ++i) {
      checks[i].tangent = t.derivatives[3 * i];
      // The dot-product test's normwise error: the derivative is <w, J d> = <J^T w, d> with w
      // the objective's derivatives and J the trajectory's Jacobian; each side is bounded by
      // Cauchy-Schwarz, |J^T w| |d| = |g| (d a unit vector) and sum_k |w_k| |(J d)_k|, and
      // round-off is relative to those bounds, not to the derivative: along a direction nearly
      // orthogonal to g (nu on a stiff body, Y on the cube whose gap is 3e-7 m) the terms cancel
      // to 1e-5 of their size and the pointwise error only measures that cancellation.
      const double a = checks[i].adjoint, t_i = checks[i].tangent;
      checks[i].tangent_pointwise_error = relative_difference(t_i, a);
      const double scale =
          std::max({result.gradient_norm, t.bounds[3 * i], std::abs(t_i), std::abs(a)});
      checks[i].tangent_relative_error = scale > 0 ? std::abs(t_i - a) / scale : 0.0;
      checks[i].tangent_noise =
          scale > 0 ? std::abs(t_i - t.derivatives[3 * i + 1] - t.derivatives[3 * i + 2]) / scale
                    : 0.0;
      result.max_tangent_relative_error =
          std::max(result.max_tangent_relative_error, checks[i].tangent_relative_error);
      result.max_tangent_noise = std::max(result.max_tangent_noise, checks[i].tangent_noise);
    }
    // The round-off is the run's (one recurrence over the same steps and factors), and each split
    // is one sample of it: on the 300-tet cube's nu one run's three samples spread from 2.6e-11 to
    // 9.3e-10, so a direction judged by its own sample alone failed at 2.6e-10, below what the
    // same run measured for its other directions (a wrong adjoint term is off by 1e-3 to 1).
    const double floor = options.tangent_noise_factor * result.max_tangent_noise;
    for (const DirectionCheck& c : checks) {
      result.tangent_pass = result.tangent_pass &&
                            c.tangent_relative_error <= std::max(options.tangent_tolerance, floor);
    }
  }

  // Richardson: D(s) = D + a s^2 + O(s^4), so (4 D(s/2) - D(s)) / 3 = D + O(s^4).
  auto extrapolated = [&](const Eigen::VectorXd& d, double s) {
    const double d1 = central(d, s);
    return options.richardson ? (4.0 * central(d, 0.5 * s) - d1) / 3.0 : d1;
  };
  int failing = 0, noisy = 0;
  for (std::size_t i = 0; i < dirs.size(); ++i) {
    DirectionCheck& c = checks[i];
    if (fd) {
      c.finite_difference = extrapolated(dirs[i], options.step);
      c.relative_error = relative_difference(c.finite_difference, c.adjoint);
      if (c.relative_error > options.fd_tolerance) {
        // The two estimates' own disagreement is the finite differences' error bar: noise
        // (Newton's tolerance over the step) moves them apart, while a wrong adjoint leaves them
        // agreeing with each other and not with it. Noise: the adjoint lies within twice the bar.
        ++failing;
        c.coarse_finite_difference = extrapolated(dirs[i], 4.0 * options.step);
        c.coarse_relative_error = relative_difference(c.coarse_finite_difference, c.adjoint);
        const double spread = std::abs(c.coarse_finite_difference - c.finite_difference);
        c.noise_dominated = std::abs(c.finite_difference - c.adjoint) <= 2.0 * spread;
        noisy += c.noise_dominated;
      }
      result.max_relative_error = std::max(result.max_relative_error, c.relative_error);
    }
    result.directions.push_back(c);
    if (on_direction) on_direction(static_cast<int>(i), c);
  }
  result.fd_noise_dominated = failing > 0 && noisy == failing;
  return result;
}

}  // namespace rbaa
