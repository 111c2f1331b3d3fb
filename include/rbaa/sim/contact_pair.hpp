#pragma once
// One IPC contact pair's potential, shared by the forms against triangle-mesh obstacles
// (mesh_obstacle_form.hpp) and between bodies (body_contact_form.hpp):
//
//   phi(x) = m(x) f(s(x)),  f(s) = b(sqrt(s)),
//
// over the pair's four points x = (p, t0, t1, t2) (vertex-triangle) or (ea0, ea1, eb0, eb1)
// (edge-edge), 12 dofs; s is the squared distance of the closest features (the distance type of
// contact/distance_type.hpp, so degenerate closest points are exact), b the log barrier
// (barrier.hpp) and m IPC's mollifier for edge-edge pairs (contact/edge_edge_mollifier.hpp; 1 for
// vertex-triangle). With f' = b'(d) / (2 d) and f'' = (b''(d) - b'(d) / d) / (4 d^2):
//
//   grad phi = m f' grad s + f grad m,
//   hess phi = m (f' hess s + f'' grad s grad s^T) + f hess m + f' (grad m grad s^T + grad s grad
//   m^T).
//
// Each point carries the simulator vertex behind it, or -1 for a fixed obstacle point: scattering
// a pair's derivatives skips the dofs of fixed points.

#include <Eigen/Core>

#include "rbaa/contact/fixed_size.hpp"
#include "rbaa/contact/barrier.hpp"
#include "rbaa/sim/form.hpp"
#include "rbaa/sim/sparse_hessian.hpp"

namespace rbaa {

/// A pair's four points in the order the distance functions take them, with the simulator
/// vertex behind each (-1: a fixed obstacle point).
struct ContactPairPoints {
  Eigen::Vector3d x[4];
  int vertex[4] = {-1, -1, -1, -1};
  bool edge_edge = false;
  double eps_x = 0;  ///< mollifier threshold (edge-edge only)
};

/// s, the squared distance of the pair's closest features.
double pair_squared_distance(const ContactPairPoints& P);
/// m: the edge-edge mollifier, 1 for vertex-triangle pairs.
double pair_mollifier(const ContactPairPoints& P);
/// Gradient g and exact Hessian H of phi over the pair's 12 dofs (P within d_hat, s > 0).
void pair_derivatives(const ContactPairPoints& P, const contact::Barrier& b, contact::Vector12d& g,
                      contact::Matrix12d& H);
/// phi(P1) - phi(P0) = m1 (b(d1) - b(d0)) + (m1 - m0) b(d0), the b difference without
/// cancellation (Barrier::difference); +infinity when d1 is not positive.
double pair_value_difference(const ContactPairPoints& P0, const ContactPairPoints& P1,
                             const contact::Barrier& b);
/// grad += scale * g over the pair's movable points.
void add_pair_gradient(const ContactPairPoints& P, const contact::Vector12d& g, double scale,
                       Eigen::VectorXd& grad);
/// Adds scale * H's block over the movable points to the Hessian (kProjected: that block
/// projected to PSD first, its eigenvalues below zero clamped). Returns whether the projection
/// changed it (an eigenvalue below -1e-12 of the largest in magnitude).
bool add_pair_hessian(const ContactPairPoints& P, const contact::Matrix12d& H, double scale,
                      HessianKind kind, SparseHessian& hessian);

}  // namespace rbaa
