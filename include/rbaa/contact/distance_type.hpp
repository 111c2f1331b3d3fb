#pragma once
// Which features of two primitives are closest (IPC's distance types). The squared distance of a
// point-triangle or edge-edge pair is the distance of the closest pair of features: vertex-vertex,
// vertex-edge (a point and a line) or vertex-face / edge-edge interiors (a point and a plane, two
// lines). Each of these has a smooth closed form; classifying first and then evaluating the one
// formula keeps the distance and its derivatives exact when the closest point sits on an edge or a
// corner, where the general formula's projection would leave the primitive.

#include <Eigen/Core>

namespace rbaa::contact {

/// Point p against edge (e0, e1): closest to e0, to e1, or to the edge's interior (the line).
enum class PointEdgeDistanceType { P_E0, P_E1, P_E };

/// Point p against triangle (t0, t1, t2): a corner t_i, an edge (E0 = t0t1, E1 = t1t2,
/// E2 = t2t0), or the interior (the plane).
enum class PointTriangleDistanceType { P_T0, P_T1, P_T2, P_E0, P_E1, P_E2, P_T };

/// Edge (ea0, ea1) against edge (eb0, eb1): two endpoints, an endpoint and the other edge's
/// interior (EA_EB0: eb0 against the line of ea; EA0_EB: ea0 against the line of eb), or both
/// interiors (the two lines).
enum class EdgeEdgeDistanceType {
  EA0_EB0,
  EA0_EB1,
  EA1_EB0,
  EA1_EB1,
  EA_EB0,
  EA_EB1,
  EA0_EB,
  EA1_EB,
  EA_EB
};

/// Closest feature of the edge to p: the parameter t = (p - e0).(e1 - e0) / |e1 - e0|^2 below 0,
/// above 1, or between. A zero-length edge is its point e0.
PointEdgeDistanceType point_edge_distance_type(const Eigen::Vector3d& p, const Eigen::Vector3d& e0,
                                               const Eigen::Vector3d& e1);

/// Closest feature of the triangle to p, by the Voronoi regions of its corners, edges and face
/// (signs of dot products and of sub-areas, no division). A degenerate triangle (|ab x ac|^2 <=
/// kParallelThreshold |ab|^2 |ac|^2, including a zero-length edge) never answers P_T or the
/// line of a zero-length edge: its closest edge or corner as segments is returned.
PointTriangleDistanceType point_triangle_distance_type(const Eigen::Vector3d& p,
                                                       const Eigen::Vector3d& t0,
                                                       const Eigen::Vector3d& t1,
                                                       const Eigen::Vector3d& t2);

/// Closest features of two segments: the minimiser (s, t) of |ea0 + s a - eb0 - t b|^2 over the
/// unit square (a = ea1 - ea0, b = eb1 - eb0), each parameter at 0, 1 or inside. Parallel edges
/// (|a x b|^2 <= 1e-20 |a|^2 |b|^2, where the two lines have no unique closest points and their
/// distance formula divides by ~0) never answer EA_EB: the closest endpoint-edge pair is returned,
/// which is exact since two parallel segments attain their distance at an endpoint of one of them.
EdgeEdgeDistanceType edge_edge_distance_type(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                                             const Eigen::Vector3d& eb0,
                                             const Eigen::Vector3d& eb1);

/// |a x b|^2 / (|a|^2 |b|^2) below this counts as parallel (sin^2 of the angle; 1e-10 rad).
inline constexpr double kParallelThreshold = 1e-20;

/// Names for messages and test output ("P_T0", "EA_EB1", ...).
const char* to_string(PointEdgeDistanceType type);
const char* to_string(PointTriangleDistanceType type);
const char* to_string(EdgeEdgeDistanceType type);

}  // namespace rbaa::contact
