#include "rbaa/sim/mesh_obstacle_form.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <tuple>

#include "rbaa/contact/additive_ccd.hpp"
#include "rbaa/contact/solid_angle.hpp"
#include "rbaa/mesh/topology.hpp"
#include "rbaa/sim/contact_pair.hpp"

namespace rbaa {
namespace {

Eigen::Vector3d at(const Eigen::VectorXd& q, int v) { return q.segment<3>(3 * v); }
Eigen::Vector3d row(const contact::Positions& V, int v) { return V.row(v).transpose(); }

ContactPairPoints pair_points(const MeshObstacleForm& f, const ObstaclePair& p,
                              const Eigen::VectorXd& q) {
  ContactPairPoints P;
  const contact::StaticMeshBroadPhase& o = f.obstacles();
  switch (p.kind) {
    case ObstaclePairKind::kVertexTriangle:
      P.vertex[0] = p.body;
      P.x[0] = at(q, p.body);
      for (int k = 0; k < 3; ++k) P.x[1 + k] = row(o.V(), o.F()(p.obstacle, k));
      break;
    case ObstaclePairKind::kTriangleVertex:
      P.x[0] = row(o.V(), p.obstacle);
      for (int k = 0; k < 3; ++k) {
        P.vertex[1 + k] = f.surface_triangles()(p.body, k);
        P.x[1 + k] = at(q, P.vertex[1 + k]);
      }
      break;
    case ObstaclePairKind::kEdgeEdge: {
      P.edge_edge = true;
      for (int k = 0; k < 2; ++k) {
        P.vertex[k] = f.surface_edges()(p.body, k);
        P.x[k] = at(q, P.vertex[k]);
        P.x[2 + k] = row(o.V(), o.E()(p.obstacle, k));
      }
      // eps_x = 1e-3 |ea_rest|^2 |eb_rest|^2 (edge_edge_mollifier_threshold); obstacles do not
      // move.
      P.eps_x = 1e-3 * f.edge_rest_squared_length(p.body) * (P.x[3] - P.x[2]).squaredNorm();
      break;
    }
  }
  return P;
}

}  // namespace

MeshObstacleForm::MeshObstacleForm(const TetMesh& rest, const std::vector<ObstacleMesh>& obstacles,
                                   double d_hat, double kappa)
    : barrier_(d_hat), kappa_(kappa) {
  body_vertices_ = boundary_vertices(rest);
  body_F_ = boundary_faces(rest);
  body_E_ = contact::unique_edges(body_F_);
  edge_rest_squared_length_.resize(body_E_.rows());
  for (Eigen::Index e = 0; e < body_E_.rows(); ++e) {
    edge_rest_squared_length_[e] =
        (rest.V.row(body_E_(e, 0)) - rest.V.row(body_E_(e, 1))).squaredNorm();
  }
  // The obstacles stacked into one static surface.
  Eigen::Index nv = 0, nf = 0;
  for (const ObstacleMesh& m : obstacles) {
    nv += m.V.rows();
    nf += m.F.rows();
  }
  contact::Positions V(nv, 3);
  contact::Triangles F(nf, 3);
  std::vector<contact::Edges> edges;
  Eigen::Index ov = 0, of = 0, ne = 0;
  for (std::size_t i = 0; i < obstacles.size(); ++i) {
    const ObstacleMesh& m = obstacles[i];
    V.middleRows(ov, m.V.rows()) = m.V;
    F.middleRows(of, m.F.rows()) = m.F.array() + static_cast<int>(ov);
    edges.push_back(contact::unique_edges(m.F).array() + static_cast<int>(ov));
    ne += edges.back().rows();
    mesh_of_vertex_.insert(mesh_of_vertex_.end(), m.V.rows(), static_cast<int>(i));
    mesh_names_.push_back(m.name.empty() ? "obstacle mesh " + std::to_string(i) : m.name);
    ov += m.V.rows();
    of += m.F.rows();
  }
  contact::Edges E(ne, 2);
  Eigen::Index oe = 0;
  for (const contact::Edges& e : edges) {
    E.middleRows(oe, e.rows()) = e;
    oe += e.rows();
  }
  broad_ = contact::StaticMeshBroadPhase(std::move(V), std::move(F), std::move(E));
}

std::vector<ObstaclePair> MeshObstacleForm::build(const Eigen::VectorXd& q) const {
  const Eigen::Map<const contact::Positions> V(q.data(), q.size() / 3, 3);
  const contact::StaticMeshCandidates c =
      broad_.query(V, V, body_vertices_, body_F_, body_E_, barrier_.d_hat());
  std::vector<ObstaclePair> pairs;
  const double s_hat = barrier_.d_hat() * barrier_.d_hat();
  auto narrow = [&](ObstaclePairKind kind, const std::vector<std::pair<int, int>>& list) {
    for (const auto& [body, obstacle] : list) {
      ObstaclePair p{kind, body, obstacle, 0.0};
      p.squared_distance = pair_squared_distance(pair_points(*this, p, q));
      if (p.squared_distance < s_hat) pairs.push_back(p);
    }
  };
  narrow(ObstaclePairKind::kVertexTriangle, c.vertex_triangle);
  narrow(ObstaclePairKind::kTriangleVertex, c.triangle_vertex);
  narrow(ObstaclePairKind::kEdgeEdge, c.edge_edge);
  return pairs;
}

const std::vector<ObstaclePair>& MeshObstacleForm::active(const Eigen::VectorXd& q) const {
  for (Cache& c : cache_) {
    if (c.valid && c.q.size() == q.size() && (c.q.array() == q.array()).all()) return c.pairs;
  }
  Cache& c = cache_[next_slot_];
  next_slot_ = 1 - next_slot_;
  c.valid = false;
  c.pairs = build(q);
  c.q = q;
  c.valid = true;
  return c.pairs;
}

double MeshObstacleForm::value(const Eigen::VectorXd& q) const {
  double sum = 0;
  for (const ObstaclePair& p : active(q)) {
    sum += pair_mollifier(pair_points(*this, p, q)) * barrier_.value(std::sqrt(p.squared_distance));
  }
  return kappa_ * sum;
}

double MeshObstacleForm::value_difference(const Eigen::VectorXd& q0,
                                          const Eigen::VectorXd& q1) const {
  // Pairwise m1 b(d1) - m0 b(d0) = m1 (b(d1) - b(d0)) + (m1 - m0) b(d0) over the union of both
  // active sets (b = 0 beyond d_hat), each b difference without cancellation (Barrier::difference).
  std::vector<ObstaclePair> all = active(q0);
  const std::vector<ObstaclePair>& a1 = active(q1);
  all.insert(all.end(), a1.begin(), a1.end());
  auto key = [](const ObstaclePair& p) {
    return std::make_tuple(static_cast<int>(p.kind), p.body, p.obstacle);
  };
  std::sort(all.begin(), all.end(),
            [&](const ObstaclePair& a, const ObstaclePair& b) { return key(a) < key(b); });
  all.erase(
      std::unique(all.begin(), all.end(),
                  [&](const ObstaclePair& a, const ObstaclePair& b) { return key(a) == key(b); }),
      all.end());
  double sum = 0;
  for (const ObstaclePair& p : all) {
    const double term =
        pair_value_difference(pair_points(*this, p, q0), pair_points(*this, p, q1), barrier_);
    if (term == std::numeric_limits<double>::infinity()) return term;
    sum += term;
  }
  return kappa_ * sum;
}

void MeshObstacleForm::add_gradient(const Eigen::VectorXd& q, double scale,
                                    Eigen::VectorXd& grad) const {
  contact::Vector12d g;
  contact::Matrix12d H;
  for (const ObstaclePair& p : active(q)) {
    const ContactPairPoints P = pair_points(*this, p, q);
    pair_derivatives(P, barrier_, g, H);
    add_pair_gradient(P, g, scale * kappa_, grad);
  }
}

void MeshObstacleForm::add_hessian(const Eigen::VectorXd& q, double scale, HessianKind kind,
                                   SparseHessian& hessian) const {
  contact::Vector12d g;
  contact::Matrix12d H;
  bool projected = false;
  for (const ObstaclePair& p : active(q)) {
    const ContactPairPoints P = pair_points(*this, p, q);
    pair_derivatives(P, barrier_, g, H);
    projected |= add_pair_hessian(P, H, scale * kappa_, kind, hessian);
  }
  if (projected) hessian.mark_projection_active();
}

double MeshObstacleForm::max_step_size(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const {
  return ccd(q0, q1, barrier_.d_hat(), contact::AdditiveCcdSettings{});
}

double MeshObstacleForm::ccd(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1, double inflation,
                             const contact::AdditiveCcdSettings& settings) const {
  const Eigen::Map<const contact::Positions> V0(q0.data(), q0.size() / 3, 3),
      V1(q1.data(), q1.size() / 3, 3);
  const contact::StaticMeshCandidates c =
      broad_.query(V0, V1, body_vertices_, body_F_, body_E_, inflation);
  double t = 1.0;
  const auto take = [&](const contact::CcdResult& r) {
    t = std::min(t, r.toi);
    if (!r.converged) ++ccd_caps_;
  };
  for (const auto& [body, obstacle] : c.vertex_triangle) {
    const ContactPairPoints P0 =
        pair_points(*this, {ObstaclePairKind::kVertexTriangle, body, obstacle, 0}, q0);
    const Eigen::Vector3d p1 = at(q1, body);
    take(contact::point_triangle_ccd(P0.x[0], P0.x[1], P0.x[2], P0.x[3], p1, P0.x[1], P0.x[2],
                                     P0.x[3], settings));
  }
  for (const auto& [body, obstacle] : c.triangle_vertex) {
    const ContactPairPoints P0 =
        pair_points(*this, {ObstaclePairKind::kTriangleVertex, body, obstacle, 0}, q0);
    const ContactPairPoints P1 =
        pair_points(*this, {ObstaclePairKind::kTriangleVertex, body, obstacle, 0}, q1);
    take(contact::point_triangle_ccd(P0.x[0], P0.x[1], P0.x[2], P0.x[3], P1.x[0], P1.x[1], P1.x[2],
                                     P1.x[3], settings));
  }
  for (const auto& [body, obstacle] : c.edge_edge) {
    const ContactPairPoints P0 =
        pair_points(*this, {ObstaclePairKind::kEdgeEdge, body, obstacle, 0}, q0);
    const ContactPairPoints P1 =
        pair_points(*this, {ObstaclePairKind::kEdgeEdge, body, obstacle, 0}, q1);
    take(contact::edge_edge_ccd(P0.x[0], P0.x[1], P0.x[2], P0.x[3], P1.x[0], P1.x[1], P1.x[2],
                                P1.x[3], settings));
  }
  return t;
}

bool MeshObstacleForm::is_step_valid(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const {
  for (const ObstaclePair& p : active(q1)) {
    if (!(p.squared_distance > 0)) return false;
  }
  // Unlike a half-space, a triangle can be passed through and left behind: an admissible end point
  // says nothing about the path. The line search's trial need not lie on the segment its
  // max_step_size saw (Newton's rotation-correcting step transform bends the path), so the
  // straight segment q0 -> q1 is checked here: no pair may close below 1e-3 of its gap on it.
  contact::AdditiveCcdSettings s;
  s.min_gap_ratio = 1e-3;
  return ccd(q0, q1, 0.0, s) >= 1.0;
}

int MeshObstacleForm::mesh_of_pair(const ObstaclePair& p) const {
  const int v = p.kind == ObstaclePairKind::kVertexTriangle   ? broad_.F()(p.obstacle, 0)
                : p.kind == ObstaclePairKind::kTriangleVertex ? p.obstacle
                                                              : broad_.E()(p.obstacle, 0);
  return mesh_of_vertex_[v];
}

ContactPairPoints MeshObstacleForm::points(const ObstaclePair& p, const Eigen::VectorXd& q) const {
  return pair_points(*this, p, q);
}

double MeshObstacleForm::min_distance(const Eigen::VectorXd& q) const {
  double s = std::numeric_limits<double>::infinity();
  for (const ObstaclePair& p : active(q)) s = std::min(s, p.squared_distance);
  return std::sqrt(s);
}

ObstacleClearance MeshObstacleForm::clearance(const Eigen::VectorXd& q, double within) const {
  ObstacleClearance r;
  const Eigen::Map<const contact::Positions> V(q.data(), q.size() / 3, 3);
  const contact::StaticMeshCandidates c =
      broad_.query(V, V, body_vertices_, body_F_, body_E_, within);
  const char* kind_names[] = {"body vertex %d - obstacle triangle %d",
                              "body surface triangle %d - obstacle vertex %d",
                              "body surface edge %d - obstacle edge %d"};
  auto consider = [&](ObstaclePairKind kind, const std::vector<std::pair<int, int>>& list) {
    for (const auto& [body, obstacle] : list) {
      const ObstaclePair p{kind, body, obstacle, 0};
      const double d = std::sqrt(pair_squared_distance(pair_points(*this, p, q)));
      if (d < r.distance) {
        r.distance = d;
        const int ov = kind == ObstaclePairKind::kVertexTriangle   ? broad_.F()(obstacle, 0)
                       : kind == ObstaclePairKind::kTriangleVertex ? obstacle
                                                                   : broad_.E()(obstacle, 0);
        r.mesh = mesh_of_vertex_[ov];
        char text[160];
        std::snprintf(text, sizeof text, kind_names[static_cast<int>(kind)], body, obstacle);
        r.pair = text;
      }
    }
  };
  consider(ObstaclePairKind::kVertexTriangle, c.vertex_triangle);
  consider(ObstaclePairKind::kTriangleVertex, c.triangle_vertex);
  consider(ObstaclePairKind::kEdgeEdge, c.edge_edge);

  std::vector<std::pair<int, int>> edge_triangle, triangle_edge;
  broad_.crossing_candidates(V, body_F_, body_E_, edge_triangle, triangle_edge);
  const contact::Positions& OV = broad_.V();
  for (const auto& [e, f] : edge_triangle) {
    if (contact::segment_triangle_intersect(at(q, body_E_(e, 0)), at(q, body_E_(e, 1)),
                                            row(OV, broad_.F()(f, 0)), row(OV, broad_.F()(f, 1)),
                                            row(OV, broad_.F()(f, 2)))) {
      r.intersecting = true;
      r.mesh = mesh_of_vertex_[broad_.F()(f, 0)];
      r.pair = "body surface edge " + std::to_string(e) + " crosses obstacle triangle " +
               std::to_string(f);
      return r;
    }
  }
  for (const auto& [f, e] : triangle_edge) {
    if (contact::segment_triangle_intersect(row(OV, broad_.E()(e, 0)), row(OV, broad_.E()(e, 1)),
                                            at(q, body_F_(f, 0)), at(q, body_F_(f, 1)),
                                            at(q, body_F_(f, 2)))) {
      r.intersecting = true;
      r.mesh = mesh_of_vertex_[broad_.E()(e, 0)];
      r.pair = "obstacle edge " + std::to_string(e) + " crosses body surface triangle " +
               std::to_string(f);
      return r;
    }
  }
  // An obstacle mesh wholly inside the body crosses nothing: its first vertex's winding number
  // with respect to the body's closed surface is then 1 (0 outside).
  std::size_t first = 0;
  for (std::size_t m = 0; m < mesh_names_.size(); ++m) {
    while (first < mesh_of_vertex_.size() && mesh_of_vertex_[first] < static_cast<int>(m)) ++first;
    if (first >= mesh_of_vertex_.size()) break;
    const double omega = contact::surface_solid_angle(row(OV, static_cast<int>(first)), V, body_F_);
    if (std::abs(omega) > 2.0 * M_PI) {
      r.intersecting = true;
      r.mesh = static_cast<int>(m);
      r.pair = "obstacle vertex " + std::to_string(first) + " is inside the body";
      return r;
    }
  }
  return r;
}

}  // namespace rbaa
