#include "rbaa/study/gradient_comparison.hpp"

#include <algorithm>
#include <cmath>

#include "rbaa/study/material_transfer.hpp"

namespace rbaa {

Eigen::MatrixXd gradient_density(const TetMesh& mesh, const MaterialGradient& gradient,
                                 const Eigen::Vector4d& half_ranges,
                                 const std::vector<std::string>& fields) {
  const int nt = mesh.num_tets();
  const Eigen::VectorXd V = tet_volumes(mesh);
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(nt, 4);
  const char* names[4] = {"Y", "nu", "rho", "alpha"};
  const Eigen::VectorXd* columns[4] = {&gradient.Y, &gradient.nu, &gradient.rho, &gradient.alpha};
  for (int f = 0; f < 4; ++f) {
    if (std::find(fields.begin(), fields.end(), names[f]) == fields.end()) continue;
    if (columns[f]->size() != nt) continue;
    d.col(f) = columns[f]->cwiseQuotient(V) * half_ranges[f];
  }
  return d;
}

double gradient_cosine(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b,
                       const Eigen::VectorXd& volumes) {
  double ab = 0, aa = 0, bb = 0;
  for (Eigen::Index e = 0; e < a.rows(); ++e) {
    ab += volumes[e] * a.row(e).dot(b.row(e));
    aa += volumes[e] * a.row(e).squaredNorm();
    bb += volumes[e] * b.row(e).squaredNorm();
  }
  if (!(aa > 0) || !(bb > 0)) return 0.0;
  return ab / std::sqrt(aa * bb);
}

double gradient_cosine_across(const TetMesh& mesh_a, const Eigen::MatrixXd& a,
                              const TetMesh& mesh_b, const Eigen::MatrixXd& b) {
  const bool same = mesh_a.T.rows() == mesh_b.T.rows() && mesh_a.V.rows() == mesh_b.V.rows() &&
                    mesh_a.T == mesh_b.T && mesh_a.V == mesh_b.V;
  const Eigen::MatrixXd moved = same ? a : transfer_element_values(mesh_a, a, mesh_b);
  return gradient_cosine(moved, b, tet_volumes(mesh_b));
}

}  // namespace rbaa
