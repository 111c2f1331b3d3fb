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

UnitElementMass::UnitElementMass(const TetMesh& rest, MassModel model)
    : T_(rest.T), volume_(tet_volumes(rest)), model_(model) {}

double UnitElementMass::product(int e, const Eigen::VectorXd& a, const Eigen::VectorXd& u) const {
  double diag = 0;
  Eigen::Vector3d sa = Eigen::Vector3d::Zero(), su = Eigen::Vector3d::Zero();
  for (int i = 0; i < 4; ++i) {
    const int v = T_(e, i);
    diag += a.segment<3>(3 * v).dot(u.segment<3>(3 * v));
    sa += a.segment<3>(3 * v);
    su += u.segment<3>(3 * v);
  }
  return model_ == MassModel::kConsistent ? (sa.dot(su) + diag) / 20.0 : diag / 4.0;
}

void UnitElementMass::add_times(int e, double dm, const Eigen::VectorXd& u, Eigen::VectorXd& out) const {
  if (model_ == MassModel::kConsistent) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int i = 0; i < 4; ++i) sum += u.segment<3>(3 * T_(e, i));
    for (int i = 0; i < 4; ++i) {
      const int v = T_(e, i);
      out.segment<3>(3 * v) += dm / 20.0 * (sum + u.segment<3>(3 * v));
    }
  } else {
    for (int i = 0; i < 4; ++i) {
      const int v = T_(e, i);
      out.segment<3>(3 * v) += dm / 4.0 * u.segment<3>(3 * v);
    }
  }
}

double UnitElementMass::mass_change(int e, const MaterialField& materials,
                                    const MaterialGradient& d) const {
  const double drho = d.rho.size() == 0 ? 0.0 : d.rho[e];
  const double dalpha = d.alpha.size() == 0 ? 0.0 : d.alpha[e];
  return volume_[e] * (materials.alpha[e] * drho + materials.rho[e] * dalpha);
}

void UnitElementMass::add_mass_gradient(int e, double c, const MaterialField& materials,
                                        MaterialGradient& g) const {
  g.rho[e] += c * materials.alpha[e] * volume_[e];
  g.alpha[e] += c * materials.rho[e] * volume_[e];
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
