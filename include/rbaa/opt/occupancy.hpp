#pragma once
// Post-processing of the occupancy field (SPEC section 5, steps 1 and 2): rounding interior alpha
// to {0, 1}, and joining the occupied elements into one face-connected component containing the
// boundary shell.

#include <Eigen/Core>

#include <vector>

#include "rbaa/mesh/tet_mesh.hpp"

namespace rbaa {

/// #T rounded occupancy: 1 on boundary elements (#T flags); elsewhere 1 where alpha >= threshold,
/// else 0. Throws rbaa::InputError unless 0 < threshold < 1 and the sizes match.
Eigen::VectorXd round_occupancy(const Eigen::VectorXd& alpha, const std::vector<char>& boundary,
                                double threshold = 0.5);

struct ConnectivityReport {
  int components_before = 0;  ///< face-connected components of occupied elements before
  int components_after = 0;   ///< ... and after (1 on success)
  int elements_added = 0;     ///< void elements set to alpha = 1
  double volume_added = 0.0;  ///< their volume (m^3)
};

/// Joins the occupied elements (alpha = 1; alpha must be 0 or 1, boundary elements 1) into one
/// face-connected component with an approximate Steiner tree on the element dual graph (the
/// shortest-path heuristic): starting from the component holding the most boundary elements,
/// repeatedly find the void path of least volume (Boost.Graph Dijkstra from the whole tree,
/// entering an element costs its volume if void, 0 if occupied) to the nearest other component,
/// and set alpha = 1 along it. Deterministic (ties go to the lowest element index). Throws
/// rbaa::InputError when alpha is not binary, a boundary element is void, or the mesh itself is
/// not face-connected.
ConnectivityReport repair_connectivity(const TetMesh& mesh, const std::vector<char>& boundary,
                                       Eigen::VectorXd& alpha);

}  // namespace rbaa
