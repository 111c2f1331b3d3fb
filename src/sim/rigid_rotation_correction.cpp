#include "rbaa/sim/rigid_rotation_correction.hpp"

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include <cmath>

namespace rbaa {

Eigen::VectorXd rigid_rotation_correction(const Eigen::VectorXd& x, const Eigen::VectorXd& dq,
                                          const Eigen::VectorXd& vertex_masses) {
  const Eigen::Index n = vertex_masses.size();
  const double m = vertex_masses.sum();
  Eigen::Vector3d c = Eigen::Vector3d::Zero(), t = Eigen::Vector3d::Zero();
  for (Eigen::Index i = 0; i < n; ++i) {
    c += vertex_masses[i] * x.segment<3>(3 * i);
    t += vertex_masses[i] * dq.segment<3>(3 * i);
  }
  c /= m;
  t /= m;
  // Best-fit w: (sum m_i [r_i]x^T [r_i]x) w = sum m_i r_i x (dq_i - t)  (inertia tensor about c).
  Eigen::Matrix3d I = Eigen::Matrix3d::Zero();
  Eigen::Vector3d L = Eigen::Vector3d::Zero();
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d r = x.segment<3>(3 * i) - c;
    I += vertex_masses[i] * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
    L += vertex_masses[i] * r.cross(dq.segment<3>(3 * i) - t);
  }
  const Eigen::Vector3d w = I.ldlt().solve(L);
  const double angle = w.norm();
  if (!(angle > 1e-12) || !std::isfinite(angle)) return dq;
  const Eigen::Matrix3d Rm = Eigen::AngleAxisd(angle, w / angle).toRotationMatrix() -
                             Eigen::Matrix3d::Identity();
  Eigen::VectorXd out(dq.size());
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d r = x.segment<3>(3 * i) - c;
    out.segment<3>(3 * i) = dq.segment<3>(3 * i) + Rm * r - w.cross(r);
  }
  return out;
}

}  // namespace rbaa
