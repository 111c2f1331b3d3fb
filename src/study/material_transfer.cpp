#include "rbaa/study/material_transfer.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>

namespace rbaa {

ElementLocator::ElementLocator(const TetMesh& mesh) : mesh_(mesh) {
  const int nt = mesh.num_tets();
  centroids_.resize(nt, 3);
  inverse_.resize(nt);
  lo_ = mesh.V.colwise().minCoeff().transpose();
  const Eigen::Vector3d hi = mesh.V.colwise().maxCoeff().transpose();
  const Eigen::Vector3d extent = (hi - lo_).cwiseMax(1e-12);
  // About one element per bucket: side = (volume of the box / #T)^(1/3).
  const double side = std::cbrt(extent.prod() / std::max(1, nt));
  for (int i = 0; i < 3; ++i) dims_[i] = std::max(1, static_cast<int>(std::ceil(extent[i] / side)));
  cell_size_ = extent.cwiseQuotient(dims_.cast<double>());
  const long nb = long(dims_[0]) * dims_[1] * dims_[2];
  std::vector<int> count(nb + 1, 0);
  std::vector<std::pair<Eigen::Vector3i, Eigen::Vector3i>> ranges(nt);
  for (int e = 0; e < nt; ++e) {
    Eigen::Matrix<double, 4, 3> X;
    for (int a = 0; a < 4; ++a) X.row(a) = mesh.V.row(mesh.T(e, a));
    centroids_.row(e) = X.colwise().mean();
    Eigen::Matrix3d D;
    for (int a = 0; a < 3; ++a) D.col(a) = (X.row(a + 1) - X.row(0)).transpose();
    inverse_[e] = D.inverse();
    ranges[e] = {cell(X.colwise().minCoeff().transpose()), cell(X.colwise().maxCoeff().transpose())};
  }
  auto for_cells = [&](int e, auto&& f) {
    const auto& [a, b] = ranges[e];
    for (int i = a[0]; i <= b[0]; ++i)
      for (int j = a[1]; j <= b[1]; ++j)
        for (int k = a[2]; k <= b[2]; ++k) f(bucket({i, j, k}));
  };
  for (int e = 0; e < nt; ++e) for_cells(e, [&](long b) { ++count[b + 1]; });
  start_.assign(nb + 1, 0);
  for (long b = 0; b < nb; ++b) start_[b + 1] = start_[b] + count[b + 1];
  items_.resize(start_[nb]);
  std::vector<int> fill(start_.begin(), start_.end() - 1);
  for (int e = 0; e < nt; ++e) for_cells(e, [&](long b) { items_[fill[b]++] = e; });
}

Eigen::Vector3i ElementLocator::cell(const Eigen::Vector3d& p) const {
  Eigen::Vector3i c;
  for (int i = 0; i < 3; ++i) {
    c[i] = std::clamp(static_cast<int>(std::floor((p[i] - lo_[i]) / cell_size_[i])), 0, dims_[i] - 1);
  }
  return c;
}

long ElementLocator::bucket(const Eigen::Vector3i& c) const {
  return (long(c[2]) * dims_[1] + c[1]) * dims_[0] + c[0];
}

int ElementLocator::containing(const Eigen::Vector3d& p, double tolerance) const {
  const Eigen::Vector3d lo = mesh_.V.colwise().minCoeff().transpose() - cell_size_ * 1e-9;
  const Eigen::Vector3d hi = mesh_.V.colwise().maxCoeff().transpose() + cell_size_ * 1e-9;
  if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any()) return -1;
  const long b = bucket(cell(p));
  int best = -1;
  for (int s = start_[b]; s < start_[b + 1]; ++s) {
    const int e = items_[s];
    const Eigen::Vector3d l = inverse_[e] * (p - mesh_.V.row(mesh_.T(e, 0)).transpose());
    if (l.minCoeff() >= -tolerance && 1.0 - l.sum() >= -tolerance && (best < 0 || e < best)) best = e;
  }
  return best;
}

int ElementLocator::containing_or_nearest(const Eigen::Vector3d& p) const {
  const int e = containing(p);
  if (e >= 0) return e;
  Eigen::Index nearest = 0;
  (centroids_.rowwise() - p.transpose()).rowwise().squaredNorm().minCoeff(&nearest);
  return static_cast<int>(nearest);
}

std::vector<int> centroid_lookup(const TetMesh& from, const TetMesh& to) {
  const ElementLocator locator(from);
  std::vector<int> source(to.num_tets());
  for (int e = 0; e < to.num_tets(); ++e) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int a = 0; a < 4; ++a) c += to.V.row(to.T(e, a)).transpose();
    source[e] = locator.containing_or_nearest(c / 4.0);
  }
  return source;
}

Eigen::MatrixXd transfer_element_values(const TetMesh& from, const Eigen::MatrixXd& values,
                                        const TetMesh& to) {
  const std::vector<int> source = centroid_lookup(from, to);
  Eigen::MatrixXd out(to.num_tets(), values.cols());
  for (int e = 0; e < to.num_tets(); ++e) out.row(e) = values.row(source[e]);
  return out;
}

MaterialField transfer_materials(const TetMesh& from, const MaterialField& field, const TetMesh& to) {
  Eigen::MatrixXd values(field.size(), 4);
  values << field.Y, field.nu, field.rho, field.alpha;
  const Eigen::MatrixXd moved = transfer_element_values(from, values, to);
  MaterialField out;
  out.Y = moved.col(0);
  out.nu = moved.col(1);
  out.rho = moved.col(2);
  out.alpha = moved.col(3);
  return out;
}

}  // namespace rbaa
