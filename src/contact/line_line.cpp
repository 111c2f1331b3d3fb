#include "rbaa/contact/line_line.hpp"

#include "normal_projection.hpp"

// d = f(r, a, b) with r = ea0 - eb0, a = ea1 - ea0, b = eb1 - eb0 (normal_projection.hpp); the
// map from (ea0, ea1, eb0, eb1) to (r, a, b) is linear, so the Hessian is M^T H_f M.

namespace rbaa::contact {
namespace {

const Eigen::Matrix<double, 9, 12>& line_line_map() {
  static const Eigen::Matrix<double, 9, 12> M = detail::difference_map(0, 2, 1, 0, 3, 2);
  return M;
}

}  // namespace

double line_line_distance(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                          const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1) {
  return detail::normal_projection(ea0 - eb0, ea1 - ea0, eb1 - eb0);
}

Vector12d line_line_distance_gradient(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                                      const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1) {
  return line_line_map().transpose() *
         detail::normal_projection_gradient(ea0 - eb0, ea1 - ea0, eb1 - eb0);
}

Matrix12d line_line_distance_hessian(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                                     const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1) {
  const auto& M = line_line_map();
  return M.transpose() * detail::normal_projection_hessian(ea0 - eb0, ea1 - ea0, eb1 - eb0) * M;
}

}  // namespace rbaa::contact
