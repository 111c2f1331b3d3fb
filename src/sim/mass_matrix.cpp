#include "rbaa/sim/mass_matrix.hpp"

namespace rbaa {

Eigen::VectorXd element_masses(const TetMesh& rest, const Eigen::VectorXd& density) {
  return tet_volumes(rest).cwiseProduct(density);
}

Eigen::SparseMatrix<double> mass_matrix(const TetMesh& rest, const Eigen::VectorXd& density,
                                        MassModel model, SparseHessian& pattern) {
  const Eigen::VectorXd m = element_masses(rest, density);
  pattern.set_zero();
  if (model == MassModel::kConsistent) {
    for (int e = 0; e < rest.num_tets(); ++e) {
      double* H = pattern.element_block(e);
      for (int c = 0; c < 12; ++c) {
        for (int r = c; r < 12; ++r) {
          if (r % 3 != c % 3) continue;  // the blocks are multiples of I_3
          H[SparseHessian::packed_index(r, c)] += m[e] / 20.0 * (r / 3 == c / 3 ? 2.0 : 1.0);
        }
      }
    }
  } else {
    const Eigen::VectorXd mv = vertex_masses(rest, density);
    for (int v = 0; v < rest.num_vertices(); ++v) {
      pattern.vertex_block(v) += mv[v] * Eigen::Matrix3d::Identity();
    }
  }
  Eigen::SparseMatrix<double> M = pattern.assemble();
  pattern.set_zero();
  return M;
}

Eigen::VectorXd vertex_masses(const TetMesh& rest, const Eigen::VectorXd& density) {
  const Eigen::VectorXd m = element_masses(rest, density);
  Eigen::VectorXd mv = Eigen::VectorXd::Zero(rest.num_vertices());
  for (int e = 0; e < rest.num_tets(); ++e) {
    for (int a = 0; a < 4; ++a) mv[rest.T(e, a)] += m[e] / 4.0;
  }
  return mv;
}

}  // namespace rbaa
