#include "rbaa/contact/point_plane.hpp"

#include "normal_projection.hpp"

// d = f(r, a, b) with r = p - t0, a = t1 - t0, b = t2 - t0 (normal_projection.hpp); the map from
// (p, t0, t1, t2) to (r, a, b) is linear, so the Hessian is M^T H_f M with no further term.

namespace rbaa::contact {
namespace {

const Eigen::Matrix<double, 9, 12>& point_plane_map() {
  static const Eigen::Matrix<double, 9, 12> M = detail::difference_map(0, 1, 2, 1, 3, 1);
  return M;
}

}  // namespace

double point_plane_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                            const Eigen::Vector3d& t1, const Eigen::Vector3d& t2) {
  return detail::normal_projection(p - t0, t1 - t0, t2 - t0);
}

Vector12d point_plane_distance_gradient(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                                        const Eigen::Vector3d& t1, const Eigen::Vector3d& t2) {
  return point_plane_map().transpose() *
         detail::normal_projection_gradient(p - t0, t1 - t0, t2 - t0);
}

Matrix12d point_plane_distance_hessian(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                                       const Eigen::Vector3d& t1, const Eigen::Vector3d& t2) {
  const auto& M = point_plane_map();
  return M.transpose() * detail::normal_projection_hessian(p - t0, t1 - t0, t2 - t0) * M;
}

}  // namespace rbaa::contact
