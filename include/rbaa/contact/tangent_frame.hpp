#pragma once
// Where two primitives touch, as friction needs it (IPC, Li et al. 2020, section 5.1): the
// closest points' weights and a basis of the tangent plane, per distance type
// (distance_type.hpp), so that
//
//   r = sum_i gamma_i x_i      (closest point of the first primitive minus that of the second),
//   u = T^T r                  (its tangential part, 2 components),
//
// over the pair's four points x = (p, t0, t1, t2) or (ea0, ea1, eb0, eb1). T (3x2) has orthonormal
// columns normal to the contact normal of the type:
//
//   point-point (p, q):      n = p - q; T = (a x n, n x (a x n)) normalised, a the x axis or the
//                            y axis, whichever is less parallel to n (decided on the values; the
//                            projector T T^T = I - n n^T / |n|^2 does not depend on the choice);
//   point-edge (p, e0, e1):  T = (e, e x (p - e0)) normalised, e = e1 - e0;
//   point-triangle:          T = (e0, n x e0) normalised, e0 = t1 - t0, n = e0 x (t2 - t0);
//   edge-edge (lines):       T = (a, (a x b) x a) normalised, a = ea1 - ea0, b = eb1 - eb0.
//
// and the weights are the closest points' barycentric coordinates on the features of the type
// (a projection parameter on a line, two on a plane, two on a pair of lines), with the weights
// of points the type does not involve zero. The type is an input: friction lags it from the
// previous step and holds it fixed (a piecewise choice, as IPC does), so the frame and its
// Jacobian are smooth functions of the 12 coordinates for a given type.

#include <Eigen/Core>

#include "rbaa/contact/distance_type.hpp"
#include "rbaa/contact/fixed_size.hpp"

namespace rbaa::contact {

struct TangentFrame {
  Eigen::Vector4d gamma;              ///< closest-point weights, one per point of the pair
  Eigen::Matrix<double, 3, 2> basis;  ///< T, orthonormal columns
};

/// Derivatives of a frame with respect to the pair's 12 coordinates (point after point).
struct TangentFrameJacobian {
  Eigen::Matrix<double, 4, 12> gamma;  ///< d gamma_i / d x_k
  Eigen::Matrix<double, 6, 12> basis;  ///< row 3 j + i: d T(i, j) / d x_k
};

TangentFrame point_triangle_tangent_frame(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                                          const Eigen::Vector3d& t1, const Eigen::Vector3d& t2,
                                          PointTriangleDistanceType type);
TangentFrame edge_edge_tangent_frame(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                                     const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1,
                                     EdgeEdgeDistanceType type);

/// The frames' exact Jacobians (forward-mode automatic differentiation, ceres::Jet).
TangentFrameJacobian point_triangle_tangent_frame_jacobian(const Eigen::Vector3d& p,
                                                           const Eigen::Vector3d& t0,
                                                           const Eigen::Vector3d& t1,
                                                           const Eigen::Vector3d& t2,
                                                           PointTriangleDistanceType type);
TangentFrameJacobian edge_edge_tangent_frame_jacobian(const Eigen::Vector3d& ea0,
                                                      const Eigen::Vector3d& ea1,
                                                      const Eigen::Vector3d& eb0,
                                                      const Eigen::Vector3d& eb1,
                                                      EdgeEdgeDistanceType type);

}  // namespace rbaa::contact
