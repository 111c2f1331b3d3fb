#include "rbaa/contact/point_triangle.hpp"

#include "rbaa/contact/point_line.hpp"
#include "rbaa/contact/point_plane.hpp"
#include "rbaa/contact/point_point.hpp"
#include "scatter.hpp"

namespace rbaa::contact {

using detail::scatter;
using T = PointTriangleDistanceType;

double point_triangle_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                               const Eigen::Vector3d& t1, const Eigen::Vector3d& t2, T type) {
  switch (type) {
    case T::P_T0:
      return point_point_distance(p, t0);
    case T::P_T1:
      return point_point_distance(p, t1);
    case T::P_T2:
      return point_point_distance(p, t2);
    case T::P_E0:
      return point_line_distance(p, t0, t1);
    case T::P_E1:
      return point_line_distance(p, t1, t2);
    case T::P_E2:
      return point_line_distance(p, t2, t0);
    case T::P_T:
      break;
  }
  return point_plane_distance(p, t0, t1, t2);
}

double point_triangle_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                               const Eigen::Vector3d& t1, const Eigen::Vector3d& t2) {
  return point_triangle_distance(p, t0, t1, t2, point_triangle_distance_type(p, t0, t1, t2));
}

Vector12d point_triangle_distance_gradient(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                                           const Eigen::Vector3d& t1, const Eigen::Vector3d& t2,
                                           T type) {
  switch (type) {
    case T::P_T0:
      return scatter<2, 4>(point_point_distance_gradient(p, t0), {0, 1});
    case T::P_T1:
      return scatter<2, 4>(point_point_distance_gradient(p, t1), {0, 2});
    case T::P_T2:
      return scatter<2, 4>(point_point_distance_gradient(p, t2), {0, 3});
    case T::P_E0:
      return scatter<3, 4>(point_line_distance_gradient(p, t0, t1), {0, 1, 2});
    case T::P_E1:
      return scatter<3, 4>(point_line_distance_gradient(p, t1, t2), {0, 2, 3});
    case T::P_E2:
      return scatter<3, 4>(point_line_distance_gradient(p, t2, t0), {0, 3, 1});
    case T::P_T:
      break;
  }
  return point_plane_distance_gradient(p, t0, t1, t2);
}

Vector12d point_triangle_distance_gradient(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                                           const Eigen::Vector3d& t1, const Eigen::Vector3d& t2) {
  return point_triangle_distance_gradient(p, t0, t1, t2,
                                          point_triangle_distance_type(p, t0, t1, t2));
}

Matrix12d point_triangle_distance_hessian(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                                          const Eigen::Vector3d& t1, const Eigen::Vector3d& t2,
                                          T type) {
  switch (type) {
    case T::P_T0:
      return scatter<2, 4>(point_point_distance_hessian(p, t0), {0, 1});
    case T::P_T1:
      return scatter<2, 4>(point_point_distance_hessian(p, t1), {0, 2});
    case T::P_T2:
      return scatter<2, 4>(point_point_distance_hessian(p, t2), {0, 3});
    case T::P_E0:
      return scatter<3, 4>(point_line_distance_hessian(p, t0, t1), {0, 1, 2});
    case T::P_E1:
      return scatter<3, 4>(point_line_distance_hessian(p, t1, t2), {0, 2, 3});
    case T::P_E2:
      return scatter<3, 4>(point_line_distance_hessian(p, t2, t0), {0, 3, 1});
    case T::P_T:
      break;
  }
  return point_plane_distance_hessian(p, t0, t1, t2);
}

Matrix12d point_triangle_distance_hessian(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                                          const Eigen::Vector3d& t1, const Eigen::Vector3d& t2) {
  return point_triangle_distance_hessian(p, t0, t1, t2,
                                         point_triangle_distance_type(p, t0, t1, t2));
}

}  // namespace rbaa::contact
