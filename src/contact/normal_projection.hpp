#pragma once
// Shared by point-plane and line-line (private to the module): the squared length of r's
// component along n = a x b,
//
//   f(r, a, b) = (r.n)^2 / |n|^2,
//
// with its gradient and Hessian with respect to (r, a, b) (9 dofs), and the chain rule to the
// 12 dofs of four points when r, a, b are differences of them. With s = r.n, q = n.n:
//
//   df/dr = 2 s n / q,   df/dn = (2 s / q) (r - (s / q) n),
//   d2f/dr2 = 2 n n^T / q,
//   d2f/dr dn = (2 / q) (n r^T + s I) - (4 s / q^2) n n^T,
//   d2f/dn2 = 2 r r^T / q - (4 s / q^2) (r n^T + n r^T) - (2 s^2 / q^2) I + (8 s^2 / q^3) n n^T,
//
// and n is bilinear in (a, b): dn = -[b]x da + [a]x db, d2n_k / da_i db_j = eps_kij, which adds
// -[df/dn]x to the (a, b) block of the Hessian.

#include <Eigen/Core>

#include "rbaa/contact/fixed_size.hpp"

namespace rbaa::contact::detail {

double normal_projection(const Eigen::Vector3d& r, const Eigen::Vector3d& a,
                         const Eigen::Vector3d& b);
Vector9d normal_projection_gradient(const Eigen::Vector3d& r, const Eigen::Vector3d& a,
                                    const Eigen::Vector3d& b);
Matrix9d normal_projection_hessian(const Eigen::Vector3d& r, const Eigen::Vector3d& a,
                                   const Eigen::Vector3d& b);

/// [v]x, the matrix of v x (.).
Eigen::Matrix3d cross_matrix(const Eigen::Vector3d& v);

/// The 9 x 12 matrix of the linear map from four points (x0, x1, x2, x3) to (r, a, b), each of
/// r, a, b being x_plus - x_minus (point indices into the four).
Eigen::Matrix<double, 9, 12> difference_map(int r_plus, int r_minus, int a_plus, int a_minus,
                                            int b_plus, int b_minus);

}  // namespace rbaa::contact::detail
