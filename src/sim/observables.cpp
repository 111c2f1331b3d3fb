#include "rbaa/sim/observables.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <limits>
#include <sstream>
#include <string>

#include "rbaa/error.hpp"

namespace rbaa {

Eigen::Vector3d centre_of_mass(const Eigen::VectorXd& q, const Eigen::VectorXd& vertex_masses) {
  if (q.size() != 3 * vertex_masses.size()) {
    std::ostringstream msg;
    msg << "centre of mass: " << q.size() << " coordinates for " << vertex_masses.size()
        << " vertex masses";
    throw InputError(msg.str());
  }
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

const char* bounce_kind_name(BounceKind kind) {
  switch (kind) {
    case BounceKind::kBounce:
      return "bounce";
    case BounceKind::kCorner:
      return "corner";
    case BounceKind::kNoReversal:
      return "no_reversal";
    case BounceKind::kUnfinished:
      return "unfinished";
  }
  return "?";
}

namespace {

// "0", "0 and 1", "0, 1 and 2".
std::string plane_list(const std::vector<int>& planes) {
  std::string s;
  for (size_t i = 0; i < planes.size(); ++i) {
    if (i > 0) s += i + 1 == planes.size() ? " and " : ", ";
    s += std::to_string(planes[i]);
  }
  return s;
}

}  // namespace

std::vector<Bounce> find_bounces(const std::vector<std::vector<double>>& distances,
                                 const std::vector<Eigen::Vector3d>& com_velocity,
                                 const std::vector<Plane>& planes, double d_hat,
                                 const Eigen::Vector3d& gravity, double time_step, int settle_steps) {
  std::vector<Bounce> bounces;
  const int n = static_cast<int>(distances.size());
  const int num_planes = static_cast<int>(planes.size());
  auto in_contact = [&](int k) {
    for (double d : distances[k]) {
      if (d < d_hat) return true;
    }
    return false;
  };
  int k = 0;
  while (k < n) {
    if (!in_contact(k)) {
      ++k;
      continue;
    }
    Bounce b;
    b.first_step = k;
    std::vector<char> touched(num_planes, 0);
    // A body that leaves d_hat still approaching every plane it touched is still in the same
    // impact; it ends when the centre of mass turns away from one of those planes.
    k = impact_end(
        k, n, in_contact,
        [&](int j) {
          for (int p = 0; p < num_planes; ++p) touched[p] |= distances[j][p] < d_hat;
        },
        [&](int j) {
          for (int p = 0; p < num_planes; ++p) {
            if (touched[p] && planes[p].normal.dot(com_velocity[j]) > 0) return false;
          }
          return true;
        });
    b.last_step = k - 1;
    for (int p = 0; p < num_planes; ++p) {
      if (touched[p]) b.planes.push_back(p);
    }
    const bool over = k < n;
    // BDF-2's velocity settles after a bounce through its parasitic root 1/3 (the ball's rebound
    // read 0.925 one step after contact and 1.166 once settled), so the outgoing velocity is read
    // `settle_steps` later (before any next contact), with the gravity of the steps in between
    // taken back out.
    int j = over ? k : n - 1;
    if (over) {
      while (j + 1 < n && j - k < settle_steps && !in_contact(j + 1)) ++j;
    }
    b.out_step = j;
    const Eigen::Vector3d v_in = com_velocity[std::max(0, b.first_step - 1)];
    const int settled = over ? j - k : 0;
    const Eigen::Vector3d v_out = com_velocity[j] - gravity * time_step * settled;
    for (int p : b.planes) {
      b.normal_velocity_in.push_back(planes[p].normal.dot(v_in));
      b.normal_velocity_out.push_back(planes[p].normal.dot(v_out));
    }
    std::ostringstream note;
    if (!over) {
      b.kind = BounceKind::kUnfinished;
      note << "still in contact with plane" << (b.planes.size() > 1 ? "s " : " ")
           << plane_list(b.planes) << " at the end of the run";
    } else if (b.planes.size() > 1) {
      b.kind = BounceKind::kCorner;
      note << "planes " << plane_list(b.planes)
           << " were touched within one contact episode (a corner): each pushes the velocity "
              "along the others' normals, so no restitution is a bounce off one plane";
    } else if (!(b.normal_velocity_in[0] < 0 && b.normal_velocity_out[0] > 0)) {
      b.kind = BounceKind::kNoReversal;
      note << "the centre of mass's normal velocity went from " << b.normal_velocity_in[0] << " to "
           << b.normal_velocity_out[0] << " m/s: it did not reverse, so this contact is no bounce";
    } else {
      b.kind = BounceKind::kBounce;
      b.restitution = -b.normal_velocity_out[0] / b.normal_velocity_in[0];
    }
    b.note = note.str();
    bounces.push_back(b);
  }
  return bounces;
}

}  // namespace rbaa
