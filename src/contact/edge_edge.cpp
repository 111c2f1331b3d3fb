#include "rbaa/contact/edge_edge.hpp"

#include "rbaa/contact/line_line.hpp"
#include "rbaa/contact/point_line.hpp"
#include "rbaa/contact/point_point.hpp"
#include "scatter.hpp"

// Point indices in the pair: ea0 = 0, ea1 = 1, eb0 = 2, eb1 = 3. An endpoint against the other
// edge's interior is that point against the other edge's line.

namespace rbaa::contact {

using detail::scatter;
using T = EdgeEdgeDistanceType;

double edge_edge_distance(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                          const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1, T type) {
  switch (type) {
    case T::EA0_EB0:
      return point_point_distance(ea0, eb0);
    case T::EA0_EB1:
      return point_point_distance(ea0, eb1);
    case T::EA1_EB0:
      return point_point_distance(ea1, eb0);
    case T::EA1_EB1:
      return point_point_distance(ea1, eb1);
    case T::EA_EB0:
      return point_line_distance(eb0, ea0, ea1);
    case T::EA_EB1:
      return point_line_distance(eb1, ea0, ea1);
    case T::EA0_EB:
      return point_line_distance(ea0, eb0, eb1);
    case T::EA1_EB:
      return point_line_distance(ea1, eb0, eb1);
    case T::EA_EB:
      break;
  }
  return line_line_distance(ea0, ea1, eb0, eb1);
}

double edge_edge_distance(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                          const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1) {
  return edge_edge_distance(ea0, ea1, eb0, eb1, edge_edge_distance_type(ea0, ea1, eb0, eb1));
}

Vector12d edge_edge_distance_gradient(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                                      const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1,
                                      T type) {
  switch (type) {
    case T::EA0_EB0:
      return scatter<2, 4>(point_point_distance_gradient(ea0, eb0), {0, 2});
    case T::EA0_EB1:
      return scatter<2, 4>(point_point_distance_gradient(ea0, eb1), {0, 3});
    case T::EA1_EB0:
      return scatter<2, 4>(point_point_distance_gradient(ea1, eb0), {1, 2});
    case T::EA1_EB1:
      return scatter<2, 4>(point_point_distance_gradient(ea1, eb1), {1, 3});
    case T::EA_EB0:
      return scatter<3, 4>(point_line_distance_gradient(eb0, ea0, ea1), {2, 0, 1});
    case T::EA_EB1:
      return scatter<3, 4>(point_line_distance_gradient(eb1, ea0, ea1), {3, 0, 1});
    case T::EA0_EB:
      return scatter<3, 4>(point_line_distance_gradient(ea0, eb0, eb1), {0, 2, 3});
    case T::EA1_EB:
      return scatter<3, 4>(point_line_distance_gradient(ea1, eb0, eb1), {1, 2, 3});
    case T::EA_EB:
      break;
  }
  return line_line_distance_gradient(ea0, ea1, eb0, eb1);
}

Vector12d edge_edge_distance_gradient(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                                      const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1) {
  return edge_edge_distance_gradient(ea0, ea1, eb0, eb1,
                                     edge_edge_distance_type(ea0, ea1, eb0, eb1));
}

Matrix12d edge_edge_distance_hessian(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                                     const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1,
                                     T type) {
  switch (type) {
    case T::EA0_EB0:
      return scatter<2, 4>(point_point_distance_hessian(ea0, eb0), {0, 2});
    case T::EA0_EB1:
      return scatter<2, 4>(point_point_distance_hessian(ea0, eb1), {0, 3});
    case T::EA1_EB0:
      return scatter<2, 4>(point_point_distance_hessian(ea1, eb0), {1, 2});
    case T::EA1_EB1:
      return scatter<2, 4>(point_point_distance_hessian(ea1, eb1), {1, 3});
    case T::EA_EB0:
      return scatter<3, 4>(point_line_distance_hessian(eb0, ea0, ea1), {2, 0, 1});
    case T::EA_EB1:
      return scatter<3, 4>(point_line_distance_hessian(eb1, ea0, ea1), {3, 0, 1});
    case T::EA0_EB:
      return scatter<3, 4>(point_line_distance_hessian(ea0, eb0, eb1), {0, 2, 3});
    case T::EA1_EB:
      return scatter<3, 4>(point_line_distance_hessian(ea1, eb0, eb1), {1, 2, 3});
    case T::EA_EB:
      break;
  }
  return line_line_distance_hessian(ea0, ea1, eb0, eb1);
}

Matrix12d edge_edge_distance_hessian(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                                     const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1) {
  return edge_edge_distance_hessian(ea0, ea1, eb0, eb1,
                                    edge_edge_distance_type(ea0, ea1, eb0, eb1));
}

}  // namespace rbaa::contact
