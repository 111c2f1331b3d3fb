#pragma once
// An exact check that a simulated configuration does not intersect (issue 19: no configuration in
// any test ever intersects), independent of the simulator's own contact code: CGAL's exact
// predicates on the positions as they are (doubles), no tolerance anywhere. (The kernel
// Exact_predicates_inexact_constructions_kernel decides do_intersect and orientations exactly
// for double input; only constructed points would be rounded, and the checks construct none
// that matter: a ray's second point below only picks which exact ray is cast.)
//
// A configuration q (3 #V, the stacked mesh's positions) intersects when
//   * a surface triangle of one body and one of another body share a point (closed triangles:
//     touching counts), or one body lies wholly inside another's closed surface;
//   * a body's surface triangle and a triangle of an obstacle mesh share a point, or a body lies
//     wholly inside a closed obstacle mesh (or a closed obstacle mesh wholly inside a body);
//   * a body's surface vertex is on or behind a plane: normal . x - offset <= 0 (the plane's
//     obstacle is {normal . x < offset}; its boundary counts, as do_intersect's closed triangles
//     do). Vertices suffice: a triangle meets the closed half-space iff one of its corners does.
// A body against itself is not checked (the simulator has no self-contact).
//
//   const test::IntersectionCheck check(rest_mesh, settings);   // bodies, planes, meshes
//   EXPECT_EQ(check.first_intersection(trajectory), "");         // every q[k], sub-steps too
//
// The message names the position (q[k], its time and the step that produced it), the bodies or
// obstacles, the triangles or the vertex, and how many such pairs the position has.

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "rbaa/mesh/tet_mesh.hpp"
#include "rbaa/mesh/topology.hpp"
#include "rbaa/sim/simulator.hpp"
#include "rbaa/sim/trajectory.hpp"
#include "rbaa/sim/world.hpp"

namespace rbaa::test {

namespace intersection_detail {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Segment = Kernel::Segment_3;
using Triangle = Kernel::Triangle_3;
using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, int>;

inline Point point(const Eigen::Vector3d& x) { return Point(x.x(), x.y(), x.z()); }

inline std::string format_point(const Eigen::Vector3d& x) {
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, "(%.9g, %.9g, %.9g)", x.x(), x.y(), x.z());
  return buffer;
}

// Exact: do closed triangles (a0, a1, a2) and (b0, b1, b2) share a point? CGAL's
// triangle-triangle test requires non-degenerate triangles; a degenerate one (its corners
// collinear: a collapsed surface triangle, or a sliver in an obstacle file) is tested as the
// union of its edges, and an edge of length zero as its point.
inline bool triangles_intersect(const std::array<Point, 3>& a, const std::array<Point, 3>& b) {
  const Triangle ta(a[0], a[1], a[2]), tb(b[0], b[1], b[2]);
  const bool da = ta.is_degenerate(), db = tb.is_degenerate();
  if (!da && !db) return CGAL::do_intersect(ta, tb);
  // A piece of a degenerate triangle: an edge, or a point when the edge has length zero.
  struct Piece {
    Point p, q;
    bool is_point() const { return p == q; }
  };
  auto pieces = [](const std::array<Point, 3>& t) {
    return std::array<Piece, 3>{Piece{t[0], t[1]}, Piece{t[1], t[2]}, Piece{t[2], t[0]}};
  };
  auto piece_meets_triangle = [](const Piece& s, const Triangle& t) {
    return s.is_point() ? CGAL::do_intersect(s.p, t) : CGAL::do_intersect(Segment(s.p, s.q), t);
  };
  auto pieces_meet = [](const Piece& s, const Piece& r) {
    if (s.is_point() && r.is_point()) return s.p == r.p;
    if (s.is_point()) return Segment(r.p, r.q).has_on(s.p);
    if (r.is_point()) return Segment(s.p, s.q).has_on(r.p);
    return CGAL::do_intersect(Segment(s.p, s.q), Segment(r.p, r.q));
  };
  if (da && !db) {
    for (const Piece& s : pieces(a))
      if (piece_meets_triangle(s, tb)) return true;
    return false;
  }
  if (!da && db) {
    for (const Piece& s : pieces(b))
      if (piece_meets_triangle(s, ta)) return true;
    return false;
  }
  for (const Piece& s : pieces(a))
    for (const Piece& r : pieces(b))
      if (pieces_meet(s, r)) return true;
  return false;
}

// Exact sign of normal . x - offset for doubles. The sum is first taken in double: with
// S = |n0 x0| + |n1 x1| + |n2 x2| + |offset|, its rounding error is at most gamma_4 S
// (gamma_4 = 4u / (1 - 4u) < 5u, u = 2^-53; Higham, Accuracy and Stability, section 3.1), and
// products that underflow add at most 3 DBL_TRUE_MIN; whenever |sum| exceeds 8u S + DBL_MIN its
// sign is the exact one. Otherwise (a vertex within ~1e-15 relative of the plane, so rarely
// that the cost does not matter) the sum is recomputed in exact rationals, into which doubles
// convert exactly. This keeps the check exact at the cost of a few flops per vertex and plane,
// where exact rationals throughout would allocate for every vertex of every step.
inline int plane_side(const Eigen::Vector3d& normal, double offset, const Eigen::Vector3d& x) {
  const double sum = normal.x() * x.x() + normal.y() * x.y() + normal.z() * x.z() - offset;
  const double magnitude = std::abs(normal.x() * x.x()) + std::abs(normal.y() * x.y()) +
                           std::abs(normal.z() * x.z()) + std::abs(offset);
  if (std::abs(sum) > 8.0 * (DBL_EPSILON / 2) * magnitude + DBL_MIN) return sum > 0 ? 1 : -1;
  using Exact = CGAL::Exact_rational;
  const Exact exact = Exact(normal.x()) * Exact(x.x()) + Exact(normal.y()) * Exact(x.y()) +
                      Exact(normal.z()) * Exact(x.z()) - Exact(offset);
  return CGAL::sign(exact);
}

// A triangle surface whose every edge is used by an even number of its triangles: a ray from a
// point off it crosses it an odd number of times iff the point is inside.
inline bool is_closed(const std::vector<std::array<int, 3>>& triangles) {
  std::map<std::pair<int, int>, int> uses;
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) ++uses[std::minmax(t[k], t[(k + 1) % 3])];
  for (const auto& [edge, count] : uses)
    if (count % 2 != 0) return false;
  return !triangles.empty();
}

// Exact inside test of a point p known to be off the closed surface (`corners` of its
// triangles): the parity of a ray's crossings. A ray that meets a triangle at one of its edges or
// corners (or lies in its plane) is ambiguous and another direction is tried; returns -1 when
// every direction tried was ambiguous, else 1 (inside) or 0.
inline int inside_closed_surface(const Point& p, const std::vector<std::array<Point, 3>>& corners) {
  // Directions with unrelated components, unlikely to line up with mesh features.
  static const double kDirections[][3] = {{0.5773, 0.3289, 0.7473},   {-0.2113, 0.9017, -0.3771},
                                          {0.8147, -0.4218, 0.3978},  {-0.6324, -0.5475, 0.5477},
                                          {0.0975, 0.2785, -0.9554},  {-0.9058, 0.1270, 0.4043},
                                          {0.4387, -0.8116, -0.3857}, {0.3816, 0.7655, -0.5181}};
  for (const auto& d : kDirections) {
    // p + d rounded is some point other than p: the ray through it from p is exact as given.
    const Kernel::Ray_3 ray(p, Point(p.x() + d[0], p.y() + d[1], p.z() + d[2]));
    int crossings = 0;
    bool ambiguous = false;
    for (const auto& c : corners) {
      const Triangle t(c[0], c[1], c[2]);
      if (t.is_degenerate()) {
        // A degenerate triangle bounds nothing; a ray through it is still ambiguous.
        if (CGAL::do_intersect(ray, Segment(c[0], c[1])) ||
            CGAL::do_intersect(ray, Segment(c[1], c[2])) ||
            CGAL::do_intersect(ray, Segment(c[2], c[0]))) {
          ambiguous = true;
          break;
        }
        continue;
      }
      if (!CGAL::do_intersect(ray, t)) continue;
      if (CGAL::do_intersect(ray, Segment(c[0], c[1])) ||
          CGAL::do_intersect(ray, Segment(c[1], c[2])) ||
          CGAL::do_intersect(ray, Segment(c[2], c[0]))) {
        ambiguous = true;
        break;
      }
      ++crossings;
    }
    if (!ambiguous) return crossings % 2;
  }
  return -1;
}

struct Aabb {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY);
  Eigen::Vector3d hi = Eigen::Vector3d::Constant(-INFINITY);
  void add(const Eigen::Vector3d& x) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  bool empty() const { return !(lo.array() <= hi.array()).all(); }
  bool overlaps(const Aabb& o) const {
    return !empty() && !o.empty() && (lo.array() <= o.hi.array()).all() &&
           (o.lo.array() <= hi.array()).all();
  }
  bool inside(const Aabb& o) const {
    return !empty() && (o.lo.array() <= lo.array()).all() && (hi.array() <= o.hi.array()).all();
  }
};

inline Box box_of(const std::array<Point, 3>& t, int id) {
  return Box(t[0].bbox() + t[1].bbox() + t[2].bbox(), id);
}

}  // namespace intersection_detail

/// Checks configurations of one stacked tet mesh (its bodies' surfaces: boundary_faces of the
/// rest mesh) against the planes, the obstacle meshes and each other. Built once per scene, then
/// asked about any number of positions.
class IntersectionCheck {
 public:
  /// body_of_vertex: #V body labels (>= 0; a boundary face belongs to its first vertex's body);
  /// body_names: a name per label, for messages (missing: "body i").
  IntersectionCheck(const TetMesh& rest, std::vector<int> body_of_vertex,
                    std::vector<std::string> body_names, std::vector<Plane> planes,
                    std::vector<ObstacleMesh> meshes)
      : num_vertices_(rest.num_vertices()),
        body_(std::move(body_of_vertex)),
        names_(std::move(body_names)),
        planes_(std::move(planes)),
        meshes_(std::move(meshes)) {
    using namespace intersection_detail;
    F_ = boundary_faces(rest);
    surface_vertices_ = boundary_vertices(rest);
    int num_bodies = 0;
    for (int b : body_) num_bodies = std::max(num_bodies, b + 1);
    while (static_cast<int>(names_.size()) < num_bodies)
      names_.push_back("body " + std::to_string(names_.size()));
    body_faces_.resize(num_bodies);
    for (Eigen::Index f = 0; f < F_.rows(); ++f)
      body_faces_[body_[F_(f, 0)]].push_back(static_cast<int>(f));
    for (const ObstacleMesh& m : meshes_) {
      Obstacle o;
      for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
        std::array<Point, 3> c;
        for (int k = 0; k < 3; ++k) {
          const Eigen::Vector3d x = m.V.row(m.F(f, k)).transpose();
          c[k] = point(x);
          o.box.add(x);
        }
        o.corners.push_back(c);
        o.boxes.push_back(box_of(c, static_cast<int>(f)));
        o.triangles.push_back({m.F(f, 0), m.F(f, 1), m.F(f, 2)});
      }
      o.closed = is_closed(o.triangles);
      obstacles_.push_back(std::move(o));
    }
  }

  /// The bodies as ranges of the mesh (world.hpp); none: the whole mesh is one body.
  IntersectionCheck(const TetMesh& rest, const std::vector<Body>& bodies, std::vector<Plane> planes,
                    std::vector<ObstacleMesh> meshes)
      : IntersectionCheck(rest, labels(rest, bodies), names(bodies), std::move(planes),
                          std::move(meshes)) {}

  /// The bodies, planes and obstacle meshes of a simulation's settings.
  IntersectionCheck(const TetMesh& rest, const SimulationSettings& settings)
      : IntersectionCheck(rest, settings.bodies, settings.planes, settings.obstacle_meshes) {}

  /// "" when q (3 #V) does not intersect, else what intersects first (planes, then obstacle
  /// meshes, then other bodies) and how many pairs of that kind the position has.
  std::string first_intersection(const Eigen::VectorXd& q) const {
    using namespace intersection_detail;
    if (q.size() != 3 * num_vertices_) {
      return "positions of " + std::to_string(q.size()) + " entries for a mesh of " +
             std::to_string(num_vertices_) + " vertices";
    }
    auto x = [&](int v) { return Eigen::Vector3d(q.segment<3>(3 * v)); };
    auto describe_face = [&](int f) {
      std::ostringstream s;
      s << names_[body_[F_(f, 0)]] << " surface triangle " << f << " (vertices " << F_(f, 0) << ", "
        << F_(f, 1) << ", " << F_(f, 2) << ")";
      return s.str();
    };

    // Planes: every surface vertex strictly on the free side.
    {
      std::string first;
      int count = 0;
      for (int v : surface_vertices_) {
        for (std::size_t i = 0; i < planes_.size(); ++i) {
          const Plane& p = planes_[i];
          if (plane_side(p.normal, p.offset, x(v)) > 0) continue;
          if (count++ == 0) {
            char numbers[96];
            std::snprintf(numbers, sizeof numbers, ", offset %.17g): normal . x - offset = %.3e",
                          p.offset, p.normal.dot(x(v)) - p.offset);
            first = names_[body_[v]] + " surface vertex " + std::to_string(v) + " at " +
                    format_point(x(v)) + " is on or behind plane " + std::to_string(i) +
                    " (normal " + format_point(p.normal) + numbers + " (sign exact)";
          }
        }
      }
      if (count > 0) return first + "; " + std::to_string(count) + " vertex-plane pairs";
    }

    // The bodies' surface triangles at q, their boxes (all bodies, and per body).
    std::vector<std::array<Point, 3>> corners(F_.rows());
    std::vector<Box> all_boxes;
    std::vector<Aabb> body_box(body_faces_.size());
    for (std::size_t b = 0; b < body_faces_.size(); ++b) {
      for (int f : body_faces_[b]) {
        for (int k = 0; k < 3; ++k) {
          corners[f][k] = point(x(F_(f, k)));
          body_box[b].add(x(F_(f, k)));
        }
        all_boxes.push_back(box_of(corners[f], f));
      }
    }

    // Obstacle meshes: triangle pairs, then containment either way.
    for (std::size_t m = 0; m < obstacles_.size(); ++m) {
      const Obstacle& o = obstacles_[m];
      bool near = false;
      for (const Aabb& b : body_box) near = near || b.overlaps(o.box);
      if (!near) continue;
      std::string first;
      int count = 0;
      std::vector<Box> body_boxes = all_boxes, obstacle_boxes = o.boxes;
      CGAL::box_intersection_d(body_boxes.begin(), body_boxes.end(), obstacle_boxes.begin(),
                               obstacle_boxes.end(), [&](const Box& a, const Box& b) {
                                 if (!triangles_intersect(corners[a.info()], o.corners[b.info()]))
                                   return;
                                 if (count++ > 0) return;
                                 const auto& t = o.triangles[b.info()];
                                 first = describe_face(a.info()) + " intersects " +
                                         meshes_[m].name + " triangle " + std::to_string(b.info()) +
                                         " (vertices " + std::to_string(t[0]) + ", " +
                                         std::to_string(t[1]) + ", " + std::to_string(t[2]) + ")";
                               });
      if (count > 0) return first + "; " + std::to_string(count) + " intersecting triangle pairs";
      for (std::size_t b = 0; b < body_faces_.size(); ++b) {
        if (body_faces_[b].empty()) continue;
        const int v = F_(body_faces_[b][0], 0);
        if (o.closed && body_box[b].inside(o.box)) {
          const int in = inside_closed_surface(point(x(v)), o.corners);
          if (in != 0)
            return names_[b] + (in > 0 ? " is inside " : " may be inside (no unambiguous ray) ") +
                   meshes_[m].name + " (its surface vertex " + std::to_string(v) + " at " +
                   format_point(x(v)) + ")";
        }
        if (o.box.inside(body_box[b]) && !o.corners.empty()) {
          std::vector<std::array<Point, 3>> body_corners;
          for (int f : body_faces_[b]) body_corners.push_back(corners[f]);
          const int in = inside_closed_surface(o.corners[0][0], body_corners);
          if (in != 0)
            return meshes_[m].name + (in > 0 ? " is inside " : " may be inside ") + names_[b];
        }
      }
    }

    // Pairs of bodies: triangle pairs, then containment either way.
    for (std::size_t a = 0; a < body_faces_.size(); ++a) {
      for (std::size_t b = a + 1; b < body_faces_.size(); ++b) {
        if (!body_box[a].overlaps(body_box[b])) continue;
        std::vector<Box> boxes_a, boxes_b;
        for (int f : body_faces_[a]) boxes_a.push_back(box_of(corners[f], f));
        for (int f : body_faces_[b]) boxes_b.push_back(box_of(corners[f], f));
        std::string first;
        int count = 0;
        CGAL::box_intersection_d(boxes_a.begin(), boxes_a.end(), boxes_b.begin(), boxes_b.end(),
                                 [&](const Box& s, const Box& t) {
                                   if (!triangles_intersect(corners[s.info()], corners[t.info()]))
                                     return;
                                   if (count++ > 0) return;
                                   first = describe_face(s.info()) + " intersects " +
                                           describe_face(t.info());
                                 });
        if (count > 0) return first + "; " + std::to_string(count) + " intersecting triangle pairs";
        for (const auto& [inner, outer] : {std::pair{a, b}, std::pair{b, a}}) {
          if (!body_box[inner].inside(body_box[outer])) continue;
          std::vector<std::array<Point, 3>> outer_corners;
          for (int f : body_faces_[outer]) outer_corners.push_back(corners[f]);
          const int v = F_(body_faces_[inner][0], 0);
          const int in = inside_closed_surface(point(x(v)), outer_corners);
          if (in != 0)
            return names_[inner] + (in > 0 ? " is inside " : " may be inside ") + names_[outer] +
                   " (its surface vertex " + std::to_string(v) + " at " + format_point(x(v)) + ")";
        }
      }
    }
    return "";
  }

  /// "" when no position of the trajectory intersects (q[0] .. q[N], the sub-steps of
  /// contact-resolving steps included; the ballistic history is not a simulated configuration),
  /// else the first that does, named by index, time and the step that produced it.
  std::string first_intersection(const Trajectory& t) const {
    for (std::size_t k = 0; k < t.q.size(); ++k) {
      const std::string what = first_intersection(t.q[k]);
      if (what.empty()) continue;
      std::ostringstream s;
      s << "q[" << k << "] of " << t.q.size() << " (t = " << t.time(static_cast<int>(k)) << " s, "
        << (k == 0 ? std::string("the initial position") : "after step " + std::to_string(k - 1))
        << "): " << what;
      return s.str();
    }
    return "";
  }

 private:
  struct Obstacle {
    std::vector<std::array<intersection_detail::Point, 3>> corners;
    std::vector<intersection_detail::Box> boxes;
    std::vector<std::array<int, 3>> triangles;
    intersection_detail::Aabb box;
    bool closed = false;
  };

  static std::vector<int> labels(const TetMesh& rest, const std::vector<Body>& bodies) {
    if (bodies.empty()) return std::vector<int>(rest.num_vertices(), 0);
    std::vector<int> l = vertex_body_ids(bodies, rest.num_vertices());
    // A vertex outside every body (the simulator's bodies cover the mesh) gets a body of its own.
    for (int& b : l)
      if (b < 0) b = static_cast<int>(bodies.size());
    return l;
  }
  static std::vector<std::string> names(const std::vector<Body>& bodies) {
    std::vector<std::string> n;
    for (std::size_t i = 0; i < bodies.size(); ++i)
      n.push_back(bodies[i].name.empty() ? "bodies[" + std::to_string(i) + "]" : bodies[i].name);
    if (n.empty()) n.push_back("the body");
    return n;
  }

  Eigen::Index num_vertices_ = 0;
  Faces F_;
  std::vector<int> surface_vertices_;
  std::vector<int> body_;
  std::vector<std::string> names_;
  std::vector<std::vector<int>> body_faces_;
  std::vector<Plane> planes_;
  std::vector<ObstacleMesh> meshes_;
  std::vector<Obstacle> obstacles_;
};

/// One-call forms: "" when every position of `trajectory` (or q) is intersection-free with the
/// settings' bodies, planes and obstacle meshes.
inline std::string first_intersection(const TetMesh& rest, const SimulationSettings& settings,
                                      const Trajectory& trajectory) {
  return IntersectionCheck(rest, settings).first_intersection(trajectory);
}
inline std::string first_intersection(const TetMesh& rest, const SimulationSettings& settings,
                                      const Eigen::VectorXd& q) {
  return IntersectionCheck(rest, settings).first_intersection(q);
}

}  // namespace rbaa::test
