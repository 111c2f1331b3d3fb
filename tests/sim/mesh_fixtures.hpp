#pragma once
// Small tet meshes built by hand for the simulator's tests (no CGAL): a box of cubes split into
// 6 tets each (Freudenthal), and a coarse ball made by pushing such a box onto a sphere.

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "rbaa/mesh/tet_mesh.hpp"
#include "rbaa/scene/scene.hpp"

namespace rbaa::test {

/// nx x ny x nz cubes of side `cell` with the corner at `origin`, 6 tets per cube.
inline TetMesh box_mesh(int nx, int ny, int nz, double cell,
                        const Eigen::Vector3d& origin = Eigen::Vector3d::Zero()) {
  TetMesh m;
  auto id = [&](int i, int j, int k) { return (k * (ny + 1) + j) * (nx + 1) + i; };
  m.V.resize((nx + 1) * (ny + 1) * (nz + 1), 3);
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i)
        m.V.row(id(i, j, k)) = origin + cell * Eigen::Vector3d(i, j, k);
  const std::array<std::array<int, 3>, 6> perms = {
      {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
  m.T.resize(6 * nx * ny * nz, 4);
  int t = 0;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (const auto& p : perms) {
          std::array<int, 3> c = {i, j, k};
          m.T(t, 0) = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[p[s]];
            m.T(t, s + 1) = id(c[0], c[1], c[2]);
          }
          ++t;
        }
  orient_tets_positively(m);
  return m;
}

/// A coarse ball of the given radius centred at `centre`: an n^3 box mapped radially onto the ball
/// (each point scaled by max|x_i| / |x|, which sends the cube's surface to the sphere).
inline TetMesh ball_mesh(double radius, int n = 4,
                         const Eigen::Vector3d& centre = Eigen::Vector3d::Zero()) {
  TetMesh m = box_mesh(n, n, n, 2.0 / n, Eigen::Vector3d::Constant(-1.0));
  for (int v = 0; v < m.num_vertices(); ++v) {
    Eigen::Vector3d x = m.V.row(v).transpose();
    const double r = x.norm();
    if (r > 0) x *= x.cwiseAbs().maxCoeff() / r;
    m.V.row(v) = (centre + radius * x).transpose();
  }
  orient_tets_positively(m);
  return m;
}

/// The mesh translated so that its lowest vertex is `gap` above z = 0 (x, y unchanged).
inline TetMesh lifted(TetMesh m, double gap) {
  m.V.col(2).array() += gap - m.V.col(2).minCoeff();
  return m;
}

/// The mesh's vertices as the stacked vector q (3 #V).
/// One positively oriented tet with corners a, b, c, d.
inline TetMesh tet(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                   const Eigen::Vector3d& d) {
  TetMesh m;
  m.V.resize(4, 3);
  m.V << a.transpose(), b.transpose(), c.transpose(), d.transpose();
  m.T.resize(1, 4);
  m.T << 0, 1, 2, 3;
  orient_tets_positively(m);
  return m;
}

inline Eigen::VectorXd positions(const TetMesh& m) {
  return Eigen::Map<const Eigen::VectorXd>(m.V.data(), 3 * m.num_vertices());
}

/// q moved by a random rotation-free affine map plus a random perturbation of relative size
/// `noise` of the bounding box, with a fixed seed.
inline Eigen::VectorXd deformed(const TetMesh& m, double noise, unsigned seed,
                                const Eigen::Matrix3d& A = Eigen::Matrix3d::Identity()) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double size = (m.V.colwise().maxCoeff() - m.V.colwise().minCoeff()).norm();
  Eigen::VectorXd q(3 * m.num_vertices());
  for (int v = 0; v < m.num_vertices(); ++v) {
    Eigen::Vector3d x = A * m.V.row(v).transpose();
    for (int i = 0; i < 3; ++i) x[i] += noise * size * u(rng);
    q.segment<3>(3 * v) = x;
  }
  return q;
}

/// The smallest signed distance n . x - offset over ALL vertices of q (not only the surface list
/// the contact code uses) and every plane: an independent non-penetration check.
/// With `material` (#V flags, optional), only the flagged vertices count.
inline double min_vertex_plane_distance(const Eigen::VectorXd& q, const std::vector<Plane>& planes,
                                        const std::vector<char>& material = {}) {
  double d = std::numeric_limits<double>::infinity();
  for (Eigen::Index v = 0; v < q.size() / 3; ++v) {
    if (!material.empty() && !material[v]) continue;
    for (const Plane& p : planes) {
      d = std::min(d, p.normal.normalized().dot(q.segment<3>(3 * v)) - p.offset);
    }
  }
  return d;
}

}  // namespace rbaa::test
