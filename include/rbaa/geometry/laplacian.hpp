#pragma once
// The cotangent Laplacian of a tetrahedral mesh (libigl's cotmatrix convention: symmetric,
// negative semi-definite, rows summing to zero).

#include <Eigen/SparseCore>

#include "rbaa/mesh/tet_mesh.hpp"

namespace rbaa {

/// #V by #V cotangent Laplacian L = -sum_e V_e G_e^T G_e, with G_e the 3 by 4 gradients of
/// element e's linear hat functions; equivalently L_ij = sum over tets containing edge ij of
/// l_kl cot(theta_kl) / 6, with kl the opposite edge and theta_kl its dihedral angle.
/// Summed in element order (deterministic).
Eigen::SparseMatrix<double> cotangent_laplacian(const TetMesh& mesh);

/// Mean length of the mesh's distinct edges (m).
double mean_edge_length(const TetMesh& mesh);

}  // namespace rbaa
