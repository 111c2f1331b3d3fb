#pragma once
// Structured tet meshes of boxes: small, exact test objects with known moments.

#include <Eigen/Core>

#include "rbaa/mesh/tet_mesh.hpp"

namespace rbaa {

/// The box [lo, hi] cut into nx by ny by nz cells, each split into 6 tets around its main
/// diagonal (Kuhn/Freudenthal split, conforming between cells); (nx+1)(ny+1)(nz+1) vertices,
/// 6 nx ny nz positively oriented tets.
TetMesh box_tet_mesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int nx, int ny, int nz);

}  // namespace rbaa
