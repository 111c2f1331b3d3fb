#include "rbaa/sim/rigid_rotation_correction.hpp"

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>

#include "rbaa/sim/observables.hpp"

namespace rbaa {

RigidClusters RigidClusters::whole(int num_vertices) {
  RigidClusters c;
  c.cluster.assign(num_vertices, 0);
  c.count = num_vertices > 0 ? 1 : 0;
  c.hinge.assign(c.count, {});
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

// The w minimising sum m |d_i - w x r_i|^2 from the tensor I = sum m (|r|^2 - r r^T) and
// L = sum m r x d; a pseudo-inverse where I is singular (a flap whose vertices lie on one line
// through its hinge cannot fix the rotation about that line, and needs none).
Eigen::Vector3d best_fit_rotation(const Eigen::Matrix3d& I, const Eigen::Vector3d& L) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(I);
  const Eigen::Vector3d lambda = eig.eigenvalues();
  const double cut = 1e-12 * lambda.cwiseAbs().maxCoeff();
  Eigen::Vector3d w = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) {
    if (lambda[k] > cut) {
      const Eigen::Vector3d u = eig.eigenvectors().col(k);
      w += u * (u.dot(L) / lambda[k]);
    }
  }
  return w;
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
  // Union-find over the stiff elements through shared faces: two stiff regions touching only at
  // an edge or a vertex turn independently about it, so they are two clusters.
  std::vector<int> parent(nt);
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<char> stiff(nt, 0);
  std::map<std::array<int, 3>, int> face_owner;
  for (int e = 0; e < nt; ++e) {
    if (stiffness[e] < ratio * largest) continue;
    stiff[e] = 1;
    for (int skip = 0; skip < 4; ++skip) {
      std::array<int, 3> f;
      for (int a = 0, k = 0; a < 4; ++a) {
        if (a != skip) f[k++] = mesh.T(e, a);
      }
      std::sort(f.begin(), f.end());
      const auto [it, inserted] = face_owner.emplace(f, e);
      if (!inserted) {
        const int r0 = find_root(parent, e), r1 = find_root(parent, it->second);
        if (r0 != r1) parent[std::max(r0, r1)] = std::min(r0, r1);
      }
    }
  }
  // Mass of each component, then its rank: heaviest first, ties by its first element.
  std::vector<double> mass(nt, 0.0);
  for (int e = 0; e < nt; ++e) {
    if (!stiff[e]) continue;
    const Eigen::Vector3d a = mesh.V.row(mesh.T(e, 0)).transpose();
    const double volume = std::abs((mesh.V.row(mesh.T(e, 1)).transpose() - a)
                                       .cross(mesh.V.row(mesh.T(e, 2)).transpose() - a)
                                       .dot(mesh.V.row(mesh.T(e, 3)).transpose() - a)) / 6.0;
    mass[find_root(parent, e)] += materials.rho[e] * materials.alpha[e] * volume;
  }
  std::vector<int> roots;
  for (int e = 0; e < nt; ++e) {
    if (stiff[e] && find_root(parent, e) == e) roots.push_back(e);
  }
  std::stable_sort(roots.begin(), roots.end(), [&](int a, int b) { return mass[a] > mass[b]; });
  std::vector<int> rank(nt, -1);
  for (std::size_t k = 0; k < roots.size(); ++k) rank[roots[k]] = static_cast<int>(k);

  RigidClusters c;
  c.count = static_cast<int>(roots.size());
  c.cluster.assign(nv, -1);
  c.hinge.assign(c.count, {});
  std::vector<std::vector<int>> members(c.count);
  for (int e = 0; e < nt; ++e) {
    if (!stiff[e]) continue;
    const int k = rank[find_root(parent, e)];
    for (int a = 0; a < 4; ++a) {
      const int v = mesh.T(e, a);
      members[k].push_back(v);
      if (c.cluster[v] < 0 || k < c.cluster[v]) c.cluster[v] = k;
    }
  }
  for (int k = 0; k < c.count; ++k) {
    std::sort(members[k].begin(), members[k].end());
    members[k].erase(std::unique(members[k].begin(), members[k].end()), members[k].end());
    for (int v : members[k]) {
      if (c.cluster[v] < k) c.hinge[k].push_back(v);
    }
  }
  return c;
}

Eigen::VectorXd rigid_rotation_correction(const Eigen::VectorXd& x, const Eigen::VectorXd& dq,
                                          const Eigen::VectorXd& vertex_masses,
                                          const RigidClusters& clusters) {
  const Eigen::Index n = vertex_masses.size();
  const int k = clusters.count;
  // Each cluster's own vertices (those it is the heaviest cluster of), in vertex order.
  std::vector<std::vector<int>> own(k);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (clusters.cluster[i] >= 0) own[clusters.cluster[i]].push_back(static_cast<int>(i));
  }
  Eigen::VectorXd out = dq;
  // Heaviest first, so that a flap's hinge has been corrected by its heavier clusters.
  for (int j = 0; j < k; ++j) {
    const std::vector<int>& hinge = j < static_cast<int>(clusters.hinge.size())
                                        ? clusters.hinge[j]
                                        : std::vector<int>{};
    // Centre c and the motion d_c it takes linearly (t) and with its corrections (t + shift).
    Eigen::Vector3d c = Eigen::Vector3d::Zero(), t = Eigen::Vector3d::Zero();
    Eigen::Vector3d shift = Eigen::Vector3d::Zero();
    if (hinge.empty()) {
      double mass = 0;
      for (int i : own[j]) {
        mass += vertex_masses[i];
        c += vertex_masses[i] * x.segment<3>(3 * i);
        t += vertex_masses[i] * dq.segment<3>(3 * i);
      }
      if (!(mass > 0)) continue;
      c /= mass;
      t /= mass;
    } else {
      for (int i : hinge) {
        c += x.segment<3>(3 * i);
        t += dq.segment<3>(3 * i);
        shift += out.segment<3>(3 * i) - dq.segment<3>(3 * i);
      }
      c /= static_cast<double>(hinge.size());
      t /= static_cast<double>(hinge.size());
      shift /= static_cast<double>(hinge.size());
    }
    // Best-fit w: (sum m_i [r_i]x^T [r_i]x) w = sum m_i r_i x (dq_i - t) over the cluster's
    // vertices, its hinge included (the hinge pins the axis of a flap).
    Eigen::Matrix3d I = Eigen::Matrix3d::Zero();
    Eigen::Vector3d L = Eigen::Vector3d::Zero();
    auto add = [&](int i) {
      const Eigen::Vector3d r = x.segment<3>(3 * i) - c;
      I += vertex_masses[i] * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
      L += vertex_masses[i] * r.cross(dq.segment<3>(3 * i) - t);
    };
    for (int i : own[j]) add(i);
    for (int i : hinge) add(i);
    const Eigen::Vector3d w = hinge.empty() ? Eigen::Vector3d(I.ldlt().solve(L))
                                            : best_fit_rotation(I, L);
    const double angle = w.norm();
    if (!(angle > 1e-12) || !std::isfinite(angle)) {
      for (int i : own[j]) out.segment<3>(3 * i) += shift;
      continue;
    }
    const Eigen::Matrix3d Rm =
        Eigen::AngleAxisd(angle, w / angle).toRotationMatrix() - Eigen::Matrix3d::Identity();
    for (int i : own[j]) {
      const Eigen::Vector3d r = x.segment<3>(3 * i) - c;
      out.segment<3>(3 * i) += shift + Rm * r - w.cross(r);
    }
  }
  return out;
}

namespace {

// The vertex ranges the rigid motions act on: each body's, or the whole mesh.
std::vector<std::pair<Eigen::Index, Eigen::Index>> rigid_ranges(const std::vector<Body>& bodies,
                                                               Eigen::Index num_vertices) {
  std::vector<std::pair<Eigen::Index, Eigen::Index>> ranges;
  for (const Body& b : bodies) ranges.emplace_back(b.vertex_begin, b.vertex_end);
  if (ranges.empty()) ranges.emplace_back(0, num_vertices);
  return ranges;
}

}  // namespace

Eigen::VectorXd rigid_predictor(const Eigen::VectorXd& from, const Eigen::VectorXd& to,
                                const Eigen::VectorXd& vertex_masses,
                                const std::vector<Body>& bodies) {
  Eigen::VectorXd out = to;
  for (const auto& [begin, end] : rigid_ranges(bodies, vertex_masses.size())) {
    const Eigen::Index n = end - begin;
    const auto m = vertex_masses.segment(begin, n);
    const auto f = from.segment(3 * begin, 3 * n), t = to.segment(3 * begin, 3 * n);
    const Eigen::Vector3d a = centre_of_mass(f, m), b = centre_of_mass(t, m);
    Eigen::Matrix3d S = Eigen::Matrix3d::Zero();  // sum m (to - b)(from - a)^T
    for (Eigen::Index i = 0; i < n; ++i) {
      S += m[i] * (t.segment<3>(3 * i) - b) * (f.segment<3>(3 * i) - a).transpose();
    }
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(S, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
    D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
    const Eigen::Matrix3d R = svd.matrixU() * D * svd.matrixV().transpose();
    for (Eigen::Index i = 0; i < n; ++i) {
      out.segment<3>(3 * (begin + i)) = b + R * (f.segment<3>(3 * i) - a);
    }
  }
  return out;
}

Eigen::VectorXd rigid_newton_step(const Eigen::VectorXd& x, const Eigen::VectorXd& g,
                                  const Eigen::SparseMatrix<double>& H_lower,
                                  const Eigen::VectorXd& vertex_masses,
                                  const std::vector<Body>& bodies) {
  const Eigen::Index n = vertex_masses.size();
  if (x.size() != 3 * n || g.size() != 3 * n) return {};
  const auto ranges = rigid_ranges(bodies, n);
  const Eigen::Index k = static_cast<Eigen::Index>(ranges.size());
  std::vector<Eigen::Vector3d> centres;
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(3 * n, 6 * k);
  for (Eigen::Index b = 0; b < k; ++b) {
    const auto [begin, end] = ranges[b];
    const auto m = vertex_masses.segment(begin, end - begin);
    if (!(m.sum() > 0)) return {};
    centres.push_back(centre_of_mass(x.segment(3 * begin, 3 * (end - begin)), m));
    for (Eigen::Index i = begin; i < end; ++i) {
      const Eigen::Vector3d r = x.segment<3>(3 * i) - centres[b];
      G.block<3, 3>(3 * i, 6 * b).setIdentity();
      // Column 6 b + 3 + j: e_j x r.
      G.block<3, 3>(3 * i, 6 * b + 3) << 0, r.z(), -r.y(), -r.z(), 0, r.x(), r.y(), -r.x(), 0;
    }
  }
  const Eigen::MatrixXd HG = H_lower.selfadjointView<Eigen::Lower>() * G;
  const Eigen::MatrixXd A = G.transpose() * HG;
  const Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (A + A.transpose()));
  if (llt.info() != Eigen::Success) return {};
  const Eigen::VectorXd d = llt.solve(-(G.transpose() * g));
  Eigen::VectorXd out = Eigen::VectorXd::Zero(3 * n);
  for (Eigen::Index b = 0; b < k; ++b) {
    const Eigen::Vector3d t = d.segment<3>(6 * b), w = d.segment<3>(6 * b + 3);
    const double angle = w.norm();
    Eigen::Matrix3d Rm = Eigen::Matrix3d::Zero();
    if (angle > 0 && std::isfinite(angle)) {
      Rm = Eigen::AngleAxisd(angle, w / angle).toRotationMatrix() - Eigen::Matrix3d::Identity();
    }
    for (Eigen::Index i = ranges[b].first; i < ranges[b].second; ++i) {
      out.segment<3>(3 * i) = t + Rm * (x.segment<3>(3 * i) - centres[b]);
    }
  }
  return out;
}

}  // namespace rbaa
