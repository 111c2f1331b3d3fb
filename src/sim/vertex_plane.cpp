#include "rbaa/sim/vertex_plane.hpp"

namespace rbaa {

double vertex_plane_ccd(const Eigen::Vector3d& x0, const Eigen::Vector3d& x1, const Plane& plane,
                        double min_ratio) {
  const double d0 = vertex_plane_distance(x0, plane);
  const double d1 = vertex_plane_distance(x1, plane);
  if (d1 >= min_ratio * d0) return 1.0;
  // d(t) = d0 + t (d1 - d0) = min_ratio d0
  return (1.0 - min_ratio) * d0 / (d0 - d1);
}

}  // namespace rbaa
