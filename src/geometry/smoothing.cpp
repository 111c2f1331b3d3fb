#include "rbaa/geometry/smoothing.hpp"

#include <Eigen/SparseCholesky>

#include <cmath>
#include <sstream>

#include "rbaa/error.hpp"
#include "rbaa/geometry/laplacian.hpp"

namespace rbaa {

TetMesh false_barycentric_subdivision(const TetMesh& mesh) {
  const int nv = mesh.num_vertices(), nt = mesh.num_tets();
  TetMesh sub;
  sub.V.resize(nv + nt, 3);
  sub.V.topRows(nv) = mesh.V;
  sub.T.resize(4 * nt, 4);
  for (int e = 0; e < nt; ++e) {
    sub.V.row(nv + e) = 0.25 * (mesh.V.row(mesh.T(e, 0)) + mesh.V.row(mesh.T(e, 1)) +
                                mesh.V.row(mesh.T(e, 2)) + mesh.V.row(mesh.T(e, 3)));
    // The barycentre lies on the same side of every face as the vertex it replaces, so each child
    // keeps the parent's orientation (and a quarter of its volume).
    for (int k = 0; k < 4; ++k) {
      sub.T.row(4 * e + k) = mesh.T.row(e);
      sub.T(4 * e + k, k) = nv + e;
    }
  }
  return sub;
}

struct GradientSmoother::Impl {
  int num_vertices = 0;
  double gamma = 0.0;
  Eigen::VectorXd volumes;
  // Factorised once: every application is one pair of triangular solves.
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt;
};

GradientSmoother::GradientSmoother(const TetMesh& mesh, double gamma_relative)
    : impl_(std::make_unique<Impl>()) {
  if (!(gamma_relative > 0.0 && std::isfinite(gamma_relative))) {
    std::ostringstream msg;
    msg << "smoothing gamma = " << gamma_relative
        << " (relative to the mean edge length squared) must be positive and finite";
    throw InputError(msg.str());
  }
  const int nv = mesh.num_vertices(), nt = mesh.num_tets();
  impl_->num_vertices = nv;
  const double h = mean_edge_length(mesh);
  impl_->gamma = gamma_relative * h * h;
  impl_->volumes = tet_volumes(mesh);

  const Eigen::SparseMatrix<double> Lt = cotangent_laplacian(false_barycentric_subdivision(mesh));
  Eigen::SparseMatrix<double> Mt(nv + nt, nv + nt);
  std::vector<Eigen::Triplet<double>> diag;
  diag.reserve(nt);
  for (int e = 0; e < nt; ++e) diag.emplace_back(nv + e, nv + e, impl_->volumes[e]);
  Mt.setFromTriplets(diag.begin(), diag.end());
  const Eigen::SparseMatrix<double> K = Mt - impl_->gamma * Lt;

  impl_->ldlt.compute(K);
  if (impl_->ldlt.info() != Eigen::Success) {
    throw SolverError("gradient smoothing: the factorisation of K = Mt - gamma Lt failed");
  }
}

GradientSmoother::~GradientSmoother() = default;
GradientSmoother::GradientSmoother(GradientSmoother&&) noexcept = default;
GradientSmoother& GradientSmoother::operator=(GradientSmoother&&) noexcept = default;

int GradientSmoother::num_tets() const { return static_cast<int>(impl_->volumes.size()); }
double GradientSmoother::gamma() const { return impl_->gamma; }
const Eigen::VectorXd& GradientSmoother::volumes() const { return impl_->volumes; }

Eigen::VectorXd GradientSmoother::apply(const Eigen::VectorXd& g) const {
  const int nv = impl_->num_vertices, nt = num_tets();
  if (g.size() != nt) {
    std::ostringstream msg;
    msg << "gradient smoothing: input has " << g.size() << " entries, the mesh " << nt
        << " elements";
    throw InputError(msg.str());
  }
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(nv + nt);
  rhs.tail(nt) = g;
  const Eigen::VectorXd x = impl_->ldlt.solve(rhs);
  return x.tail(nt);
}

Eigen::VectorXd GradientSmoother::apply_interior(const std::vector<int>& interior,
                                                 const Eigen::VectorXd& g) const {
  if (static_cast<size_t>(g.size()) != interior.size()) {
    std::ostringstream msg;
    msg << "gradient smoothing: " << g.size() << " gradient entries for " << interior.size()
        << " interior elements";
    throw InputError(msg.str());
  }
  Eigen::VectorXd full = Eigen::VectorXd::Zero(num_tets());
  for (size_t i = 0; i < interior.size(); ++i) {
    if (interior[i] < 0 || interior[i] >= num_tets()) {
      throw InputError("gradient smoothing: interior element " + std::to_string(interior[i]) +
                       " out of range");
    }
    full[interior[i]] = g[static_cast<Eigen::Index>(i)];
  }
  const Eigen::VectorXd smooth = apply(full);
  Eigen::VectorXd out(g.size());
  for (size_t i = 0; i < interior.size(); ++i) out[static_cast<Eigen::Index>(i)] = smooth[interior[i]];
  return out;
}

}  // namespace rbaa
