#include "rbaa/sim/rigid_rotation_correction.hpp"

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include <cmath>
#include <numeric>

#include "rbaa/sim/observables.hpp"

namespace rbaa {

RigidClusters RigidClusters::whole(int num_vertices) {
  RigidClusters c;
  c.cluster.assign(num_vertices, 0);
  c.count = num_vertices > 0 ? 1 : 0;
  return c;
}

namespace {

int find_root(std::vector<int>& parent, int v) {
  while (parent[v] != v) {
    parent[v] = parent[parent[v]];
    v = parent[v];
  }
  return v;
}

}  // namespace

RigidClusters stiff_clusters(const TetMesh& mesh, const MaterialField& materials, double ratio) {
  const int nv = mesh.num_vertices(), nt = mesh.num_tets();
  std::vector<double> stiffness(nt);
  double largest = 0;
  for (int e = 0; e < nt; ++e) {
    const double a = materials.alpha[e];
    stiffness[e] = a * a * a * materials.Y[e];
    largest = std::max(largest, stiffness[e]);
  }
  // Union-find over shared vertices, not face adjacency (label_components): a vertex belongs to
  // exactly one cluster, so two stiff regions touching at a vertex or an edge are one.
  std::vector<int> parent(nv);
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<char> stiff_vertex(nv, 0);
  for (int e = 0; e < nt; ++e) {
    if (stiffness[e] < ratio * largest) continue;
    const int r0 = find_root(parent, mesh.T(e, 0));
    stiff_vertex[mesh.T(e, 0)] = 1;
    for (int a = 1; a < 4; ++a) {
      stiff_vertex[mesh.T(e, a)] = 1;
      const int ra = find_root(parent, mesh.T(e, a));
      if (ra != r0) parent[ra] = find_root(parent, r0);
    }
  }
  // Number the clusters in order of their first vertex (deterministic).
  RigidClusters c;
  c.cluster.assign(nv, -1);
  std::vector<int> id(nv, -1);
  for (int v = 0; v < nv; ++v) {
    if (!stiff_vertex[v]) continue;
    const int r = find_root(parent, v);
    if (id[r] < 0) id[r] = c.count++;
    c.cluster[v] = id[r];
  }
  return c;
}

Eigen::VectorXd rigid_rotation_correction(const Eigen::VectorXd& x, const Eigen::VectorXd& dq,
                                          const Eigen::VectorXd& vertex_masses,
                                          const RigidClusters& clusters) {
  const Eigen::Index n = vertex_masses.size();
  const int k = clusters.count;
  std::vector<double> mass(k, 0.0);
  std::vector<Eigen::Vector3d> c(k, Eigen::Vector3d::Zero()), t(k, Eigen::Vector3d::Zero());
  for (Eigen::Index i = 0; i < n; ++i) {
    const int j = clusters.cluster[i];
    if (j < 0) continue;
    mass[j] += vertex_masses[i];
    c[j] += vertex_masses[i] * x.segment<3>(3 * i);
    t[j] += vertex_masses[i] * dq.segment<3>(3 * i);
  }
  for (int j = 0; j < k; ++j) {
    if (mass[j] > 0) {
      c[j] /= mass[j];
      t[j] /= mass[j];
    }
  }
  // Best-fit w per cluster: (sum m_i [r_i]x^T [r_i]x) w = sum m_i r_i x (dq_i - t)  (inertia
  // tensor about the cluster's centre).
  std::vector<Eigen::Matrix3d> I(k, Eigen::Matrix3d::Zero());
  std::vector<Eigen::Vector3d> L(k, Eigen::Vector3d::Zero());
  for (Eigen::Index i = 0; i < n; ++i) {
    const int j = clusters.cluster[i];
    if (j < 0) continue;
    const Eigen::Vector3d r = x.segment<3>(3 * i) - c[j];
    I[j] += vertex_masses[i] * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
    L[j] += vertex_masses[i] * r.cross(dq.segment<3>(3 * i) - t[j]);
  }
  std::vector<Eigen::Vector3d> w(k);
  std::vector<Eigen::Matrix3d> Rm(k);
  std::vector<char> rotates(k, 0);
  for (int j = 0; j < k; ++j) {
    w[j] = I[j].ldlt().solve(L[j]);
    const double angle = w[j].norm();
    if (!(angle > 1e-12) || !std::isfinite(angle)) continue;
    rotates[j] = 1;
    Rm[j] = Eigen::AngleAxisd(angle, w[j] / angle).toRotationMatrix() - Eigen::Matrix3d::Identity();
  }
  Eigen::VectorXd out = dq;
  for (Eigen::Index i = 0; i < n; ++i) {
    const int j = clusters.cluster[i];
    if (j < 0 || !rotates[j]) continue;
    const Eigen::Vector3d r = x.segment<3>(3 * i) - c[j];
    out.segment<3>(3 * i) += Rm[j] * r - w[j].cross(r);
  }
  return out;
}

Eigen::VectorXd rigid_predictor(const Eigen::VectorXd& from, const Eigen::VectorXd& to,
                                const Eigen::VectorXd& vertex_masses) {
  const Eigen::Index n = vertex_masses.size();
  const Eigen::Vector3d a = centre_of_mass(from, vertex_masses), b = centre_of_mass(to, vertex_masses);
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();  // sum m (to - b)(from - a)^T
  for (Eigen::Index i = 0; i < n; ++i) {
    S += vertex_masses[i] * (to.segment<3>(3 * i) - b) * (from.segment<3>(3 * i) - a).transpose();
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(S, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  const Eigen::Matrix3d R = svd.matrixU() * D * svd.matrixV().transpose();
  Eigen::VectorXd out(3 * n);
  for (Eigen::Index i = 0; i < n; ++i) out.segment<3>(3 * i) = b + R * (from.segment<3>(3 * i) - a);
  return out;
}

Eigen::VectorXd rigid_newton_step(const Eigen::VectorXd& x, const Eigen::VectorXd& g,
                                  const Eigen::SparseMatrix<double>& H_lower,
                                  const Eigen::VectorXd& vertex_masses) {
  const Eigen::Index n = vertex_masses.size();
  if (!(vertex_masses.sum() > 0) || x.size() != 3 * n || g.size() != 3 * n) return {};
  const Eigen::Vector3d c = centre_of_mass(x, vertex_masses);
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(3 * n, 6);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d r = x.segment<3>(3 * i) - c;
    G.block<3, 3>(3 * i, 0).setIdentity();
    // Column 3 + k: e_k x r.
    G.block<3, 3>(3 * i, 3) << 0, r.z(), -r.y(), -r.z(), 0, r.x(), r.y(), -r.x(), 0;
  }
  const Eigen::MatrixXd HG = H_lower.selfadjointView<Eigen::Lower>() * G;
  const Eigen::Matrix<double, 6, 6> A = G.transpose() * HG;
  const Eigen::LLT<Eigen::Matrix<double, 6, 6>> llt(0.5 * (A + A.transpose()));
  if (llt.info() != Eigen::Success) return {};
  const Eigen::Matrix<double, 6, 1> d = llt.solve(-(G.transpose() * g));
  const Eigen::Vector3d t = d.head<3>(), w = d.tail<3>();
  const double angle = w.norm();
  Eigen::Matrix3d Rm = Eigen::Matrix3d::Zero();
  if (angle > 0 && std::isfinite(angle)) {
    Rm = Eigen::AngleAxisd(angle, w / angle).toRotationMatrix() - Eigen::Matrix3d::Identity();
  }
  Eigen::VectorXd out(3 * n);
  for (Eigen::Index i = 0; i < n; ++i) out.segment<3>(3 * i) = t + Rm * (x.segment<3>(3 * i) - c);
  return out;
}

}  // namespace rbaa
