#include "rbaa/eval/contact_episodes.hpp"

#include <algorithm>
#include <limits>
#include <sstream>

#include "rbaa/contact/aabb.hpp"
#include "rbaa/contact/broad_phase.hpp"
#include "rbaa/contact/edge_edge.hpp"
#include "rbaa/contact/point_triangle.hpp"
#include "rbaa/contact/static_mesh_broad_phase.hpp"
#include "rbaa/error.hpp"
#include "rbaa/mesh/topology.hpp"
#include "rbaa/sim/observables.hpp"
#include "rbaa/sim/vertex_plane.hpp"

namespace rbaa {
namespace {

using contact::Edges;
using contact::Positions;
using contact::Triangles;

// One body's boundary surface: its vertices, triangles and edges as stacked-mesh ids, and the
// triangles and edges again as rows of `vertices` (for a tree over this body alone).
struct BodySurface {
  std::vector<int> vertices;
  Triangles F, F_local;
  Edges E, E_local;
};

std::vector<BodySurface> body_surfaces(const TetMesh& mesh, const std::vector<Body>& bodies) {
  const Faces faces = boundary_faces(mesh);
  std::vector<BodySurface> out(bodies.size());
  std::vector<int> local(mesh.num_vertices(), -1);
  for (size_t b = 0; b < bodies.size(); ++b) {
    std::vector<int> rows;
    for (Eigen::Index f = 0; f < faces.rows(); ++f) {
      if (faces(f, 0) >= bodies[b].vertex_begin && faces(f, 0) < bodies[b].vertex_end) {
        rows.push_back(static_cast<int>(f));
      }
    }
    BodySurface& s = out[b];
    s.F.resize(static_cast<Eigen::Index>(rows.size()), 3);
    for (size_t r = 0; r < rows.size(); ++r)
      s.F.row(static_cast<Eigen::Index>(r)) = faces.row(rows[r]);
    s.vertices.assign(s.F.data(), s.F.data() + s.F.size());
    std::sort(s.vertices.begin(), s.vertices.end());
    s.vertices.erase(std::unique(s.vertices.begin(), s.vertices.end()), s.vertices.end());
    for (size_t i = 0; i < s.vertices.size(); ++i) local[s.vertices[i]] = static_cast<int>(i);
    s.E = contact::unique_edges(s.F);
    s.F_local = s.F.unaryExpr([&](int v) { return local[v]; });
    s.E_local = s.E.unaryExpr([&](int v) { return local[v]; });
  }
  return out;
}

// The closest pair found so far between a moving surface and a static one.
struct Closest {
  double d2 = std::numeric_limits<double>::infinity();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // static -> moving
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   // on the static side
};

// The gradient of a squared distance with respect to a point on one side is 2 (that point - its
// closest point on the other side), whichever features are closest: the pair's normal and points.
void closest_pair(const contact::StaticMeshBroadPhase& fixed, const Positions& P,
                  const BodySurface& s, double d_hat, Closest& c) {
  const contact::StaticMeshCandidates cand = fixed.query(P, P, s.vertices, s.F, s.E, d_hat);
  const Positions& SV = fixed.V();
  const Triangles& SF = fixed.F();
  const Edges& SE = fixed.E();
  auto keep = [&](double d2, const Eigen::Vector3d& moving_minus_static,
                  const Eigen::Vector3d& point) {
    if (!(d2 < c.d2) || !(moving_minus_static.norm() > 0)) return;
    c.d2 = d2;
    c.normal = moving_minus_static.normalized();
    c.point = point;
  };
  for (const auto& [v, t] : cand.vertex_triangle) {
    const Eigen::Vector3d p = P.row(v), a = SV.row(SF(t, 0)), b = SV.row(SF(t, 1)),
                          d = SV.row(SF(t, 2));
    const double d2 = contact::point_triangle_distance(p, a, b, d);
    if (!(d2 < c.d2)) continue;
    const Eigen::Vector3d half =
        contact::point_triangle_distance_gradient(p, a, b, d).head<3>() / 2;
    keep(d2, half, p - half);
  }
  for (const auto& [t, v] : cand.triangle_vertex) {
    const Eigen::Vector3d p = SV.row(v), a = P.row(s.F(t, 0)), b = P.row(s.F(t, 1)),
                          d = P.row(s.F(t, 2));
    const double d2 = contact::point_triangle_distance(p, a, b, d);
    if (!(d2 < c.d2)) continue;
    const Eigen::Vector3d half =
        contact::point_triangle_distance_gradient(p, a, b, d).head<3>() / 2;
    keep(d2, -half, p);
  }
  for (const auto& [e, f] : cand.edge_edge) {
    const Eigen::Vector3d a0 = P.row(s.E(e, 0)), a1 = P.row(s.E(e, 1)), b0 = SV.row(SE(f, 0)),
                          b1 = SV.row(SE(f, 1));
    const double d2 = contact::edge_edge_distance(a0, a1, b0, b1);
    if (!(d2 < c.d2)) continue;
    const contact::Vector12d g = contact::edge_edge_distance_gradient(a0, a1, b0, b1);
    // d/da0 + d/da1 = 2 (closest on a - closest on b).
    const Eigen::Vector3d diff = (g.segment<3>(0) + g.segment<3>(3)) / 2;
    keep(d2, diff, (b0 + b1) / 2);
  }
}

contact::Aabb box_of(const Positions& P, const std::vector<int>& vertices) {
  contact::Aabb box;
  for (int v : vertices) box.extend(Eigen::Vector3d(P.row(v)));
  return box;
}

struct PairTrack {
  PairTrack(ContactEpisode::Kind kind_, int body_, int other_)
      : kind(kind_), body(body_), other(other_) {}
  ContactEpisode::Kind kind;
  int body, other;
  std::vector<char> in_contact;  // per position
  int first = -1;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero(), point = Eigen::Vector3d::Zero();
};

}  // namespace

std::vector<ContactEpisode> first_contact_episodes(const SimulationRun& run,
                                                   const std::vector<ObstacleMesh>& meshes,
                                                   const std::vector<Plane>& planes, double d_hat,
                                                   int settle_steps) {
  if (!(d_hat > 0)) {
    std::ostringstream msg;
    msg << "contact episodes: d_hat must be positive, got " << d_hat << " m";
    throw InputError(msg.str());
  }
  std::vector<Body> bodies = run.bodies;
  if (bodies.empty()) {
    Body whole;
    whole.vertex_end = run.mesh.num_vertices();
    whole.element_end = run.mesh.num_tets();
    bodies.push_back(whole);
  }
  // On the grid of h, like the traces the episodes index; with contact-resolving steps a position
  // of the grid counts as in contact when any sub-step since the previous one was (an impact can
  // begin and end between two positions of the grid).
  const std::vector<int> frames = run.trajectory.grid_frames();
  const int num_positions = static_cast<int>(frames.size());
  const std::vector<BodySurface> surfaces = body_surfaces(run.mesh, bodies);
  std::vector<contact::StaticMeshBroadPhase> obstacles;
  for (const ObstacleMesh& m : meshes) {
    obstacles.emplace_back(m.V, m.F, contact::unique_edges(m.F));
  }
  std::vector<PairTrack> tracks;
  for (size_t m = 0; m < meshes.size(); ++m) {
    for (size_t b = 0; b < bodies.size(); ++b) {
      tracks.emplace_back(ContactEpisode::Kind::kMesh, static_cast<int>(b), static_cast<int>(m));
    }
  }
  for (size_t a = 0; a < bodies.size(); ++a) {
    for (size_t b = a + 1; b < bodies.size(); ++b) {
      tracks.emplace_back(ContactEpisode::Kind::kBodies, static_cast<int>(a), static_cast<int>(b));
    }
  }
  for (size_t b = 0; b < bodies.size(); ++b) {
    for (size_t p = 0; p < planes.size(); ++p) {
      tracks.emplace_back(ContactEpisode::Kind::kPlane, static_cast<int>(b), static_cast<int>(p));
    }
  }
  for (PairTrack& t : tracks) t.in_contact.assign(num_positions, 0);
  // near[b][k]: body b within d_hat of anything (plane, mesh, body) at position k.
  std::vector<std::vector<char>> near(bodies.size(), std::vector<char>(num_positions, 0));

  const double d2_hat = d_hat * d_hat;
  // Marks position k of the grid with what positions q show.
  auto mark = [&](int k, const Eigen::VectorXd& q) {
    const Positions P = Eigen::Map<const Positions>(q.data(), q.size() / 3, 3);
    std::vector<contact::Aabb> boxes;
    for (size_t b = 0; b < bodies.size(); ++b) boxes.push_back(box_of(P, surfaces[b].vertices));
    for (PairTrack& t : tracks) {
      if (t.kind == ContactEpisode::Kind::kPlane) {
        const Plane& plane = planes[t.other];
        double closest = d_hat;
        int vertex = -1;
        for (int v : surfaces[t.body].vertices) {
          const double d = vertex_plane_distance(P.row(v).transpose(), plane);
          if (d < closest) {
            closest = d;
            vertex = v;
          }
        }
        if (vertex < 0) continue;
        t.in_contact[k] = 1;
        near[t.body][k] = 1;
        if (t.first < 0) {
          t.first = k;
          t.normal = plane.normal;
          t.point = P.row(vertex).transpose() - closest * plane.normal;
        }
        continue;
      }
      contact::Aabb box = boxes[t.body];
      box.inflate(d_hat);
      Closest c;
      if (t.kind == ContactEpisode::Kind::kMesh) {
        if (!box.overlaps(obstacles[t.other].bounds())) continue;
        closest_pair(obstacles[t.other], P, surfaces[t.body], d_hat, c);
      } else {
        if (!box.overlaps(boxes[t.other])) continue;
        const BodySurface& s = surfaces[t.other];
        Positions V(static_cast<Eigen::Index>(s.vertices.size()), 3);
        for (size_t i = 0; i < s.vertices.size(); ++i) {
          V.row(static_cast<Eigen::Index>(i)) = P.row(s.vertices[i]);
        }
        closest_pair(contact::StaticMeshBroadPhase(V, s.F_local, s.E_local), P, surfaces[t.body],
                     d_hat, c);
      }
      if (!(c.d2 < d2_hat)) continue;
      t.in_contact[k] = 1;
      near[t.body][k] = 1;
      if (t.kind == ContactEpisode::Kind::kBodies) near[t.other][k] = 1;
      if (t.first < 0) {
        t.first = k;
        t.normal = c.normal;
        t.point = c.point;
      }
    }
  };
  for (int k = 0; k < num_positions; ++k) {
    for (int j = k == 0 ? frames[0] : frames[k - 1] + 1; j <= frames[k]; ++j) {
      mark(k, run.trajectory.q[j]);
    }
  }

  // A body's centre-of-mass velocity at grid position k (the whole mesh's for a run of one body).
  auto com_velocity = [&](int b, int k) { return body_velocity(run, b, frames[k]); };

  // Pick, per mesh, the track with the earliest contact; every body pair and every (body, plane)
  // pair stands alone.
  std::vector<const PairTrack*> chosen;
  for (size_t m = 0; m < meshes.size(); ++m) {
    const PairTrack* best = nullptr;
    for (const PairTrack& t : tracks) {
      if (t.kind == ContactEpisode::Kind::kMesh && t.other == static_cast<int>(m) && t.first >= 0 &&
          (!best || t.first < best->first)) {
        best = &t;
      }
    }
    if (best) chosen.push_back(best);
  }
  for (const PairTrack& t : tracks) {
    if (t.kind == ContactEpisode::Kind::kBodies && t.first >= 0) chosen.push_back(&t);
  }
  for (const PairTrack& t : tracks) {
    if (t.kind == ContactEpisode::Kind::kPlane && t.first >= 0) chosen.push_back(&t);
  }
  std::vector<ContactEpisode> episodes;
  for (const PairTrack* t : chosen) {
    ContactEpisode e;
    e.kind = t->kind;
    e.body = t->body;
    e.other = t->other;
    e.first_step = t->first;
    // The positions in contact from the first, and on through positions out of contact at which
    // the pair still approaches along the episode's normal (impact_end, as find_bounces).
    auto in_contact = [&](int k) { return t->in_contact[k] != 0; };
    auto approaching = [&](int k) {
      Eigen::Vector3d w = com_velocity(t->body, k);
      if (t->kind == ContactEpisode::Kind::kBodies) w -= com_velocity(t->other, k);
      return w.dot(t->normal) <= 0;
    };
    e.last_step = impact_end(t->first, num_positions, in_contact, [](int) {}, approaching) - 1;
    e.complete = e.first_step > 0 && e.last_step + 1 < num_positions;
    e.out_step = std::min(e.last_step + 1, num_positions - 1);
    auto quiet = [&](int k) {
      return !near[e.body][k] && (e.kind != ContactEpisode::Kind::kBodies || !near[e.other][k]);
    };
    while (e.out_step < e.last_step + 1 + settle_steps && e.out_step + 1 < num_positions &&
           quiet(e.out_step + 1)) {
      ++e.out_step;
    }
    e.normal = t->normal;
    e.point = t->point;
    episodes.push_back(e);
  }
  std::stable_sort(
      episodes.begin(), episodes.end(),
      [](const ContactEpisode& x, const ContactEpisode& y) { return x.first_step < y.first_step; });
  return episodes;
}

}  // namespace rbaa
