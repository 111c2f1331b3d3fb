#pragma once
// Gradient smoothing of theta_alpha (SPEC section 4, the paper's Eq. 10 corrected): on the false
// barycentric subdivision of the mesh, with Lt its cotangent Laplacian (negative semi-definite),
// Mt the diagonal holding element volumes at the barycentre vertices (0 at the original vertices),
// N the #T by (#V + #T) selection of the barycentre vertices, A = diag(volumes) and
// K = Mt - gamma Lt (symmetric positive definite):
//     g_smooth = N K^-1 N^T g.
// The operator is symmetric positive definite, so -g_smooth is a descent direction; it maps A 1
// to 1, keeps sum(A g_smooth) = sum(g), tends to A^-1 g as gamma -> 0 and to the constant
// sum(g) / sum(A) as gamma -> infinity.

#include <Eigen/Core>

#include <memory>
#include <vector>

#include "rbaa/mesh/tet_mesh.hpp"

namespace rbaa {

/// The false barycentric subdivision: #V + #T vertices (the originals, then element e's
/// barycentre at index #V + e) and 4 #T tets (element e's children at 4e .. 4e + 3, child k being
/// e with its local vertex k replaced by the barycentre; orientation is kept).
TetMesh false_barycentric_subdivision(const TetMesh& mesh);

class GradientSmoother {
 public:
  /// Builds K for gamma = gamma_relative * (mean edge length of `mesh`)^2 and factorises it once
  /// (sparse LDL^T, AMD ordering). Throws rbaa::InputError unless gamma_relative > 0 is finite,
  /// rbaa::SolverError if the factorisation fails.
  GradientSmoother(const TetMesh& mesh, double gamma_relative = 1.0);
  ~GradientSmoother();
  GradientSmoother(GradientSmoother&&) noexcept;
  GradientSmoother& operator=(GradientSmoother&&) noexcept;

  int num_tets() const;
  /// The absolute gamma (m^2).
  double gamma() const;
  /// #T element volumes, the diagonal of A (m^3).
  const Eigen::VectorXd& volumes() const;

  /// g_smooth = N K^-1 N^T g for a #T vector g.
  Eigen::VectorXd apply(const Eigen::VectorXd& g) const;

  /// Smooths the gradient of the interior elements' variables: scatters the #interior vector g
  /// into #T (zeros on the other elements), applies N K^-1 N^T and gathers the interior entries.
  Eigen::VectorXd apply_interior(const std::vector<int>& interior, const Eigen::VectorXd& g) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rbaa
