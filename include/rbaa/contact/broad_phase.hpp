#pragma once
// Broad phase: the vertex-triangle and edge-edge pairs of a surface that may come within
// `inflation` of each other during a linear step V0 -> V1, from their swept, inflated bounding
// boxes and a BVH (bvh.hpp). Every pair that does is reported (the test is conservative); pairs
// that share a vertex are not (their distance is zero by construction). Bodies and obstacle
// meshes are one stacked surface here; `can_collide(u, v)`, given one vertex of each primitive
// (primitives never span two bodies), drops pairs that cannot touch, e.g. obstacle against
// obstacle, before they are stored.
//
// Shapes: V0, V1 #V by 3 (equal for a static query), F #F by 3 triangles, E #E by 2 edges, both
// indexing rows of V0 / V1.

#include <Eigen/Core>
#include <functional>
#include <vector>

namespace rbaa::contact {

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

/// Whether primitives holding vertices u and v may touch; empty: all may.
using CanCollide = std::function<bool(int u, int v)>;

/// Vertices (all rows of V0) against triangles whose swept boxes, inflated by `inflation` (m),
/// overlap, and for which can_collide(vertex, first corner); sorted by (vertex, triangle).
std::vector<VertexTriangleCandidate> vertex_triangle_candidates(const Eigen::MatrixXd& V0,
                                                                const Eigen::MatrixXd& V1,
                                                                const Eigen::MatrixXi& F,
                                                                double inflation,
                                                                const CanCollide& can_collide = {});

/// Edge pairs whose swept boxes, inflated by `inflation` (m), overlap, and for which
/// can_collide(first vertex of a, first vertex of b); sorted by (edge_a, edge_b).
std::vector<EdgeEdgeCandidate> edge_edge_candidates(const Eigen::MatrixXd& V0,
                                                    const Eigen::MatrixXd& V1,
                                                    const Eigen::MatrixXi& E, double inflation,
                                                    const CanCollide& can_collide = {});

}  // namespace rbaa::contact
