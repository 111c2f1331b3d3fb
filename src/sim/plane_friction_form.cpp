#include "rbaa/sim/plane_friction_form.hpp"

#include <cmath>
#include <string>

#include "rbaa/contact/smooth_friction.hpp"
#include "rbaa/error.hpp"
#include "rbaa/sim/vertex_plane.hpp"

namespace rbaa {

PlaneFrictionForm::PlaneFrictionForm(std::vector<int> surface_vertices, std::vector<Plane> planes,
                                     std::vector<double> mu, double d_hat, double kappa,
                                     double eps_v, Integrator integrator, double time_step)
    : surface_vertices_(std::move(surface_vertices)), planes_(std::move(planes)),
      mu_(std::move(mu)), barrier_(d_hat), kappa_(kappa) {
  if (mu_.size() != planes_.size()) throw InputError("friction: one coefficient per plane is needed");
  for (std::size_t p = 0; p < mu_.size(); ++p) {
    if (!(mu_[p] >= 0 && std::isfinite(mu_[p]))) {
      throw InputError("friction: the coefficient of plane " + std::to_string(p) + " is " +
                       std::to_string(mu_[p]) + "; it must be finite and >= 0");
    }
  }
  if (!(eps_v > 0 && std::isfinite(eps_v))) throw InputError("friction: eps_v must be positive");
  eps_v_ = eps_v;
  set_step_rule(bdf_step_rule(integrator, time_step, time_step));
}

void PlaneFrictionForm::lag(const Eigen::VectorXd& q_n, const Eigen::VectorXd& q_previous) {
  q_n_ = q_n;
  q_previous_ = q_previous;
  lag_at(q_n);
}

void PlaneFrictionForm::relag(const Eigen::VectorXd& x) { lag_at(x); }

void PlaneFrictionForm::lag_at(const Eigen::VectorXd& q_lag) {
  pairs_.clear();
  for (int v : surface_vertices_) {
    const Eigen::Vector3d x = q_lag.segment<3>(3 * v);
    for (int p = 0; p < static_cast<int>(planes_.size()); ++p) {
      if (mu_[p] == 0) continue;
      const double d = vertex_plane_distance(x, planes_[p]);
      if (!(d < barrier_.d_hat())) continue;
      Pair pair;
      pair.vertex = v;
      pair.plane = p;
      pair.normal_force = -kappa_ * barrier_.first_derivative(d);
      pair.normal_force_derivative = -kappa_ * barrier_.second_derivative(d);
      pair.x_tilde = a0_ * q_n_.segment<3>(3 * v) + a1_ * q_previous_.segment<3>(3 * v);
      pairs_.push_back(pair);
    }
  }
}

PlaneFrictionForm::Slip PlaneFrictionForm::slip(const Pair& p, const Eigen::VectorXd& x) const {
  const Eigen::Vector3d& n = planes_[p.plane].normal;
  const Eigen::Vector3d r = x.segment<3>(3 * p.vertex) - p.x_tilde;
  Slip s;
  s.u = r - n * n.dot(r);
  s.y = s.u.norm();
  s.f1_over_y = contact::smooth_friction_f1_over_y(s.y, eps_);
  s.c1 = contact::smooth_friction_c1(s.y, eps_);
  return s;
}

Eigen::Matrix3d PlaneFrictionForm::block(const Pair& p, const Slip& s) const {
  const Eigen::Vector3d& n = planes_[p.plane].normal;
  const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - n * n.transpose();
  return mu_[p.plane] * p.normal_force * (s.c1 * s.u * s.u.transpose() + s.f1_over_y * P);
}

double PlaneFrictionForm::value(const Eigen::VectorXd& x) const {
  double sum = 0;
  for (const Pair& p : pairs_) {
    sum += mu_[p.plane] * p.normal_force * contact::smooth_friction_f0(slip(p, x).y, eps_);
  }
  return sum;
}

double PlaneFrictionForm::value_difference(const Eigen::VectorXd& x0,
                                          const Eigen::VectorXd& x1) const {
  // Near convergence Newton compares energies ~1e-24 apart while D ~ mu lambda |u| ~ 1e-3:
  // D(x1) - D(x0) rounds to noise, and the line search stalled 100 iterations at ~5e-11 m/s.
  // Per pair, y1 - y0 = (u1 - u0) . (u1 + u0) / (y1 + y0) with u1 - u0 = P (x1 - x0) taken from
  // the positions' difference, and f0(y1) - f0(y0) factored through it.
  double sum = 0;
  for (const Pair& p : pairs_) {
    const Slip s0 = slip(p, x0), s1 = slip(p, x1);
    const Eigen::Vector3d& n = planes_[p.plane].normal;
    const Eigen::Vector3d dx = x1.segment<3>(3 * p.vertex) - x0.segment<3>(3 * p.vertex);
    const Eigen::Vector3d du = dx - n * n.dot(dx);
    const double y0 = s0.y, y1 = s1.y;
    const double dy = y0 + y1 > 0 ? du.dot(s1.u + s0.u) / (y0 + y1) : 0.0;
    sum += mu_[p.plane] * p.normal_force * contact::smooth_friction_f0_difference(y0, y1, dy, eps_);
  }
  return sum;
}

void PlaneFrictionForm::add_gradient(const Eigen::VectorXd& x, double scale,
                                     Eigen::VectorXd& grad) const {
  for (const Pair& p : pairs_) {
    const Slip s = slip(p, x);
    grad.segment<3>(3 * p.vertex) += scale * mu_[p.plane] * p.normal_force * s.f1_over_y * s.u;
  }
}

void PlaneFrictionForm::add_hessian(const Eigen::VectorXd& x, double scale, HessianKind,
                                    SparseHessian& hessian) const {
  for (const Pair& p : pairs_) hessian.vertex_block(p.vertex) += scale * block(p, slip(p, x));
}

void PlaneFrictionForm::add_history_adjoint(const Eigen::VectorXd& x, const Eigen::VectorXd& a,
                                            double w, Eigen::VectorXd& bar_n,
                                            Eigen::VectorXd& bar_previous) const {
  for (const Pair& p : pairs_) {
    const Slip s = slip(p, x);
    const Eigen::Vector3d av = a.segment<3>(3 * p.vertex);
    // Through x~: d(grad D)/dx~ = -hess D, x~ = a0 q_n + a1 q_{n-1}.
    const Eigen::Vector3d Ha = block(p, s) * av;
    bar_n.segment<3>(3 * p.vertex) += (w * a0_) * Ha;
    bar_previous.segment<3>(3 * p.vertex) += (w * a1_) * Ha;
    // Through lambda(q_n): d(grad D)/d lambda = mu f1/y u, d lambda / d x_v = lambda' n.
    const double g_dot_a = mu_[p.plane] * s.f1_over_y * s.u.dot(av);
    bar_n.segment<3>(3 * p.vertex) -= (w * g_dot_a * p.normal_force_derivative) * planes_[p.plane].normal;
  }
}

Eigen::VectorXd PlaneFrictionForm::history_tangent(const Eigen::VectorXd& x,
                                                   const Eigen::VectorXd& dq_n,
                                                   const Eigen::VectorXd& dq_previous,
                                                   double w) const {
  Eigen::VectorXd out = Eigen::VectorXd::Zero(x.size());
  for (const Pair& p : pairs_) {
    const Slip s = slip(p, x);
    const int v = p.vertex;
    const Eigen::Vector3d dx_tilde = a0_ * dq_n.segment<3>(3 * v) + a1_ * dq_previous.segment<3>(3 * v);
    const double dlambda = p.normal_force_derivative * planes_[p.plane].normal.dot(dq_n.segment<3>(3 * v));
    out.segment<3>(3 * v) += w * (-(block(p, s) * dx_tilde) + (mu_[p.plane] * s.f1_over_y * dlambda) * s.u);
  }
  return out;
}

}  // namespace rbaa
