#include "rbaa/sim/observables.hpp"

#include <Eigen/SVD>

#include <algorithm>
#include <limits>

namespace rbaa {

Eigen::Vector3d centre_of_mass(const Eigen::VectorXd& q, const Eigen::VectorXd& vertex_masses) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int v = 0; v < vertex_masses.size(); ++v) c += vertex_masses[v] * q.segment<3>(3 * v);
  return c / vertex_masses.sum();
}

Eigen::Vector3d linear_momentum(const Eigen::VectorXd& Mv) {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (Eigen::Index v = 0; v < Mv.size() / 3; ++v) p += Mv.segment<3>(3 * v);
  return p;
}

Eigen::Vector3d angular_momentum(const Eigen::VectorXd& q, const Eigen::VectorXd& Mv) {
  Eigen::Vector3d L = Eigen::Vector3d::Zero();
  for (Eigen::Index v = 0; v < Mv.size() / 3; ++v) {
    L += q.segment<3>(3 * v).cross(Mv.segment<3>(3 * v));
  }
  return L;
}

Eigen::Quaterniond best_fit_rotation(const Eigen::VectorXd& rest, const Eigen::VectorXd& q,
                                     const Eigen::VectorXd& vertex_masses) {
  const Eigen::Vector3d c0 = centre_of_mass(rest, vertex_masses), c = centre_of_mass(q, vertex_masses);
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();  // sum m (x - c)(X - c0)^T
  for (int v = 0; v < vertex_masses.size(); ++v) {
    A += vertex_masses[v] * (q.segment<3>(3 * v) - c) * (rest.segment<3>(3 * v) - c0).transpose();
  }
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) D(2, 2) = -1;
  const Eigen::Matrix3d R = svd.matrixU() * D * svd.matrixV().transpose();
  Eigen::Quaterniond quat(R);
  quat.normalize();
  if (quat.w() < 0) quat.coeffs() *= -1.0;
  return quat;
}

std::vector<Bounce> find_bounces(const std::vector<std::vector<double>>& distances,
                                 const std::vector<Eigen::Vector3d>& com_velocity,
                                 const std::vector<Plane>& planes, double d_hat,
                                 const Eigen::Vector3d& gravity, double time_step, int settle_steps) {
  std::vector<Bounce> bounces;
  const int n = static_cast<int>(distances.size());
  auto in_contact = [&](int k) {
    for (double d : distances[k]) {
      if (d < d_hat) return true;
    }
    return false;
  };
  for (int p = 0; p < static_cast<int>(planes.size()); ++p) {
    int k = 0;
    while (k < n) {
      if (distances[k][p] >= d_hat) {
        ++k;
        continue;
      }
      Bounce b;
      b.plane = p;
      b.first_step = k;
      while (k < n && distances[k][p] < d_hat) ++k;
      b.last_step = k - 1;
      const Eigen::Vector3d& normal = planes[p].normal;
      b.normal_velocity_in = normal.dot(com_velocity[std::max(0, b.first_step - 1)]);
      b.complete = k < n;
      if (b.complete) {
        // BDF-2's velocity settles after a bounce through its parasitic root 1/3 (the ball's
        // rebound read 0.925 one step after contact and 1.166 once settled), so the outgoing
        // velocity is read `settle_steps` later (before any next contact), with the gravity of the
        // steps in between taken back out.
        int j = k;
        while (j + 1 < n && j - k < settle_steps && !in_contact(j + 1)) ++j;
        b.normal_velocity_out = normal.dot(com_velocity[j] - gravity * time_step * (j - k));
        b.restitution = -b.normal_velocity_out / b.normal_velocity_in;
      } else {
        b.normal_velocity_out = normal.dot(com_velocity[n - 1]);
        b.restitution = std::numeric_limits<double>::quiet_NaN();
      }
      bounces.push_back(b);
    }
  }
  std::sort(bounces.begin(), bounces.end(),
            [](const Bounce& a, const Bounce& b) { return a.first_step < b.first_step; });
  return bounces;
}

}  // namespace rbaa
