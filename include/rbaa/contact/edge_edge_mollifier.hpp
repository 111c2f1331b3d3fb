#pragma once
// IPC's mollifier for nearly parallel edges (Li et al. 2020, section 4.3). Two edges that turn
// parallel while in contact switch the closest features from the lines to an endpoint, so the
// barrier b(d) of an edge-edge pair is only C0 across that switch; multiplying it by
//
//   m(c) = (2 - c / eps_x) c / eps_x  for c < eps_x,  1 otherwise,   c = |(ea1-ea0) x (eb1-eb0)|^2,
//
// which vanishes with the cross product, makes the product C1. eps_x is fixed per pair at rest:
// eps_x = 1e-3 |ea0-ea1|^2 |eb0-eb1|^2 (so the mollifier acts below an angle of about 1.8 deg).
// m is C1 at c = eps_x (m = 1, m' = 0 on both sides) but not C2: m'' jumps from -2/eps_x^2 to 0.
//
// Derivatives with respect to the current positions (ea0, ea1, eb0, eb1) (12 dofs) are for the
// forward Newton solve; those with respect to the rest positions (through eps_x only) are for a
// shape derivative. The latter is the path on which a well-known library used the positions'
// gradient of m where the rest gradient of eps_x belongs; tests reach it.

#include <Eigen/Core>

#include "rbaa/contact/fixed_size.hpp"

namespace rbaa::contact {

/// c = |(ea1 - ea0) x (eb1 - eb0)|^2.
double edge_edge_cross_squarednorm(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                                   const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1);
/// dc/d(ea0, ea1, eb0, eb1): with a = ea1 - ea0, b = eb1 - eb0, n = a x b,
/// dc/da = 2 b x n, dc/db = 2 n x a.
Vector12d edge_edge_cross_squarednorm_gradient(const Eigen::Vector3d& ea0,
                                               const Eigen::Vector3d& ea1,
                                               const Eigen::Vector3d& eb0,
                                               const Eigen::Vector3d& eb1);
/// d2c/d(ea0, ea1, eb0, eb1)^2 (exact).
Matrix12d edge_edge_cross_squarednorm_hessian(const Eigen::Vector3d& ea0,
                                              const Eigen::Vector3d& ea1,
                                              const Eigen::Vector3d& eb0,
                                              const Eigen::Vector3d& eb1);

/// m(c) as a function of c (see above), and its first and second derivatives in c.
double mollifier(double c, double eps_x);
double mollifier_derivative(double c, double eps_x);
double mollifier_second_derivative(double c, double eps_x);
/// dm/d eps_x = (2 c / eps_x^2) (c / eps_x - 1) for c < eps_x, 0 otherwise.
double mollifier_derivative_wrt_eps_x(double c, double eps_x);

/// eps_x = 1e-3 |ea0 - ea1|^2 |eb0 - eb1|^2, from the rest positions.
double edge_edge_mollifier_threshold(const Eigen::Vector3d& ea0_rest,
                                     const Eigen::Vector3d& ea1_rest,
                                     const Eigen::Vector3d& eb0_rest,
                                     const Eigen::Vector3d& eb1_rest);
/// d eps_x / d(rest positions).
Vector12d edge_edge_mollifier_threshold_gradient(const Eigen::Vector3d& ea0_rest,
                                                 const Eigen::Vector3d& ea1_rest,
                                                 const Eigen::Vector3d& eb0_rest,
                                                 const Eigen::Vector3d& eb1_rest);

/// m(c(x)) for the current positions x = (ea0, ea1, eb0, eb1).
double edge_edge_mollifier(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                           const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1, double eps_x);
/// m'(c) dc/dx (zero for c >= eps_x).
Vector12d edge_edge_mollifier_gradient(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                                       const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1,
                                       double eps_x);
/// m''(c) dc/dx dc/dx^T + m'(c) d2c/dx2 (zero for c >= eps_x).
Matrix12d edge_edge_mollifier_hessian(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                                      const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1,
                                      double eps_x);
/// Gradient of m with respect to the rest positions, which enter through eps_x only:
/// dm/d eps_x * d eps_x / d(rest).
Vector12d edge_edge_mollifier_gradient_wrt_rest(
    const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1, const Eigen::Vector3d& eb0,
    const Eigen::Vector3d& eb1, const Eigen::Vector3d& ea0_rest, const Eigen::Vector3d& ea1_rest,
    const Eigen::Vector3d& eb0_rest, const Eigen::Vector3d& eb1_rest);

}  // namespace rbaa::contact
