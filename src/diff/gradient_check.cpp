#include "rbaa/diff/gradient_check.hpp"

#include <algorithm>
#include <cmath>
#include <random>

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

// A material field as one vector in the design's fields: per field #T entries (alpha: interior
// only), each scaled by its range so that one unit is the whole range.
struct MaterialCoordinates {
  const DesignSpace& ds;
  int size() const {
    int n = 0;
    for (int f = 0; f < 4; ++f) {
      const auto field = static_cast<DesignField>(f);
      if (ds.optimises(field)) n += field == DesignField::kAlpha ? ds.num_interior() : ds.num_tets();
    }
    return n;
  }
  MaterialField moved(const MaterialField& base, const Eigen::VectorXd& d, double s) const {
    MaterialField m = base;
    int o = 0;
    auto field_move = [&](DesignField f, Eigen::VectorXd& x) {
      if (!ds.optimises(f)) return;
      const double range = ds.map(f).hi() - ds.map(f).lo();
      if (f == DesignField::kAlpha) {
        for (int i : ds.interior()) x[i] += s * range * d[o++];
      } else {
        for (int e = 0; e < ds.num_tets(); ++e) x[e] += s * range * d[o++];
      }
    };
    field_move(DesignField::kY, m.Y);
    field_move(DesignField::kNu, m.nu);
    field_move(DesignField::kRho, m.rho);
    field_move(DesignField::kAlpha, m.alpha);
    return m;
  }
  double dot(const MaterialGradient& g, const Eigen::VectorXd& d) const {
    double sum = 0;
    int o = 0;
    auto field_dot = [&](DesignField f, const Eigen::VectorXd& x) {
      if (!ds.optimises(f)) return;
      const double range = ds.map(f).hi() - ds.map(f).lo();
      if (f == DesignField::kAlpha) {
        for (int i : ds.interior()) sum += range * x[i] * d[o++];
      } else {
        for (int e = 0; e < ds.num_tets(); ++e) sum += range * x[e] * d[o++];
      }
    };
    field_dot(DesignField::kY, g.Y);
    field_dot(DesignField::kNu, g.nu);
    field_dot(DesignField::kRho, g.rho);
    field_dot(DesignField::kAlpha, g.alpha);
    return sum;
  }
};

}  // namespace

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

  std::mt19937_64 rng(options.seed);
  for (int i = 0; i < options.directions; ++i) {
    const Eigen::VectorXd d = random_unit(n, rng);
    DirectionCheck c;
    c.adjoint = options.material_space ? mc.dot(g_material, d) : g_theta.dot(d);
    const double d1 = central(d, options.step);
    // Richardson: D(s) = D + a s^2 + O(s^4), so (4 D(s/2) - D(s)) / 3 = D + O(s^4).
    c.finite_difference =
        options.richardson ? (4.0 * central(d, 0.5 * options.step) - d1) / 3.0 : d1;
    const double scale = std::max(std::abs(c.finite_difference), std::abs(c.adjoint));
    c.relative_error = scale > 0 ? std::abs(c.finite_difference - c.adjoint) / scale : 0.0;
    result.max_relative_error = std::max(result.max_relative_error, c.relative_error);
    result.directions.push_back(c);
    if (on_direction) on_direction(i, c);
  }
  return result;
}

}  // namespace rbaa
