#include "rbaa/contact/solid_angle.hpp"

#include <Eigen/Geometry>
#include <cmath>

namespace rbaa::contact {

double solid_angle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                   const Eigen::Vector3d& c) {
  // tan(omega / 2) = u . (v x w) / (|u||v||w| + (u.v)|w| + (v.w)|u| + (w.u)|v|).
  const Eigen::Vector3d u = a - p, v = b - p, w = c - p;
  const double lu = u.norm(), lv = v.norm(), lw = w.norm();
  const double num = u.dot(v.cross(w));
  const double den = lu * lv * lw + u.dot(v) * lw + v.dot(w) * lu + w.dot(u) * lv;
  return 2.0 * std::atan2(num, den);
}

double surface_solid_angle(const Eigen::Vector3d& p, const Eigen::Ref<const Positions>& V,
                           const Eigen::Ref<const Triangles>& F) {
  double omega = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    omega += solid_angle(p, V.row(F(f, 0)).transpose(), V.row(F(f, 1)).transpose(),
                         V.row(F(f, 2)).transpose());
  }
  return omega;
}

}  // namespace rbaa::contact
