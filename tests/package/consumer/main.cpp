// Meshes-free use of the installed library: moments of a unit box at density 1.
#include <rbaa/geometry/moments.hpp>
#include <rbaa/mesh/grid_mesh.hpp>

#include <cmath>
#include <iostream>

int main() {
  const rbaa::TetMesh mesh = rbaa::box_tet_mesh({0, 0, 0}, {1, 1, 1}, 2, 2, 2);
  const rbaa::Moments m = rbaa::compute_moments(mesh, 1.0);
  std::cout << "m0 = " << m.m0 << "\n";
  return std::abs(m.m0 - 1.0) < 1e-12 ? 0 : 1;
}
