#include "rbaa/geometry/laplacian.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <utility>
#include <vector>

namespace rbaa {

Eigen::SparseMatrix<double> cotangent_laplacian(const TetMesh& mesh) {
  const int nt = mesh.num_tets();
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(16 * static_cast<size_t>(nt));
  for (int e = 0; e < nt; ++e) {
    Eigen::Vector3d p[4];
    for (int k = 0; k < 4; ++k) p[k] = mesh.V.row(mesh.T(e, k)).transpose();
    Eigen::Matrix3d Dm;
    Dm << p[1] - p[0], p[2] - p[0], p[3] - p[0];
    const double vol = std::abs(Dm.determinant()) / 6.0;
    // Gradients of the hat functions: rows of Dm^-1 for vertices 1..3, minus their sum for 0.
    const Eigen::Matrix3d Dinv = Dm.inverse();
    Eigen::Matrix<double, 3, 4> G;
    G.col(0) = -Dinv.transpose().rowwise().sum();
    G.rightCols<3>() = Dinv.transpose();
    const Eigen::Matrix4d K = vol * G.transpose() * G;
    for (int a = 0; a < 4; ++a) {
      for (int b = 0; b < 4; ++b) triplets.emplace_back(mesh.T(e, a), mesh.T(e, b), -K(a, b));
    }
  }
  Eigen::SparseMatrix<double> L(mesh.num_vertices(), mesh.num_vertices());
  // setFromTriplets sums duplicates in triplet order, which is element order.
  L.setFromTriplets(triplets.begin(), triplets.end());
  return L;
}

double mean_edge_length(const TetMesh& mesh) {
  std::vector<std::pair<int, int>> edges;
  edges.reserve(6 * static_cast<size_t>(mesh.num_tets()));
  for (int e = 0; e < mesh.num_tets(); ++e) {
    for (int a = 0; a < 4; ++a) {
      for (int b = a + 1; b < 4; ++b) {
        const int i = mesh.T(e, a), j = mesh.T(e, b);
        edges.emplace_back(std::min(i, j), std::max(i, j));
      }
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  double sum = 0.0;
  for (const auto& [i, j] : edges) sum += (mesh.V.row(i) - mesh.V.row(j)).norm();
  return edges.empty() ? 0.0 : sum / static_cast<double>(edges.size());
}

}  // namespace rbaa
