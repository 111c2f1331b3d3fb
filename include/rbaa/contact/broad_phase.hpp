#pragma once
// Broad phase: the vertex-triangle and edge-edge pairs of a surface that may come within
// `inflation` of each other during a linear step V0 -> V1, from their swept, inflated bounding
// boxes and a BVH (bvh.hpp). Every pair that does is reported (the test is conservative); pairs
// that share a vertex are not (their distance is zero by construction). Bodies and obstacle
// meshes are one stacked surface here; with `groups` (one id per vertex: a body's id, one id for
// all static obstacles) pairs within one group are skipped, without being found first: each
// group has its own tree. A primitive belongs to the group of its first vertex (none spans two).
//
// Shapes: V0, V1 #V by 3 (equal for a static query), F #F by 3 triangles, E #E by 2 edges, both
// indexing rows of V0 / V1. Row-major, so that the simulator's stacked coordinates q (3 #V) map
// onto positions without a copy: Eigen::Map<const Positions>(q.data(), q.size() / 3, 3). Other
// matrices (e.g. column-major Eigen::MatrixXd) are accepted through a temporary copy.

#include <Eigen/Core>
#include <vector>

namespace rbaa::contact {

using Positions = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using Triangles = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;
using Edges = Eigen::Matrix<int, Eigen::Dynamic, 2, Eigen::RowMajor>;

struct VertexTriangleCandidate {
  int vertex;
  int triangle;
  friend bool operator==(const VertexTriangleCandidate& a, const VertexTriangleCandidate& b) {
    return a.vertex == b.vertex && a.triangle == b.triangle;
  }
};

struct EdgeEdgeCandidate {
  int edge_a;  ///< edge_a < edge_b
  int edge_b;
  friend bool operator==(const EdgeEdgeCandidate& a, const EdgeEdgeCandidate& b) {
    return a.edge_a == b.edge_a && a.edge_b == b.edge_b;
  }
};

/// Vertices (all rows of V0) against triangles whose swept boxes, inflated by `inflation` (m),
/// overlap, in different groups if `groups` (#V ids) is given; sorted by (vertex, triangle).
std::vector<VertexTriangleCandidate> vertex_triangle_candidates(
    const Eigen::Ref<const Positions>& V0, const Eigen::Ref<const Positions>& V1,
    const Eigen::Ref<const Triangles>& F, double inflation, const std::vector<int>& groups = {});

/// Edge pairs whose swept boxes, inflated by `inflation` (m), overlap, in different groups if
/// `groups` (#V ids) is given; sorted by (edge_a, edge_b).
std::vector<EdgeEdgeCandidate> edge_edge_candidates(const Eigen::Ref<const Positions>& V0,
                                                    const Eigen::Ref<const Positions>& V1,
                                                    const Eigen::Ref<const Edges>& E,
                                                    double inflation,
                                                    const std::vector<int>& groups = {});

}  // namespace rbaa::contact
