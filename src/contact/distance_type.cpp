#include "rbaa/contact/distance_type.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <limits>

#include "rbaa/contact/point_edge.hpp"

namespace rbaa::contact {
namespace {

// The point-triangle type for the closest feature of triangle edge k (E0 = t0t1, E1 = t1t2,
// E2 = t2t0) against p.
PointTriangleDistanceType triangle_type_of_edge(int k, PointEdgeDistanceType t) {
  static constexpr PointTriangleDistanceType corner[3] = {PointTriangleDistanceType::P_T0,
                                                          PointTriangleDistanceType::P_T1,
                                                          PointTriangleDistanceType::P_T2};
  static constexpr PointTriangleDistanceType edge[3] = {PointTriangleDistanceType::P_E0,
                                                        PointTriangleDistanceType::P_E1,
                                                        PointTriangleDistanceType::P_E2};
  switch (t) {
    case PointEdgeDistanceType::P_E0:
      return corner[k];
    case PointEdgeDistanceType::P_E1:
      return corner[(k + 1) % 3];
    case PointEdgeDistanceType::P_E:
      return edge[k];
  }
  return edge[k];
}

// Closest edge of a zero-area triangle (or of any triangle when p is known to be outside).
PointTriangleDistanceType closest_triangle_edge(const Eigen::Vector3d& p,
                                                const std::array<Eigen::Vector3d, 3>& t) {
  int best = 0;
  double best_d = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    const double d = point_edge_distance(p, t[k], t[(k + 1) % 3]);
    if (d < best_d) best_d = d, best = k;
  }
  return triangle_type_of_edge(best, point_edge_distance_type(p, t[best], t[(best + 1) % 3]));
}

// Parallel edges: the closest of the four endpoint-vs-segment pairs.
EdgeEdgeDistanceType parallel_edge_edge_distance_type(const Eigen::Vector3d& ea0,
                                                      const Eigen::Vector3d& ea1,
                                                      const Eigen::Vector3d& eb0,
                                                      const Eigen::Vector3d& eb1) {
  using T = EdgeEdgeDistanceType;
  using P = PointEdgeDistanceType;
  struct Option {
    const Eigen::Vector3d *p, *e0, *e1;
    T at_e0, at_e1, inside;
  };
  const Option options[4] = {{&eb0, &ea0, &ea1, T::EA0_EB0, T::EA1_EB0, T::EA_EB0},
                             {&eb1, &ea0, &ea1, T::EA0_EB1, T::EA1_EB1, T::EA_EB1},
                             {&ea0, &eb0, &eb1, T::EA0_EB0, T::EA0_EB1, T::EA0_EB},
                             {&ea1, &eb0, &eb1, T::EA1_EB0, T::EA1_EB1, T::EA1_EB}};
  T best = T::EA0_EB0;
  double best_d = std::numeric_limits<double>::infinity();
  for (const Option& o : options) {
    const P type = point_edge_distance_type(*o.p, *o.e0, *o.e1);
    const double d = point_edge_distance(*o.p, *o.e0, *o.e1, type);
    if (d < best_d) {
      best_d = d;
      best = type == P::P_E0 ? o.at_e0 : type == P::P_E1 ? o.at_e1 : o.inside;
    }
  }
  return best;
}

}  // namespace

PointEdgeDistanceType point_edge_distance_type(const Eigen::Vector3d& p, const Eigen::Vector3d& e0,
                                               const Eigen::Vector3d& e1) {
  const Eigen::Vector3d e = e1 - e0;
  const double q = e.squaredNorm();
  const double te = (p - e0).dot(e);  // t |e|^2: compare without dividing
  if (q == 0 || te <= 0) return PointEdgeDistanceType::P_E0;
  if (te >= q) return PointEdgeDistanceType::P_E1;
  return PointEdgeDistanceType::P_E;
}

PointTriangleDistanceType point_triangle_distance_type(const Eigen::Vector3d& p,
                                                       const Eigen::Vector3d& t0,
                                                       const Eigen::Vector3d& t1,
                                                       const Eigen::Vector3d& t2) {
  using T = PointTriangleDistanceType;
  // Voronoi regions of the corners, edges and face (Ericson, Real-Time Collision Detection,
  // 5.1.5): d1..d6 place p against the corners along the two edges out of t0; va, vb, vc are
  // (twice the triangle's area times) the barycentric coordinates of p's projection.
  const Eigen::Vector3d ab = t1 - t0, ac = t2 - t0;
  // A triangle with no area to speak of has no plane, and a zero-length edge no line: its closest
  // feature is found among its edges (as segments, which handle zero length).
  const double area2 = ab.cross(ac).squaredNorm();
  if (!(area2 > kParallelThreshold * ab.squaredNorm() * ac.squaredNorm()))
    return closest_triangle_edge(p, {t0, t1, t2});
  const Eigen::Vector3d ap = p - t0;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return T::P_T0;
  const Eigen::Vector3d bp = p - t1;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return T::P_T1;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return T::P_E0;
  const Eigen::Vector3d cp = p - t2;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return T::P_T2;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return T::P_E2;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return T::P_E1;
  return T::P_T;
}

EdgeEdgeDistanceType edge_edge_distance_type(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                                             const Eigen::Vector3d& eb0,
                                             const Eigen::Vector3d& eb1) {
  using T = EdgeEdgeDistanceType;
  const Eigen::Vector3d a = ea1 - ea0, b = eb1 - eb0, r = ea0 - eb0;
  const double A = a.squaredNorm(), E = b.squaredNorm();
  // A E - B^2 = |a x b|^2, computed from the cross product to keep its digits when small.
  const double denom = a.cross(b).squaredNorm();
  if (!(denom > kParallelThreshold * A * E))
    return parallel_edge_edge_distance_type(ea0, ea1, eb0, eb1);

  // Minimise |r + s a - t b|^2 over the unit square (Ericson 5.1.9): the unconstrained s,
  // clamped; the best t for it; if t leaves [0, 1], clamp t and take the best s for it.
  const double B = a.dot(b), C = a.dot(r), F = b.dot(r);
  double s = std::clamp((B * F - C * E) / denom, 0.0, 1.0);
  const double t_num = B * s + F;  // t = t_num / E
  bool t_at_0 = false, t_at_1 = false;
  if (t_num <= 0) {
    t_at_0 = true;
    s = std::clamp(-C / A, 0.0, 1.0);
  } else if (t_num >= E) {
    t_at_1 = true;
    s = std::clamp((B - C) / A, 0.0, 1.0);
  }
  const bool s_at_0 = s == 0.0, s_at_1 = s == 1.0;
  if (t_at_0) return s_at_0 ? T::EA0_EB0 : s_at_1 ? T::EA1_EB0 : T::EA_EB0;
  if (t_at_1) return s_at_0 ? T::EA0_EB1 : s_at_1 ? T::EA1_EB1 : T::EA_EB1;
  return s_at_0 ? T::EA0_EB : s_at_1 ? T::EA1_EB : T::EA_EB;
}

const char* to_string(PointEdgeDistanceType type) {
  static constexpr const char* names[] = {"P_E0", "P_E1", "P_E"};
  return names[static_cast<int>(type)];
}

const char* to_string(PointTriangleDistanceType type) {
  static constexpr const char* names[] = {"P_T0", "P_T1", "P_T2", "P_E0", "P_E1", "P_E2", "P_T"};
  return names[static_cast<int>(type)];
}

const char* to_string(EdgeEdgeDistanceType type) {
  static constexpr const char* names[] = {"EA0_EB0", "EA0_EB1", "EA1_EB0", "EA1_EB1", "EA_EB0",
                                          "EA_EB1",  "EA0_EB",  "EA1_EB",  "EA_EB"};
  return names[static_cast<int>(type)];
}

}  // namespace rbaa::contact
