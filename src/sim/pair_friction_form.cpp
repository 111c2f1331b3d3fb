#include "rbaa/sim/pair_friction_form.hpp"

#include <cmath>
#include <string>

#include "rbaa/contact/distance_type.hpp"
#include "rbaa/contact/edge_edge.hpp"
#include "rbaa/contact/edge_edge_mollifier.hpp"
#include "rbaa/contact/point_triangle.hpp"
#include "rbaa/contact/smooth_friction.hpp"
#include "rbaa/contact/tangent_frame.hpp"
#include "rbaa/error.hpp"

namespace rbaa {

using contact::Matrix12d;
using contact::Vector12d;

namespace {

void check_coefficient(double mu, const std::string& what) {
  if (!(mu >= 0 && std::isfinite(mu))) {
    throw InputError("friction: the coefficient " + what + " is " + std::to_string(mu) +
                     "; it must be finite and >= 0");
  }
}

contact::TangentFrame frame(const ContactPairPoints& P, int type) {
  return P.edge_edge
             ? contact::edge_edge_tangent_frame(P.x[0], P.x[1], P.x[2], P.x[3],
                                                static_cast<contact::EdgeEdgeDistanceType>(type))
             : contact::point_triangle_tangent_frame(
                   P.x[0], P.x[1], P.x[2], P.x[3],
                   static_cast<contact::PointTriangleDistanceType>(type));
}

contact::TangentFrameJacobian frame_jacobian(const ContactPairPoints& P, int type) {
  return P.edge_edge
             ? contact::edge_edge_tangent_frame_jacobian(
                   P.x[0], P.x[1], P.x[2], P.x[3], static_cast<contact::EdgeEdgeDistanceType>(type))
             : contact::point_triangle_tangent_frame_jacobian(
                   P.x[0], P.x[1], P.x[2], P.x[3],
                   static_cast<contact::PointTriangleDistanceType>(type));
}

// The pair's 12 coordinates of a stacked vector, zero at obstacle points.
Vector12d gather(const ContactPairPoints& P, const Eigen::VectorXd& q) {
  Vector12d out = Vector12d::Zero();
  for (int i = 0; i < 4; ++i) {
    if (P.vertex[i] >= 0) out.segment<3>(3 * i) = q.segment<3>(3 * P.vertex[i]);
  }
  return out;
}

// x - x~ over the pair (zero at obstacle points, which do not move).
Vector12d displacement(const LaggedFrictionPair& p, const Eigen::VectorXd& x) {
  Vector12d r = Vector12d::Zero();
  for (int i = 0; i < 4; ++i) {
    const int v = p.points.vertex[i];
    if (v >= 0) r.segment<3>(3 * i) = x.segment<3>(3 * v) - p.x_tilde.segment<3>(3 * i);
  }
  return r;
}

}  // namespace

bool any_pair_friction(const std::vector<double>& mesh_mu, const Eigen::MatrixXd& body_mu) {
  for (double m : mesh_mu) {
    if (m != 0) return true;
  }
  return body_mu.size() > 0 && (body_mu.array() != 0).any();
}

PairFrictionForm::PairFrictionForm(const MeshObstacleForm* obstacles, std::vector<double> mesh_mu,
                                   const BodyContactForm* bodies, Eigen::MatrixXd body_mu,
                                   double eps_v, Integrator integrator, double time_step)
    : obstacles_(obstacles),
      mesh_mu_(std::move(mesh_mu)),
      bodies_(bodies),
      body_mu_(std::move(body_mu)) {
  for (std::size_t m = 0; m < mesh_mu_.size(); ++m) {
    check_coefficient(mesh_mu_[m], "of obstacle mesh " + std::to_string(m));
  }
  if (body_mu_.rows() != body_mu_.cols())
    throw InputError("friction: body coefficients must be square");
  for (Eigen::Index i = 0; i < body_mu_.rows(); ++i) {
    for (Eigen::Index j = 0; j < body_mu_.cols(); ++j) {
      check_coefficient(body_mu_(i, j),
                        "between bodies " + std::to_string(i) + " and " + std::to_string(j));
      if (body_mu_(i, j) != body_mu_(j, i)) {
        throw InputError("friction: the body coefficients must be symmetric");
      }
    }
  }
  if (obstacles_ && static_cast<int>(mesh_mu_.size()) != obstacles_->num_meshes()) {
    throw InputError("friction: one coefficient per obstacle mesh is needed");
  }
  if (!(eps_v > 0 && std::isfinite(eps_v))) throw InputError("friction: eps_v must be positive");
  eps_v_ = eps_v;
  set_step_rule(bdf_step_rule(integrator, time_step, time_step));
}

void PairFrictionForm::add_pair(LaggedFrictionPair p, const contact::Barrier& barrier,
                                double kappa) {
  if (p.mu == 0) return;
  const ContactPairPoints& P = p.points;
  p.type =
      P.edge_edge
          ? static_cast<int>(contact::edge_edge_distance_type(P.x[0], P.x[1], P.x[2], P.x[3]))
          : static_cast<int>(contact::point_triangle_distance_type(P.x[0], P.x[1], P.x[2], P.x[3]));
  const double d = std::sqrt(pair_squared_distance(P));
  p.normal_force = -kappa * pair_mollifier(P) * barrier.first_derivative(d);
  // Exactly parallel edges (m = 0, and dm = 0 there) carry no force and no derivative of it.
  if (!(p.normal_force > 0)) return;
  const contact::TangentFrame f = frame(P, p.type);
  for (int i = 0; i < 4; ++i) {
    p.gamma_basis.block<3, 2>(3 * i, 0) = f.gamma[i] * f.basis;
    const int v = P.vertex[i];
    p.x_tilde.segment<3>(3 * i) =
        v >= 0 ? Eigen::Vector3d(a0_ * q_n_.segment<3>(3 * v) + a1_ * q_previous_.segment<3>(3 * v))
               : P.x[i];
  }
  pairs_.push_back(p);
}

void PairFrictionForm::lag(const Eigen::VectorXd& q_n, const Eigen::VectorXd& q_previous) {
  q_n_ = q_n;
  q_previous_ = q_previous;
  lag_at(q_n);
}

void PairFrictionForm::relag(const Eigen::VectorXd& x) { lag_at(x); }

void PairFrictionForm::lag_at(const Eigen::VectorXd& q_lag) {
  pairs_.clear();
  if (obstacles_) {
    for (const ObstaclePair& op : obstacles_->active_pairs(q_lag)) {
      LaggedFrictionPair p;
      p.points = obstacles_->points(op, q_lag);
      p.mesh = obstacles_->mesh_of_pair(op);
      p.mu = mesh_mu_[p.mesh];
      add_pair(p, obstacles_->barrier(), obstacles_->kappa());
    }
  }
  if (bodies_ && body_mu_.size() > 0) {
    for (const BodyPair& bp : bodies_->active_pairs(q_lag)) {
      LaggedFrictionPair p;
      p.points = bodies_->points(bp, q_lag);
      p.body_a = bodies_->body_of_vertex(p.points.vertex[0]);
      p.body_b = bodies_->body_of_vertex(p.points.vertex[3]);
      p.mu = body_mu_(p.body_a, p.body_b);
      add_pair(p, bodies_->barrier(), bodies_->kappa());
    }
  }
}

PairFrictionForm::Slip PairFrictionForm::slip(const LaggedFrictionPair& p,
                                              const Eigen::VectorXd& x) const {
  Slip s;
  s.u = p.gamma_basis.transpose() * displacement(p, x);
  s.y = s.u.norm();
  s.f1_over_y = contact::smooth_friction_f1_over_y(s.y, eps_);
  s.c1 = contact::smooth_friction_c1(s.y, eps_);
  return s;
}

double PairFrictionForm::value(const Eigen::VectorXd& x) const {
  double sum = 0;
  for (const LaggedFrictionPair& p : pairs_) {
    sum += p.mu * p.normal_force * contact::smooth_friction_f0(slip(p, x).y, eps_);
  }
  return sum;
}

double PairFrictionForm::value_difference(const Eigen::VectorXd& x0,
                                          const Eigen::VectorXd& x1) const {
  // As for the plane form (plane_friction_form.cpp): near convergence the energies differ by
  // ~1e-24 while D ~ 1e-3, so per pair y1 - y0 = (u1 - u0) . (u1 + u0) / (y1 + y0) with u1 - u0
  // taken from the positions' difference.
  double sum = 0;
  for (const LaggedFrictionPair& p : pairs_) {
    const Slip s0 = slip(p, x0), s1 = slip(p, x1);
    Vector12d dx = Vector12d::Zero();
    for (int i = 0; i < 4; ++i) {
      const int v = p.points.vertex[i];
      if (v >= 0) dx.segment<3>(3 * i) = x1.segment<3>(3 * v) - x0.segment<3>(3 * v);
    }
    const Eigen::Vector2d du = p.gamma_basis.transpose() * dx;
    const double dy = s0.y + s1.y > 0 ? du.dot(s1.u + s0.u) / (s0.y + s1.y) : 0.0;
    sum += p.mu * p.normal_force * contact::smooth_friction_f0_difference(s0.y, s1.y, dy, eps_);
  }
  return sum;
}

void PairFrictionForm::add_gradient(const Eigen::VectorXd& x, double scale,
                                    Eigen::VectorXd& grad) const {
  for (const LaggedFrictionPair& p : pairs_) {
    const Slip s = slip(p, x);
    const Vector12d g = (p.mu * p.normal_force * s.f1_over_y) * (p.gamma_basis * s.u);
    add_pair_gradient(p.points, g, scale, grad);
  }
}

void PairFrictionForm::add_hessian(const Eigen::VectorXd& x, double scale, HessianKind,
                                   SparseHessian& hessian) const {
  for (const LaggedFrictionPair& p : pairs_) {
    const Slip s = slip(p, x);
    const Eigen::Matrix2d Phi =
        s.c1 * s.u * s.u.transpose() + s.f1_over_y * Eigen::Matrix2d::Identity();
    const Matrix12d H = (p.mu * p.normal_force) * (p.gamma_basis * Phi * p.gamma_basis.transpose());
    // PSD by construction (the header): no projection needed.
    add_pair_hessian(p.points, H, scale, HessianKind::kExact, hessian);
  }
}

Vector12d PairFrictionForm::normal_force_gradient(const LaggedFrictionPair& p) const {
  // lambda = -kappa m b'(d), d = sqrt(s): d lambda = -kappa (m b''(d) ds / (2 d) + b'(d) dm).
  const ContactPairPoints& P = p.points;
  const contact::Barrier& barrier = p.mesh >= 0 ? obstacles_->barrier() : bodies_->barrier();
  const double kappa = p.mesh >= 0 ? obstacles_->kappa() : bodies_->kappa();
  Vector12d ds;
  double s;
  if (P.edge_edge) {
    const auto type = static_cast<contact::EdgeEdgeDistanceType>(p.type);
    s = contact::edge_edge_distance(P.x[0], P.x[1], P.x[2], P.x[3], type);
    ds = contact::edge_edge_distance_gradient(P.x[0], P.x[1], P.x[2], P.x[3], type);
  } else {
    const auto type = static_cast<contact::PointTriangleDistanceType>(p.type);
    s = contact::point_triangle_distance(P.x[0], P.x[1], P.x[2], P.x[3], type);
    ds = contact::point_triangle_distance_gradient(P.x[0], P.x[1], P.x[2], P.x[3], type);
  }
  const double d = std::sqrt(s);
  const double m = pair_mollifier(P);
  Vector12d g = (-kappa * m * barrier.second_derivative(d) / (2.0 * d)) * ds;
  if (P.edge_edge && m < 1.0) {
    g -= (kappa * barrier.first_derivative(d)) *
         contact::edge_edge_mollifier_gradient(P.x[0], P.x[1], P.x[2], P.x[3], P.eps_x);
  }
  return g;
}

void PairFrictionForm::history_jacobians(const LaggedFrictionPair& p, const Eigen::VectorXd& x,
                                         Matrix12d& J_n, Matrix12d& J_p) const {
  // G_k = mu lambda Gamma phi(u), phi = (f1/y) u, u = Gamma^T (x - x~), x~ = a0 q_n + a1 q_{n-1}:
  //   dG_k/dz_j = mu [dlambda_j Gamma phi + lambda dGamma_j phi
  //                   + lambda Gamma Phi (dGamma_j^T (x - x~) - a0 Gamma^T e_j)],
  //   dG_k/dz_prev_j = -a1 mu lambda Gamma Phi Gamma^T e_j,   Phi = c1 u u^T + (f1/y) I,
  // with dGamma_j (rows 3i..3i+2) = dgamma_i/dz_j T + gamma_i dT/dz_j.
  const Slip s = slip(p, x);
  const Eigen::Vector2d phi = s.f1_over_y * s.u;
  const Eigen::Matrix2d Phi =
      s.c1 * s.u * s.u.transpose() + s.f1_over_y * Eigen::Matrix2d::Identity();
  const Vector12d delta = displacement(p, x);
  const Vector12d dlambda = normal_force_gradient(p);
  const contact::TangentFrame f = frame(p.points, p.type);
  const contact::TangentFrameJacobian J = frame_jacobian(p.points, p.type);
  const Eigen::Matrix<double, 12, 2>& Gamma = p.gamma_basis;
  const Vector12d Gamma_phi = Gamma * phi;
  const double ml = p.mu * p.normal_force;
  const Eigen::Matrix<double, 12, 2> GammaPhi = Gamma * Phi;
  J_n.setZero();
  J_p.setZero();
  for (int j = 0; j < 12; ++j) {
    if (p.points.vertex[j / 3] < 0) continue;  // obstacle coordinates are no variables
    Eigen::Matrix<double, 3, 2> dT;
    dT.col(0) = J.basis.col(j).head<3>();
    dT.col(1) = J.basis.col(j).tail<3>();
    Eigen::Matrix<double, 12, 2> dGamma;
    for (int i = 0; i < 4; ++i) {
      dGamma.block<3, 2>(3 * i, 0) = J.gamma(i, j) * f.basis + f.gamma[i] * dT;
    }
    const Eigen::Vector2d du = dGamma.transpose() * delta - a0_ * Gamma.row(j).transpose();
    J_n.col(j) = p.mu * dlambda[j] * Gamma_phi + ml * (dGamma * phi + GammaPhi * du);
    J_p.col(j) = (-a1_ * ml) * (GammaPhi * Gamma.row(j).transpose());
  }
  for (int i = 0; i < 4; ++i) {
    if (p.points.vertex[i] < 0) {
      J_n.middleRows<3>(3 * i).setZero();
      J_p.middleRows<3>(3 * i).setZero();
    }
  }
}

void PairFrictionForm::add_history_adjoint(const Eigen::VectorXd& x, const Eigen::VectorXd& a,
                                           double w, Eigen::VectorXd& bar_n,
                                           Eigen::VectorXd& bar_previous) const {
  Matrix12d J_n, J_p;
  for (const LaggedFrictionPair& p : pairs_) {
    history_jacobians(p, x, J_n, J_p);
    const Vector12d ap = gather(p.points, a);
    add_pair_gradient(p.points, J_n.transpose() * ap, -w, bar_n);
    add_pair_gradient(p.points, J_p.transpose() * ap, -w, bar_previous);
  }
}

void PairFrictionForm::add_history_tangent(const Eigen::VectorXd& x, const Eigen::VectorXd& dq_n,
                                           const Eigen::VectorXd& dq_previous, double w,
                                           Eigen::VectorXd& out) const {
  Matrix12d J_n, J_p;
  for (const LaggedFrictionPair& p : pairs_) {
    history_jacobians(p, x, J_n, J_p);
    add_pair_gradient(p.points, J_n * gather(p.points, dq_n) + J_p * gather(p.points, dq_previous),
                      w, out);
  }
}

}  // namespace rbaa
