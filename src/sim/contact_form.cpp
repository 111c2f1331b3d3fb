#include "rbaa/sim/contact_form.hpp"

#include <limits>

#include "rbaa/sim/vertex_plane.hpp"

namespace rbaa {

double ContactForm::value(const Eigen::VectorXd& q) const {
  set_.build(q);
  double sum = 0;
  for (const VertexPlanePair& p : set_.vertex_plane_pairs()) sum += barrier_.value(p.distance);
  return kappa_ * sum;
}

int ContactForm::num_active_pairs(const Eigen::VectorXd& q) const {
  set_.build(q);
  return static_cast<int>(set_.vertex_plane_pairs().size());
}

double ContactForm::value_difference(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const {
  // Pairwise b(d1) - b(d0) over every candidate (b = 0 beyond d_hat), so that pairs entering or
  // leaving the active set are counted once each.
  double sum = 0;
  const auto& planes = set_.planes();
  for (int v : set_.surface_vertices()) {
    const Eigen::Vector3d x0 = q0.segment<3>(3 * v), x1 = q1.segment<3>(3 * v);
    for (const Plane& plane : planes) {
      const double d0 = vertex_plane_distance(x0, plane), d1 = vertex_plane_distance(x1, plane);
      if (d0 >= barrier_.d_hat() && d1 >= barrier_.d_hat()) continue;
      if (d1 <= 0) return std::numeric_limits<double>::infinity();
      // The change of distance from the change of position, not from d1 - d0.
      sum += barrier_.difference(d0, plane.normal.dot(x1 - x0));
    }
  }
  return kappa_ * sum;
}

void ContactForm::add_gradient(const Eigen::VectorXd& q, double scale, Eigen::VectorXd& grad) const {
  set_.build(q);
  for (const VertexPlanePair& p : set_.vertex_plane_pairs()) {
    const Plane& plane = set_.planes()[p.plane];
    grad.segment<3>(3 * p.vertex) +=
        scale * kappa_ * barrier_.first_derivative(p.distance) * vertex_plane_distance_gradient(plane);
  }
}

void ContactForm::add_hessian(const Eigen::VectorXd& q, double scale, HessianKind kind,
                              SparseHessian& hessian) const {
  set_.build(q);
  for (const VertexPlanePair& p : set_.vertex_plane_pairs()) {
    const Eigen::Vector3d& n = vertex_plane_distance_gradient(set_.planes()[p.plane]);
    double b2 = barrier_.second_derivative(p.distance);
    if (kind == HessianKind::kProjected && b2 < 0) {
      b2 = 0;
      hessian.mark_projection_active();
    }
    hessian.vertex_block(p.vertex) += (scale * kappa_ * b2) * n * n.transpose();
  }
}

}  // namespace rbaa
