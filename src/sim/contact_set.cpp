#include "rbaa/sim/contact_set.hpp"

#include <algorithm>
#include <limits>

#include "rbaa/sim/vertex_plane.hpp"

namespace rbaa {

void ContactSet::build(const Eigen::VectorXd& q) {
  vertex_plane_.clear();
  for (int v : surface_vertices_) {
    const Eigen::Vector3d x = q.segment<3>(3 * v);
    for (int p = 0; p < static_cast<int>(planes_.size()); ++p) {
      const double d = vertex_plane_distance(x, planes_[p]);
      if (d < d_hat_) vertex_plane_.push_back({v, p, d});
    }
  }
}

double ContactSet::min_distance(const Eigen::VectorXd& q) const {
  double dmin = std::numeric_limits<double>::infinity();
  for (double d : min_distance_per_plane(q)) dmin = std::min(dmin, d);
  return dmin;
}

std::vector<double> ContactSet::min_distance_per_plane(const Eigen::VectorXd& q) const {
  std::vector<double> dmin(planes_.size(), std::numeric_limits<double>::infinity());
  for (int v : surface_vertices_) {
    const Eigen::Vector3d x = q.segment<3>(3 * v);
    for (std::size_t p = 0; p < planes_.size(); ++p) {
      dmin[p] = std::min(dmin[p], vertex_plane_distance(x, planes_[p]));
    }
  }
  return dmin;
}

double ContactSet::max_step_size(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const {
  double t = 1.0;
  for (int v : surface_vertices_) {
    const Eigen::Vector3d x0 = q0.segment<3>(3 * v), x1 = q1.segment<3>(3 * v);
    for (const Plane& plane : planes_) t = std::min(t, vertex_plane_ccd(x0, x1, plane));
  }
  return t;
}

}  // namespace rbaa
