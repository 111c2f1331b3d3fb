#include "rbaa/mesh/grid_mesh.hpp"

#include <algorithm>
#include <array>

#include "rbaa/error.hpp"

namespace rbaa {

TetMesh box_tet_mesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int nx, int ny, int nz) {
  if (nx < 1 || ny < 1 || nz < 1 || !((hi - lo).minCoeff() > 0)) {
    throw InputError("box_tet_mesh needs hi > lo and at least one cell per axis");
  }
  auto vid = [&](int i, int j, int k) { return i + (nx + 1) * (j + (ny + 1) * k); };
  TetMesh mesh;
  mesh.V.resize((nx + 1) * (ny + 1) * (nz + 1), 3);
  for (int k = 0; k <= nz; ++k) {
    for (int j = 0; j <= ny; ++j) {
      for (int i = 0; i <= nx; ++i) {
        const Eigen::Vector3d t(double(i) / nx, double(j) / ny, double(k) / nz);
        mesh.V.row(vid(i, j, k)) = (lo.array() + t.array() * (hi - lo).array()).matrix().transpose();
      }
    }
  }
  mesh.T.resize(6 * nx * ny * nz, 4);
  int e = 0;
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        // One tet per ordering of the axes: walk from corner (0,0,0) to (1,1,1) one axis at a time.
        std::array<int, 3> axes = {0, 1, 2};
        do {
          std::array<int, 3> c = {i, j, k};
          mesh.T(e, 0) = vid(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[axes[s]];
            mesh.T(e, s + 1) = vid(c[0], c[1], c[2]);
          }
          ++e;
        } while (std::next_permutation(axes.begin(), axes.end()));
      }
    }
  }
  orient_tets_positively(mesh);
  return mesh;
}

}  // namespace rbaa
