#include "rbaa/sim/world.hpp"

#include <Eigen/Geometry>

namespace rbaa {

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
