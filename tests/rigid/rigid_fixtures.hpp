#pragma once
// The rigid twin's tests' world: a body's twin placed by its centre of mass, open rectangles of
// two triangles (a floor, a ramp, a backboard), and measures of a run (gaps between two runs, the
// least-squares slope of a velocity).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <vector>

#include "rbaa/geometry/moments.hpp"
#include "rbaa/mesh/tet_mesh.hpp"
#include "rbaa/rigid/rigid_body.hpp"
#include "rbaa/rigid/rigid_simulation.hpp"

namespace rbaa::test {

// The twin of `mesh` in uniform density `rho`, moved so that its centre of mass is at `centre`.
inline RigidBody twin(TetMesh mesh, const Eigen::Vector3d& centre, double rho,
                      const Eigen::Vector3d& velocity = Eigen::Vector3d::Zero(),
                      const Eigen::Vector3d& angular_velocity = Eigen::Vector3d::Zero()) {
  mesh.V.rowwise() += (centre - compute_moments(mesh, rho).centre_of_mass()).transpose();
  return RigidBody{"body", rigid_mass_properties(compute_moments(mesh, rho)),
                   rigid_shape_from_surface(mesh), velocity, angular_velocity};
}

// A rectangle as two triangles: corner + s u + t v for s, t in [0, 1] (an open surface).
inline ObstacleMesh rectangle(const Eigen::Vector3d& corner, const Eigen::Vector3d& u,
                              const Eigen::Vector3d& v) {
  ObstacleMesh m;
  m.name = "rectangle";
  m.V.resize(4, 3);
  m.V.row(0) = corner.transpose();
  m.V.row(1) = (corner + u).transpose();
  m.V.row(2) = (corner + u + v).transpose();
  m.V.row(3) = (corner + v).transpose();
  m.F.resize(2, 3);
  m.F << 0, 1, 2, 0, 2, 3;
  return m;
}

// The floor z = 0 as a 20 m square of two triangles.
inline ObstacleMesh square_floor() {
  return rectangle(Eigen::Vector3d(-10, -10, 0), Eigen::Vector3d(20, 0, 0),
                   Eigen::Vector3d(0, 20, 0));
}

inline double max_gap(const std::vector<RigidState>& a, const std::vector<RigidState>& b) {
  double gap = 0;
  for (size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    gap = std::max(gap, (a[i].position - b[i].position).norm());
  return gap;
}

inline double max_angle(const std::vector<RigidState>& a, const std::vector<RigidState>& b) {
  double angle = 0;
  for (size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    angle = std::max(angle, a[i].orientation.angularDistance(b[i].orientation));
  return angle;
}

// Least-squares slope of v(t) over the samples with t in [t0, t1].
inline double slope(const std::vector<RigidState>& states, const Eigen::Vector3d& direction,
                    double t0, double t1) {
  double n = 0, st = 0, sv = 0, stt = 0, stv = 0;
  for (const auto& s : states) {
    if (s.time < t0 || s.time > t1) continue;
    const double v = s.velocity.dot(direction);
    n += 1;
    st += s.time;
    sv += v;
    stt += s.time * s.time;
    stv += s.time * v;
  }
  return (n * stv - st * sv) / (n * stt - st * st);
}

}  // namespace rbaa::test
