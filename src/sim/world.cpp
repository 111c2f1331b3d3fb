#include "rbaa/sim/world.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "rbaa/error.hpp"

namespace rbaa {

namespace {

// integral of omega from the table's first time to t (the table is non-empty).
double table_integral(const std::vector<Eigen::Vector2d>& rows, double t) {
  if (t <= rows.front()[0]) return rows.front()[1] * (t - rows.front()[0]);
  double sum = 0;
  for (std::size_t i = 0; i + 1 < rows.size(); ++i) {
    const double t0 = rows[i][0], t1 = rows[i + 1][0], w0 = rows[i][1], w1 = rows[i + 1][1];
    const double s = std::min(t, t1);
    const double ws = w0 + (w1 - w0) * (s - t0) / (t1 - t0);
    sum += 0.5 * (s - t0) * (w0 + ws);  // trapezoid: omega is linear on the piece
    if (t <= t1) return sum;
  }
  return sum + rows.back()[1] * (t - rows.back()[0]);
}

}  // namespace

double PrescribedMotion::angular_speed(double t) const {
  const std::vector<Eigen::Vector2d>& rows = angular_velocity_table;
  if (rows.empty()) return angular_velocity;
  if (t <= rows.front()[0]) return rows.front()[1];
  for (std::size_t i = 0; i + 1 < rows.size(); ++i) {
    if (t <= rows[i + 1][0]) {
      return rows[i][1] +
             (rows[i + 1][1] - rows[i][1]) * (t - rows[i][0]) / (rows[i + 1][0] - rows[i][0]);
    }
  }
  return rows.back()[1];
}

double PrescribedMotion::angle(double t) const {
  if (angular_velocity_table.empty()) return angular_velocity * t;
  return table_integral(angular_velocity_table, t) - table_integral(angular_velocity_table, 0.0);
}

Eigen::Matrix3d PrescribedMotion::rotation(double t) const {
  return Eigen::AngleAxisd(angle(t), axis).toRotationMatrix();
}

Eigen::Vector3d PrescribedMotion::position(const Eigen::Vector3d& x0, double t) const {
  return centre + t * velocity + rotation(t) * (x0 - centre);
}

Eigen::Vector3d PrescribedMotion::point_velocity(const Eigen::Vector3d& x0, double t) const {
  const Eigen::Vector3d r = rotation(t) * (x0 - centre);
  return velocity + angular_speed(t) * axis.cross(r);
}

void validate_prescribed_motion(const PrescribedMotion& m, const std::string& who) {
  auto fail = [&](const std::string& what) { throw InputError(who + ": " + what); };
  if (!m.axis.allFinite() || std::abs(m.axis.norm() - 1.0) > 1e-9) {
    fail("the drive's axis must be a finite unit vector");
  }
  if (!m.centre.allFinite() || !m.velocity.allFinite() || !std::isfinite(m.angular_velocity)) {
    fail("the drive's centre, velocity and angular velocity must be finite");
  }
  for (std::size_t i = 0; i < m.angular_velocity_table.size(); ++i) {
    if (!m.angular_velocity_table[i].allFinite())
      fail("the drive's angular velocity table is not finite");
    if (i > 0 && !(m.angular_velocity_table[i][0] > m.angular_velocity_table[i - 1][0])) {
      std::ostringstream msg;
      msg << "the drive's angular velocity table's times must strictly increase (row " << i
          << " at t = " << m.angular_velocity_table[i][0] << " s)";
      fail(msg.str());
    }
  }
}

std::vector<int> driven_dofs(const std::vector<Body>& bodies) {
  std::vector<int> dofs;
  for (const Body& b : bodies) {
    for (int v : b.driven_vertices) {
      for (int k = 0; k < 3; ++k) dofs.push_back(3 * v + k);
    }
  }
  std::sort(dofs.begin(), dofs.end());
  return dofs;
}

std::vector<int> vertex_body_ids(const std::vector<Body>& bodies, int num_vertices) {
  std::vector<int> ids(num_vertices, -1);
  for (int b = 0; b < static_cast<int>(bodies.size()); ++b) {
    for (int v = bodies[b].vertex_begin; v < bodies[b].vertex_end; ++v) ids[v] = b;
  }
  return ids;
}

Eigen::VectorXd rigid_velocities(const Eigen::VectorXd& q, const Eigen::Vector3d& centre,
                                 const Eigen::Vector3d& velocity,
                                 const Eigen::Vector3d& angular_velocity) {
  Eigen::VectorXd v(q.size());
  for (Eigen::Index i = 0; i < q.size() / 3; ++i) {
    v.segment<3>(3 * i) = velocity + angular_velocity.cross(q.segment<3>(3 * i) - centre);
  }
  return v;
}

Eigen::VectorXd initial_velocities(const Eigen::VectorXd& q, const std::vector<Body>& bodies) {
  Eigen::VectorXd v = Eigen::VectorXd::Zero(q.size());
  for (const Body& b : bodies) {
    for (int i = b.vertex_begin; i < b.vertex_end; ++i) {
      v.segment<3>(3 * i) = b.velocity + b.angular_velocity.cross(q.segment<3>(3 * i) - b.centre);
    }
  }
  return v;
}

}  // namespace rbaa
