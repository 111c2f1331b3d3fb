#include "rbaa/sim/contact_pair.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

#include "rbaa/contact/edge_edge.hpp"
#include "rbaa/contact/edge_edge_mollifier.hpp"
#include "rbaa/contact/point_triangle.hpp"

namespace rbaa {

using contact::Matrix12d;
using contact::Vector12d;

double pair_squared_distance(const ContactPairPoints& P) {
  return P.edge_edge ? contact::edge_edge_distance(P.x[0], P.x[1], P.x[2], P.x[3])
                     : contact::point_triangle_distance(P.x[0], P.x[1], P.x[2], P.x[3]);
}

double pair_mollifier(const ContactPairPoints& P) {
  return P.edge_edge ? contact::edge_edge_mollifier(P.x[0], P.x[1], P.x[2], P.x[3], P.eps_x) : 1.0;
}

void pair_derivatives(const ContactPairPoints& P, const contact::Barrier& b, Vector12d& g, Matrix12d& H) {
  Vector12d ds;
  Matrix12d d2s;
  if (P.edge_edge) {
    const auto type = contact::edge_edge_distance_type(P.x[0], P.x[1], P.x[2], P.x[3]);
    ds = contact::edge_edge_distance_gradient(P.x[0], P.x[1], P.x[2], P.x[3], type);
    d2s = contact::edge_edge_distance_hessian(P.x[0], P.x[1], P.x[2], P.x[3], type);
  } else {
    const auto type = contact::point_triangle_distance_type(P.x[0], P.x[1], P.x[2], P.x[3]);
    ds = contact::point_triangle_distance_gradient(P.x[0], P.x[1], P.x[2], P.x[3], type);
    d2s = contact::point_triangle_distance_hessian(P.x[0], P.x[1], P.x[2], P.x[3], type);
  }
  const double s = pair_squared_distance(P);
  const double d = std::sqrt(s);
  const double b1 = b.first_derivative(d);
  const double f = b.value(d);
  const double f1 = b1 / (2.0 * d);
  const double f2 = (b.second_derivative(d) - b1 / d) / (4.0 * s);
  g = f1 * ds;
  H = f1 * d2s + f2 * ds * ds.transpose();
  if (P.edge_edge) {
    const double m = pair_mollifier(P);
    if (m < 1.0) {
      const Vector12d dm =
          contact::edge_edge_mollifier_gradient(P.x[0], P.x[1], P.x[2], P.x[3], P.eps_x);
      const Matrix12d d2m =
          contact::edge_edge_mollifier_hessian(P.x[0], P.x[1], P.x[2], P.x[3], P.eps_x);
      H = m * H + f * d2m + f1 * (dm * ds.transpose() + ds * dm.transpose());
      g = m * g + f * dm;
    }
  }
}

double pair_value_difference(const ContactPairPoints& P0, const ContactPairPoints& P1,
                             const contact::Barrier& b) {
  const double d0 = std::sqrt(pair_squared_distance(P0)), d1 = std::sqrt(pair_squared_distance(P1));
  if (!(d1 > 0)) return std::numeric_limits<double>::infinity();
  const double db = b.difference(d0, d1 - d0);
  const double m0 = pair_mollifier(P0), m1 = pair_mollifier(P1);
  return m1 * db + (m1 != m0 ? (m1 - m0) * b.value(d0) : 0.0);
}

void add_pair_gradient(const ContactPairPoints& P, const Vector12d& g, double scale,
                       Eigen::VectorXd& grad) {
  for (int i = 0; i < 4; ++i) {
    if (P.vertex[i] >= 0) grad.segment<3>(3 * P.vertex[i]) += scale * g.segment<3>(3 * i);
  }
}

bool add_pair_hessian(const ContactPairPoints& P, const Matrix12d& H, double scale,
                      HessianKind kind, SparseHessian& hessian) {
  int local[4];  // local point indices with a vertex
  int n = 0;
  for (int i = 0; i < 4; ++i) {
    if (P.vertex[i] >= 0) local[n++] = i;
  }
  Eigen::MatrixXd B(3 * n, 3 * n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j)
      B.block<3, 3>(3 * i, 3 * j) = H.block<3, 3>(3 * local[i], 3 * local[j]);
  }
  bool projected = false;
  if (kind == HessianKind::kProjected) {
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(B);
    const Eigen::VectorXd& lambda = eig.eigenvalues();
    const double largest = lambda.cwiseAbs().maxCoeff();
    if (lambda.minCoeff() < -1e-12 * largest) {
      B = eig.eigenvectors() * lambda.cwiseMax(0.0).asDiagonal() * eig.eigenvectors().transpose();
      projected = true;
    }
  }
  B *= scale;
  for (int i = 0; i < n; ++i) {
    hessian.vertex_block(P.vertex[local[i]]) += B.block<3, 3>(3 * i, 3 * i);
    for (int j = i + 1; j < n; ++j) {
      hessian.add_vertex_pair_block(P.vertex[local[i]], P.vertex[local[j]],
                                    B.block<3, 3>(3 * i, 3 * j));
    }
  }
  return projected;
}

}  // namespace rbaa
