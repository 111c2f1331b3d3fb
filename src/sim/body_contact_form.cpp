#include "rbaa/sim/body_contact_form.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <tuple>

#include "rbaa/contact/aabb.hpp"
#include "rbaa/contact/bvh.hpp"
#include "rbaa/contact/solid_angle.hpp"
#include "rbaa/contact/static_mesh_broad_phase.hpp"
#include "rbaa/error.hpp"
#include "rbaa/mesh/topology.hpp"
#include "rbaa/sim/contact_pair.hpp"

namespace rbaa {
namespace {

Eigen::Vector3d at(const Eigen::VectorXd& q, int v) { return q.segment<3>(3 * v); }

ContactPairPoints pair_points(const BodyContactForm& f, const BodyPair& p,
                              const Eigen::VectorXd& q) {
  ContactPairPoints P;
  if (p.kind == BodyPairKind::kVertexTriangle) {
    P.vertex[0] = p.a;
    for (int k = 0; k < 3; ++k) P.vertex[1 + k] = f.surface_triangles()(p.b, k);
  } else {
    P.edge_edge = true;
    for (int k = 0; k < 2; ++k) {
      P.vertex[k] = f.surface_edges()(p.a, k);
      P.vertex[2 + k] = f.surface_edges()(p.b, k);
    }
    // eps_x = 1e-3 |ea_rest|^2 |eb_rest|^2 (edge_edge_mollifier_threshold).
    P.eps_x = 1e-3 * f.edge_rest_squared_length(p.a) * f.edge_rest_squared_length(p.b);
  }
  for (int k = 0; k < 4; ++k) P.x[k] = at(q, P.vertex[k]);
  return P;
}

auto key(const BodyPair& p) { return std::make_tuple(static_cast<int>(p.kind), p.a, p.b); }

}  // namespace

ContactPairPoints BodyContactForm::points(const BodyPair& p, const Eigen::VectorXd& q) const {
  return pair_points(*this, p, q);
}

BodyContactForm::BodyContactForm(const TetMesh& rest, std::vector<int> body_of_vertex, double d_hat,
                                 double kappa)
    : body_of_vertex_(std::move(body_of_vertex)), barrier_(d_hat), kappa_(kappa) {
  const int nv = rest.num_vertices();
  if (static_cast<int>(body_of_vertex_.size()) != nv) {
    throw InputError("body contact: " + std::to_string(body_of_vertex_.size()) + " body ids for " +
                     std::to_string(nv) + " vertices");
  }
  for (int e = 0; e < rest.num_tets(); ++e) {
    for (int k = 1; k < 4; ++k) {
      const int a = body_of_vertex_[rest.T(e, 0)], b = body_of_vertex_[rest.T(e, k)];
      if (a != b) {
        throw InputError("body contact: tet " + std::to_string(e) + " spans bodies " +
                         std::to_string(a) + " and " + std::to_string(b));
      }
    }
  }
  body_ids_ = body_of_vertex_;
  std::sort(body_ids_.begin(), body_ids_.end());
  body_ids_.erase(std::unique(body_ids_.begin(), body_ids_.end()), body_ids_.end());

  surface_vertices_ = boundary_vertices(rest);
  F_ = boundary_faces(rest);
  E_ = contact::unique_edges(F_);
  std::vector<int> local(nv, -1);
  for (std::size_t i = 0; i < surface_vertices_.size(); ++i) {
    local[surface_vertices_[i]] = static_cast<int>(i);
    local_groups_.push_back(body_of_vertex_[surface_vertices_[i]]);
  }
  local_F_ = F_;
  for (Eigen::Index i = 0; i < local_F_.size(); ++i) local_F_.data()[i] = local[F_.data()[i]];
  local_E_ = E_;
  for (Eigen::Index i = 0; i < local_E_.size(); ++i) local_E_.data()[i] = local[E_.data()[i]];
  edge_rest_squared_length_.resize(E_.rows());
  for (Eigen::Index e = 0; e < E_.rows(); ++e) {
    edge_rest_squared_length_[e] = (rest.V.row(E_(e, 0)) - rest.V.row(E_(e, 1))).squaredNorm();
  }
  body_F_.resize(body_ids_.size());
  for (std::size_t i = 0; i < body_ids_.size(); ++i) {
    std::vector<int> rows;
    for (Eigen::Index f = 0; f < F_.rows(); ++f) {
      if (body_of_vertex_[F_(f, 0)] == body_ids_[i]) rows.push_back(static_cast<int>(f));
    }
    body_F_[i].resize(static_cast<Eigen::Index>(rows.size()), 3);
    for (std::size_t r = 0; r < rows.size(); ++r) body_F_[i].row(r) = F_.row(rows[r]);
  }
}

contact::Positions BodyContactForm::surface_positions(const Eigen::VectorXd& q) const {
  contact::Positions V(surface_vertices_.size(), 3);
  for (std::size_t i = 0; i < surface_vertices_.size(); ++i) {
    V.row(i) = at(q, surface_vertices_[i]).transpose();
  }
  return V;
}

std::vector<BodyPair> BodyContactForm::candidates(const Eigen::VectorXd& q0,
                                                  const Eigen::VectorXd& q1,
                                                  double inflation) const {
  const contact::Positions V0 = surface_positions(q0);
  const contact::Positions V1 = &q0 == &q1 ? V0 : surface_positions(q1);  // static: one copy
  std::vector<BodyPair> out;
  for (const contact::VertexTriangleCandidate& c :
       contact::vertex_triangle_candidates(V0, V1, local_F_, inflation, local_groups_)) {
    out.push_back({BodyPairKind::kVertexTriangle, surface_vertices_[c.vertex], c.triangle, 0.0});
  }
  for (const contact::EdgeEdgeCandidate& c :
       contact::edge_edge_candidates(V0, V1, local_E_, inflation, local_groups_)) {
    out.push_back({BodyPairKind::kEdgeEdge, c.edge_a, c.edge_b, 0.0});
  }
  return out;
}

std::vector<BodyPair> BodyContactForm::build(const Eigen::VectorXd& q) const {
  std::vector<BodyPair> pairs;
  const double s_hat = barrier_.d_hat() * barrier_.d_hat();
  for (BodyPair p : candidates(q, q, barrier_.d_hat())) {
    p.squared_distance = pair_squared_distance(pair_points(*this, p, q));
    if (p.squared_distance < s_hat) pairs.push_back(p);
  }
  return pairs;
}

const std::vector<BodyPair>& BodyContactForm::active(const Eigen::VectorXd& q) const {
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

double BodyContactForm::value(const Eigen::VectorXd& q) const {
  double sum = 0;
  for (const BodyPair& p : active(q)) {
    sum += pair_mollifier(pair_points(*this, p, q)) * barrier_.value(std::sqrt(p.squared_distance));
  }
  return kappa_ * sum;
}

double BodyContactForm::value_difference(const Eigen::VectorXd& q0,
                                         const Eigen::VectorXd& q1) const {
  // Pairwise differences over the union of both active sets (b = 0 beyond d_hat), each without
  // cancellation (pair_value_difference).
  std::vector<BodyPair> all = active(q0);
  const std::vector<BodyPair>& a1 = active(q1);
  all.insert(all.end(), a1.begin(), a1.end());
  std::sort(all.begin(), all.end(),
            [](const BodyPair& a, const BodyPair& b) { return key(a) < key(b); });
  all.erase(std::unique(all.begin(), all.end(),
                        [](const BodyPair& a, const BodyPair& b) { return key(a) == key(b); }),
            all.end());
  double sum = 0;
  for (const BodyPair& p : all) {
    const double term =
        pair_value_difference(pair_points(*this, p, q0), pair_points(*this, p, q1), barrier_);
    if (term == std::numeric_limits<double>::infinity()) return term;
    sum += term;
  }
  return kappa_ * sum;
}

void BodyContactForm::add_gradient(const Eigen::VectorXd& q, double scale,
                                   Eigen::VectorXd& grad) const {
  contact::Vector12d g;
  contact::Matrix12d H;
  for (const BodyPair& p : active(q)) {
    const ContactPairPoints P = pair_points(*this, p, q);
    pair_derivatives(P, barrier_, g, H);
    add_pair_gradient(P, g, scale * kappa_, grad);
  }
}

void BodyContactForm::add_hessian(const Eigen::VectorXd& q, double scale, HessianKind kind,
                                  SparseHessian& hessian) const {
  contact::Vector12d g;
  contact::Matrix12d H;
  bool projected = false;
  for (const BodyPair& p : active(q)) {
    const ContactPairPoints P = pair_points(*this, p, q);
    pair_derivatives(P, barrier_, g, H);
    projected |= add_pair_hessian(P, H, scale * kappa_, kind, hessian);
  }
  if (projected) hessian.mark_projection_active();
}

double BodyContactForm::max_step_size(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const {
  return ccd(q0, q1, barrier_.d_hat(), contact::AdditiveCcdSettings{});
}

double BodyContactForm::ccd(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1, double inflation,
                            const contact::AdditiveCcdSettings& settings) const {
  double t = 1.0;
  for (const BodyPair& p : candidates(q0, q1, inflation)) {
    const ContactPairPoints P0 = pair_points(*this, p, q0), P1 = pair_points(*this, p, q1);
    const auto ccd = p.kind == BodyPairKind::kVertexTriangle ? contact::point_triangle_ccd
                                                             : contact::edge_edge_ccd;
    const contact::CcdResult r =
        ccd(P0.x[0], P0.x[1], P0.x[2], P0.x[3], P1.x[0], P1.x[1], P1.x[2], P1.x[3], settings);
    t = std::min(t, r.toi);
    if (!r.converged) ++ccd_caps_;
  }
  return t;
}

bool BodyContactForm::is_step_valid(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const {
  for (const BodyPair& p : active(q1)) {
    if (!(p.squared_distance > 0)) return false;
  }
  // A triangle can be passed through and left behind (see MeshObstacleForm::is_step_valid).
  contact::AdditiveCcdSettings s;
  s.min_gap_ratio = 1e-3;
  return ccd(q0, q1, 0.0, s) >= 1.0;
}

double BodyContactForm::min_distance(const Eigen::VectorXd& q) const {
  double s = std::numeric_limits<double>::infinity();
  for (const BodyPair& p : active(q)) s = std::min(s, p.squared_distance);
  return std::sqrt(s);
}

std::string BodyContactForm::describe(const BodyPair& p) const {
  char text[160];
  if (p.kind == BodyPairKind::kVertexTriangle) {
    std::snprintf(text, sizeof text, "vertex %d of body %d - surface triangle %d of body %d", p.a,
                  body_of_vertex_[p.a], p.b, body_of_vertex_[F_(p.b, 0)]);
  } else {
    std::snprintf(text, sizeof text, "surface edge %d of body %d - surface edge %d of body %d", p.a,
                  body_of_vertex_[E_(p.a, 0)], p.b, body_of_vertex_[E_(p.b, 0)]);
  }
  return text;
}

BodyClearance BodyContactForm::clearance(const Eigen::VectorXd& q, double within) const {
  BodyClearance r;
  for (const BodyPair& p : candidates(q, q, within)) {
    const ContactPairPoints P = pair_points(*this, p, q);
    const double d = std::sqrt(pair_squared_distance(P));
    if (d < r.distance) {
      r.distance = d;
      r.body_a = body_of_vertex_[P.vertex[0]];
      r.body_b = body_of_vertex_[P.vertex[P.edge_edge ? 2 : 1]];
      r.pair = describe(p);
    }
  }

  // Two intersecting closed surfaces always have an edge of one crossing a triangle of the other.
  std::vector<contact::Aabb> boxes(F_.rows());
  for (Eigen::Index f = 0; f < F_.rows(); ++f) {
    for (int k = 0; k < 3; ++k) boxes[f].extend(at(q, F_(f, k)));
  }
  const contact::Bvh tree(std::move(boxes));
  for (Eigen::Index e = 0; e < E_.rows(); ++e) {
    const Eigen::Vector3d p0 = at(q, E_(e, 0)), p1 = at(q, E_(e, 1));
    contact::Aabb box;
    box.extend(p0);
    box.extend(p1);
    int crossed = -1;
    tree.query(box, [&](int f) {
      if (crossed >= 0 || body_of_vertex_[F_(f, 0)] == body_of_vertex_[E_(e, 0)]) return;
      if (contact::segment_triangle_intersect(p0, p1, at(q, F_(f, 0)), at(q, F_(f, 1)),
                                              at(q, F_(f, 2)))) {
        crossed = f;
      }
    });
    if (crossed >= 0) {
      r.intersecting = true;
      r.body_a = body_of_vertex_[E_(e, 0)];
      r.body_b = body_of_vertex_[F_(crossed, 0)];
      r.pair = "surface edge " + std::to_string(e) + " of body " + std::to_string(r.body_a) +
               " crosses surface triangle " + std::to_string(crossed) + " of body " +
               std::to_string(r.body_b);
      return r;
    }
  }
  // A body wholly inside another crosses nothing: its first surface vertex's winding number with
  // respect to the other's closed surface is then 1 (0 outside).
  const Eigen::Map<const contact::Positions> V(q.data(), q.size() / 3, 3);
  const int nb = num_bodies();
  std::vector<int> first(nb, -1);
  std::vector<contact::Aabb> bounds(nb);
  for (int v : surface_vertices_) {
    const int i =
        static_cast<int>(std::lower_bound(body_ids_.begin(), body_ids_.end(), body_of_vertex_[v]) -
                         body_ids_.begin());
    if (first[i] < 0) first[i] = v;
    bounds[i].extend(at(q, v));
  }
  for (int i = 0; i < nb; ++i) {
    for (int j = 0; j < nb; ++j) {
      if (i == j || first[i] < 0 || !bounds[i].overlaps(bounds[j])) continue;
      if (std::abs(contact::surface_solid_angle(at(q, first[i]), V, body_F_[j])) > 2.0 * M_PI) {
        r.intersecting = true;
        r.body_a = body_ids_[i];
        r.body_b = body_ids_[j];
        r.pair = "body " + std::to_string(r.body_a) + " is inside body " + std::to_string(r.body_b);
        return r;
      }
    }
  }
  return r;
}

void BodyContactForm::check_separated(const Eigen::VectorXd& q) const {
  const BodyClearance c = clearance(q, barrier_.d_hat());
  if (c.intersecting || !(c.distance > 0)) {
    throw InputError("body contact: bodies " + std::to_string(std::min(c.body_a, c.body_b)) +
                     " and " + std::to_string(std::max(c.body_a, c.body_b)) + " start " +
                     (c.intersecting ? "overlapping" : "touching") + " (" + c.pair + ")");
  }
}

}  // namespace rbaa
