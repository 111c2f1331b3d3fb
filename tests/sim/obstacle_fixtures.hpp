#pragma once
// Static triangle-mesh obstacles for the simulator's tests: a square of two triangles, an
// axis-aligned closed box of twelve, and a small open pyramid (a spike), all placed in the world.

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "rbaa/scene/scene.hpp"

namespace rbaa::test {

inline ObstacleMesh obstacle_mesh(const std::vector<Eigen::Vector3d>& V,
                                  const std::vector<std::array<int, 3>>& F,
                                  const std::string& name) {
  ObstacleMesh m;
  m.name = name;
  m.file = name;
  m.V.resize(static_cast<Eigen::Index>(V.size()), 3);
  for (std::size_t i = 0; i < V.size(); ++i)
    m.V.row(static_cast<Eigen::Index>(i)) = V[i].transpose();
  m.F.resize(static_cast<Eigen::Index>(F.size()), 3);
  for (std::size_t i = 0; i < F.size(); ++i) {
    m.F.row(static_cast<Eigen::Index>(i)) << F[i][0], F[i][1], F[i][2];
  }
  return m;
}

/// The square [-a, a]^2 at height z, normal +z, split along the diagonal from (-a, -a) to (a, a).
inline ObstacleMesh square_obstacle(double a, double z = 0.0) {
  return obstacle_mesh({{-a, -a, z}, {a, -a, z}, {a, a, z}, {-a, a, z}}, {{0, 1, 2}, {0, 2, 3}},
                       "square");
}

/// The closed box [lo, hi], outward normals.
inline ObstacleMesh box_obstacle(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  std::vector<Eigen::Vector3d> V;
  for (int k = 0; k < 8; ++k) {
    V.emplace_back(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? hi.z() : lo.z());
  }
  return obstacle_mesh(V,
                       {{0, 2, 1},
                        {1, 2, 3},
                        {4, 5, 6},
                        {5, 7, 6},
                        {0, 1, 4},
                        {1, 5, 4},
                        {2, 6, 3},
                        {3, 6, 7},
                        {0, 4, 2},
                        {2, 4, 6},
                        {1, 3, 5},
                        {3, 7, 5}},
                       "box");
}

/// An open pyramid with apex `apex`, its square base of half-width r a height h below.
inline ObstacleMesh spike_obstacle(const Eigen::Vector3d& apex, double r, double h) {
  const Eigen::Vector3d b = apex - Eigen::Vector3d(0, 0, h);
  return obstacle_mesh({apex, b + Eigen::Vector3d(-r, -r, 0), b + Eigen::Vector3d(r, -r, 0),
                        b + Eigen::Vector3d(r, r, 0), b + Eigen::Vector3d(-r, r, 0)},
                       {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1}}, "spike");
}

}  // namespace rbaa::test
