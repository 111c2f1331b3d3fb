// Contact between the bodies of one stacked mesh (body_contact_form.hpp): value, gradient and
// exact Hessian against central finite differences for every closest-feature kind (vertex over a
// face, an edge, a corner; crossing, nearly and exactly parallel edges) from 1e-6 d_hat to d_hat;
// the value against a brute-force sum over every pair; zero net force and torque; CCD keeping
// random steps free of intersections (checked with CGAL's exact predicates); and the Hessian's
// pattern growing across bodies while CHOLMOD still factorises it.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "form_checks.hpp"
#include "mesh_fixtures.hpp"
#include "rbaa/contact/edge_edge.hpp"
#include "rbaa/contact/point_triangle.hpp"
#include "rbaa/error.hpp"
#include "rbaa/mesh/topology.hpp"
#include "rbaa/sim/body_contact_form.hpp"
#include "rbaa/sim/linear_solver.hpp"
#include "support/intersection_free.hpp"

namespace rbaa {
namespace {

using test::tet;

constexpr double kDHat = 1e-3;
constexpr double kL = 0.01;  // size of the single-tet bodies

struct Bodies {
  TetMesh mesh;
  std::vector<int> body;
};

// The meshes stacked into one, body i's vertices labelled i.
Bodies stack(const std::vector<TetMesh>& parts) {
  Bodies b;
  int nv = 0, nt = 0;
  for (const TetMesh& m : parts) {
    nv += m.num_vertices();
    nt += m.num_tets();
  }
  b.mesh.V.resize(nv, 3);
  b.mesh.T.resize(nt, 4);
  int ov = 0, ot = 0;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    b.mesh.V.middleRows(ov, parts[i].num_vertices()) = parts[i].V;
    b.mesh.T.middleRows(ot, parts[i].num_tets()) = parts[i].T.array() + ov;
    b.body.insert(b.body.end(), parts[i].num_vertices(), static_cast<int>(i));
    ov += parts[i].num_vertices();
    ot += parts[i].num_tets();
  }
  return b;
}

// A tet whose top face is the triangle (0,0,0), (L,0,0), (0,L,0).
TetMesh face_up() { return tet({0, 0, 0}, {kL, 0, 0}, {0, kL, 0}, {kL / 4, kL / 4, -kL}); }
// A tet with its apex p pointing down.
TetMesh apex_down(const Eigen::Vector3d& p) {
  return tet(p, p + kL * Eigen::Vector3d(1.0, 0.2, 1.0), p + kL * Eigen::Vector3d(-0.3, 1.0, 1.0),
             p + kL * Eigen::Vector3d(-0.5, -0.6, 1.0));
}
// A tet whose top is the ridge (0,0,0) - (L,0,0).
TetMesh ridge_up() {
  return tet({0, 0, 0}, {kL, 0, 0}, {kL / 2, -kL / 2, -kL}, {kL / 2, kL / 2, -kL});
}
// A tet whose bottom is the ridge s - s + 0.7 L dir, dir horizontal (shorter than ridge_up's, so
// that the mollifier's eps_x depends on both edges' lengths).
TetMesh ridge_down(const Eigen::Vector3d& s, const Eigen::Vector3d& dir) {
  const double length = 0.7 * kL;
  const Eigen::Vector3d m = s + 0.5 * length * dir;
  const Eigen::Vector3d side(-dir.y(), dir.x(), 0.0);
  return tet(s, s + length * dir, m + kL * (Eigen::Vector3d(0, 0, 1) + 0.5 * side),
             m + kL * (Eigen::Vector3d(0, 0, 1) - 0.5 * side));
}

struct Counts {
  int vertex_triangle = 0, edge_edge = 0;
};
Counts count(const BodyContactForm& f, const Eigen::VectorXd& q) {
  Counts c;
  for (const BodyPair& p : f.active_pairs(q)) {
    c.vertex_triangle += p.kind == BodyPairKind::kVertexTriangle;
    c.edge_edge += p.kind == BodyPairKind::kEdgeEdge;
  }
  return c;
}

// The potential summed over every surface pair of different bodies, with the barrier and the
// mollifier written out here: catches pairs the form skips and factors it drops.
double brute_force_value(const Bodies& b, const Eigen::VectorXd& q, double kappa) {
  const Faces F = boundary_faces(b.mesh);
  const std::vector<int> sv = boundary_vertices(b.mesh);
  std::set<std::pair<int, int>> edge_set;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int i = F(f, k), j = F(f, (k + 1) % 3);
      edge_set.insert({std::min(i, j), std::max(i, j)});
    }
  }
  const std::vector<std::pair<int, int>> edges(edge_set.begin(), edge_set.end());
  auto x = [&](int v) { return Eigen::Vector3d(q.segment<3>(3 * v)); };
  auto rest = [&](int v) { return Eigen::Vector3d(b.mesh.V.row(v).transpose()); };
  auto barrier = [](double d) {
    return d < kDHat ? -(d - kDHat) * (d - kDHat) * std::log(d / kDHat) : 0.0;
  };
  double sum = 0;
  for (int v : sv) {
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
      if (b.body[v] == b.body[F(f, 0)]) continue;
      sum += barrier(
          std::sqrt(contact::point_triangle_distance(x(v), x(F(f, 0)), x(F(f, 1)), x(F(f, 2)))));
    }
  }
  for (std::size_t i = 0; i < edges.size(); ++i) {
    for (std::size_t j = i + 1; j < edges.size(); ++j) {
      const auto [a0, a1] = edges[i];
      const auto [b0, b1] = edges[j];
      if (b.body[a0] == b.body[b0]) continue;
      const double d = std::sqrt(contact::edge_edge_distance(x(a0), x(a1), x(b0), x(b1)));
      const double eps_x =
          1e-3 * (rest(a1) - rest(a0)).squaredNorm() * (rest(b1) - rest(b0)).squaredNorm();
      const double c = ((x(a1) - x(a0)).cross(x(b1) - x(b0))).squaredNorm();
      const double m = c < eps_x ? (2.0 - c / eps_x) * c / eps_x : 1.0;
      sum += m * barrier(d);
    }
  }
  return kappa * sum;
}

struct Case {
  std::string label;
  Bodies bodies;
  double distance;  ///< of the closest pair (0: not checked)
  /// Finite-difference step: 1e-2 of the distance or of its gap to d_hat, and for nearly
  /// parallel edges at most 1e-2 L^2 angle^2 / d (below).
  double step;
  /// Compare the whole Hessian; otherwise only along directions that keep the angles between
  /// the edges (translating either body).
  bool whole_hessian = true;
};

// The closest-feature kinds at distance d (body 0 below, body 1 above).
//
// Nearly parallel edges, seen from above, either cross before edge a starts (the closest features
// are a's end and b's line) or inside both edges (the two lines). Tilting an edge by sigma moves
// the lines' closest points by about d sigma / angle^2, so the closest-feature kind flips under
// perturbations beyond about L^2 angle^2 / d, and differences of the Hessian only converge with
// steps well below that (measured on the ridge pair alone at 1e-4 rad, d = 3e-4 m: relative
// error 0.14 with a 1e-9 m step, 1.5e-10 with 1e-10 m). At 1e-6 rad and d >= 1e-5 m that is
// below 1e-11 m, too fine for differences of 1 cm coordinates. So the whole Hessian is compared
// at 1e-4 rad with steps of 1e-2 L^2 angle^2 / d, and at 1e-6 rad only along directions that
// keep the angles and the lines' closest points (translating either body along x or z, the
// edges' direction and their common normal; a sideways shift t moves the lines' crossing by
// t / angle); gradients and values everywhere.
//
// Exactly parallel edges: m b is C1, not C2 (the mollifier's point): turning an edge makes the
// closest features the two lines, and m hess s tends to a limit that depends on the direction of
// the turn, so again only those translations have a Hessian to compare with.
std::vector<Case> cases(double d) {
  const double h = 1e-2 * std::min(d, kDHat - d);
  const auto turned = [](double a) { return Eigen::Vector3d(std::cos(a), std::sin(a), 0); };
  // Ridges turned by a whose lines cross at x = L / 8 (before a starts at L / 4) or 0.6 L (a
  // runs from 0.25 L to 0.95 L).
  const auto end_to_line = [&](double a) {
    return stack(
        {ridge_up(), ridge_down(Eigen::Vector3d(kL / 8, 0, d) + kL / 8 * turned(a), turned(a))});
  };
  const auto line_to_line = [&](double a) {
    return stack({ridge_up(),
                  ridge_down(Eigen::Vector3d(0.6 * kL, 0, d) - 0.35 * kL * turned(a), turned(a))});
  };
  return {
      {"vertex over face", stack({face_up(), apex_down({kL / 4, kL / 4, d})}), d, h},
      {"vertex over edge", stack({face_up(), apex_down({kL / 2, -0.3 * d, d})}),
       d * std::sqrt(1.09), h},
      {"vertex over corner", stack({face_up(), apex_down({-0.3 * d, -0.2 * d, d})}),
       d * std::sqrt(1.13), h},
      {"edges crossing", stack({ridge_up(), ridge_down({kL / 2, -kL / 2, d}, {0, 1, 0})}), d, h},
      {"1e-6 rad, end to line", end_to_line(1e-6), 0.0, h, false},
      {"1e-6 rad, line to line", line_to_line(1e-6), d, h, false},
      {"1e-4 rad, end to line", end_to_line(1e-4), 0.0, std::min(h, 1e-2 * kL * kL * 1e-8 / d)},
      {"1e-4 rad, line to line", line_to_line(1e-4), d, std::min(h, 1e-2 * kL * kL * 1e-8 / d)},
      {"parallel edges", stack({ridge_up(), ridge_down({kL / 4, 0, d}, {1, 0, 0})}), d, h, false},
  };
}

TEST(BodyContactForm, DerivativesMatchFiniteDifferencesForEveryFeatureKind) {
  const double kappa = 3.0;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (double d : {1e-9, 1e-7, 1e-5, 3e-4, 9e-4}) {
    for (const Case& c : cases(d)) {
      const BodyContactForm form(c.bodies.mesh, c.bodies.body, kDHat, kappa);
      const Eigen::VectorXd q = test::positions(c.bodies.mesh);
      const Counts n = count(form, q);
      ASSERT_GT(n.vertex_triangle + n.edge_edge, 0) << c.label << " at " << d;
      if (c.label.find("vertex") != 0) {
        EXPECT_GT(n.edge_edge, 0) << c.label;
      }
      if (c.distance > 0) {
        EXPECT_NEAR(form.min_distance(q), c.distance, 1e-12 * kL) << c.label;
      }
      // The value against the brute-force sum.
      const double v = form.value(q);
      EXPECT_NEAR(v, brute_force_value(c.bodies, q, kappa), 1e-12 * std::abs(v)) << c.label;

      const double eps = c.step;
      const auto value = [&](const Eigen::VectorXd& x) { return form.value(x); };
      const auto gradient = [&](const Eigen::VectorXd& x) { return test::form_gradient(form, x); };
      const Eigen::VectorXd g = gradient(q);
      const double gradient_error = test::relative_error(g, test::fd_gradient5(value, q, eps));
      SparseHessian H(c.bodies.mesh.T, c.bodies.mesh.num_vertices());
      const Eigen::MatrixXd Hx = test::form_hessian(form, q, HessianKind::kExact, H);
      // Directions: along the gradient, then (unless the whole Hessian is compared) random
      // translations of the two bodies in the x-z plane, the only ones along which the Hessian
      // is compared then (the gradient has sideways parts, which turn the edges).
      std::vector<Eigen::VectorXd> directions = {-g.normalized()};
      double hessian_error = 0;
      if (c.whole_hessian) {
        hessian_error = test::relative_error(Hx, test::fd_jacobian5(gradient, q, eps));
      } else {
        for (int k = 0; k < 3; ++k) {
          Eigen::VectorXd u(q.size());
          const Eigen::Vector3d t[2] = {Eigen::Vector3d(uniform(rng), 0, uniform(rng)),
                                        Eigen::Vector3d(uniform(rng), 0, uniform(rng))};
          for (int v = 0; v < c.bodies.mesh.num_vertices(); ++v)
            u.segment<3>(3 * v) = t[c.bodies.body[v]];
          directions.push_back(u.normalized());
        }
      }
      double slope_error = 0, direction_error = 0;
      for (std::size_t k = 0; k < directions.size(); ++k) {
        const Eigen::VectorXd& u = directions[k];
        const auto along = [&](double t) { return Eigen::VectorXd(q + t * u); };
        const double slope =
            test::fd_gradient5([&](const Eigen::VectorXd& t) { return value(along(t[0])); },
                               Eigen::VectorXd::Zero(1), eps)[0];
        slope_error = std::max(slope_error, std::abs(slope - g.dot(u)) / std::abs(g.dot(u)));
        if (k == 0 && !c.whole_hessian) continue;
        const Eigen::VectorXd Hu =
            test::fd_jacobian5([&](const Eigen::VectorXd& t) { return gradient(along(t[0])); },
                               Eigen::VectorXd::Zero(1), eps);
        direction_error = std::max(direction_error, test::relative_error(Hx * u, Hu));
      }
      std::printf(
          "%-28s d %.0e: pairs VT %d EE %d, rel err gradient %.1e Hessian %.1e, along %zu "
          "directions: slope %.1e Hessian %.1e\n",
          c.label.c_str(), d, n.vertex_triangle, n.edge_edge, gradient_error, hessian_error,
          directions.size(), slope_error, direction_error);
      EXPECT_LE(gradient_error, 1e-6) << c.label << " at " << d;
      EXPECT_LE(hessian_error, 1e-6) << c.label << " at " << d;
      EXPECT_LE(slope_error, 1e-6) << c.label << " at " << d;
      EXPECT_LE(direction_error, 1e-6) << c.label << " at " << d;
      // The value difference agrees with the difference of values.
      const Eigen::VectorXd q1 = q + 0.5 * d * directions[0];
      EXPECT_NEAR(form.value_difference(q, q1), form.value(q1) - v, 1e-9 * v) << c.label;
    }
  }
}

// Two 2x2x2 blocks of 5 mm cubes, the upper one turned about z and 0.3 mm above the lower, with
// jitter: many pairs of both kinds between them.
Bodies two_blocks(double turn) {
  TetMesh lower = test::box_mesh(2, 2, 2, 0.005, Eigen::Vector3d(-0.005, -0.005, -0.01));
  TetMesh upper = test::box_mesh(2, 2, 2, 0.005, Eigen::Vector3d(-0.005, -0.005, 3e-4));
  const Eigen::Matrix3d R = Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  upper.V = (upper.V * R.transpose()).eval();
  return stack({lower, upper});
}

Eigen::VectorXd jittered(const TetMesh& mesh, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  Eigen::VectorXd q = test::positions(mesh);
  for (Eigen::Index i = 0; i < q.size(); ++i) q[i] += u(rng);
  return q;
}

TEST(BodyContactForm, ForcesHaveNoNetForceOrTorque) {
  const Bodies b = two_blocks(0.3);
  const BodyContactForm form(b.mesh, b.body, kDHat, 2.0);
  const Eigen::VectorXd q = jittered(b.mesh, 5e-5, 4);
  const Counts n = count(form, q);
  std::printf("blocks: pairs VT %d EE %d\n", n.vertex_triangle, n.edge_edge);
  EXPECT_GT(n.vertex_triangle, 20);
  EXPECT_GT(n.edge_edge, 20);
  const Eigen::VectorXd g = test::form_gradient(form, q);
  Eigen::Vector3d force = Eigen::Vector3d::Zero(), torque = Eigen::Vector3d::Zero();
  double force_scale = 0, torque_scale = 0;
  Eigen::Vector3d force_on_upper = Eigen::Vector3d::Zero();
  for (int v = 0; v < b.mesh.num_vertices(); ++v) {
    const Eigen::Vector3d f = -g.segment<3>(3 * v), x = q.segment<3>(3 * v);
    force += f;
    torque += x.cross(f);
    force_scale += f.norm();
    torque_scale += x.norm() * f.norm();
    if (b.body[v] == 1) force_on_upper += f;
  }
  std::printf("net force %.1e of %.1e, net torque %.1e of %.1e\n", force.norm(), force_scale,
              torque.norm(), torque_scale);
  EXPECT_LE(force.norm(), 1e-12 * force_scale);
  EXPECT_LE(torque.norm(), 1e-12 * torque_scale);
  // The upper block is pushed up, and hard: the forces do not cancel within a body.
  EXPECT_GT(force_on_upper.z(), 0.5 * force_on_upper.norm());
  EXPECT_GT(force_on_upper.norm(), 0.1 * force_scale);
}

TEST(BodyContactForm, ProjectedHessianIsPsdAndThePatternGrowsAcrossBodies) {
  const Bodies b = two_blocks(0.3);
  const BodyContactForm form(b.mesh, b.body, kDHat, 2.0);
  const Eigen::VectorXd q = jittered(b.mesh, 5e-5, 5);
  SparseHessian H(b.mesh.T, b.mesh.num_vertices());
  const std::uint64_t base_version = H.pattern_version();
  const Eigen::Index base_nnz = H.matrix().nonZeros();
  // The vertex pairs of different bodies that some active pair couples.
  std::set<std::pair<int, int>> coupled;
  for (const BodyPair& p : form.active_pairs(q)) {
    std::vector<int> v;
    if (p.kind == BodyPairKind::kVertexTriangle) {
      v = {p.a, form.surface_triangles()(p.b, 0), form.surface_triangles()(p.b, 1),
           form.surface_triangles()(p.b, 2)};
    } else {
      v = {form.surface_edges()(p.a, 0), form.surface_edges()(p.a, 1), form.surface_edges()(p.b, 0),
           form.surface_edges()(p.b, 1)};
    }
    for (int i : v)
      for (int j : v)
        if (i > j && b.body[i] != b.body[j]) coupled.insert({i, j});
  }
  ASSERT_FALSE(coupled.empty());

  LinearSolver solver;
  for (HessianKind kind : {HessianKind::kProjected, HessianKind::kExact}) {
    // A mass-like diagonal makes the sum positive definite (the contact part alone is singular,
    // and indefinite when exact).
    const Eigen::VectorXd lc =
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(test::form_hessian(form, q, kind, H))
            .eigenvalues();
    const double shift = 1e-2 * lc.cwiseAbs().maxCoeff() + std::max(0.0, -lc.minCoeff());
    H.set_zero();
    for (int v = 0; v < b.mesh.num_vertices(); ++v)
      H.vertex_block(v) += shift * Eigen::Matrix3d::Identity();
    form.add_hessian(q, 1.0, kind, H);
    const bool flagged = H.projection_active();
    const Eigen::SparseMatrix<double>& A = H.assemble();
    EXPECT_NE(H.pattern_version(), base_version);
    EXPECT_EQ(A.nonZeros(), base_nnz + 9 * static_cast<Eigen::Index>(coupled.size()));
    const std::set<std::pair<int, int>> extra(H.extra_pairs().begin(), H.extra_pairs().end());
    EXPECT_EQ(extra, coupled);
    ASSERT_TRUE(solver.factorize(A, H.pattern_version())) << static_cast<int>(kind);
    const Eigen::MatrixXd D = Eigen::SparseMatrix<double>(A.selfadjointView<Eigen::Lower>());
    const Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(D.rows(), -1.0, 1.0);
    EXPECT_LE((D * solver.solve(rhs) - rhs).norm(), 1e-10 * rhs.norm());
    if (kind == HessianKind::kProjected) {
      EXPECT_TRUE(flagged);  // the exact pair blocks are indefinite
      EXPECT_GE(lc.minCoeff(), -1e-10 * lc.cwiseAbs().maxCoeff());
    } else {
      EXPECT_LT(lc.minCoeff(), -1e-6 * lc.cwiseAbs().maxCoeff());
    }
  }
  EXPECT_EQ(solver.num_analyses(), 1);  // both kinds share the pattern
}

// Random moves of two blocks towards each other (each vertex its own random displacement on top
// of a random translation of each body): stepping by max_step_size never makes them intersect.
TEST(BodyContactForm, CcdKeepsRandomStepsApart) {
  const Bodies b = two_blocks(0.2);
  const BodyContactForm form(b.mesh, b.body, kDHat, 1.0);
  const test::IntersectionCheck check(b.mesh, b.body, {}, {}, {});
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int crossing_steps = 0;
  const int trials = 40;
  for (int trial = 0; trial < trials; ++trial) {
    const Eigen::VectorXd q0 = jittered(b.mesh, 5e-5, 100 + trial);
    ASSERT_EQ(check.first_intersection(q0), "");
    Eigen::Vector3d move[2];
    for (auto& m : move) m = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.004;
    move[1].z() -= 0.004 + 0.01 * std::abs(u(rng));  // the upper block comes down
    Eigen::VectorXd q1 = q0;
    for (int v = 0; v < b.mesh.num_vertices(); ++v) {
      q1.segment<3>(3 * v) += move[b.body[v]] + 5e-4 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    }
    const bool crossing = !check.first_intersection(q1).empty();
    crossing_steps += crossing;
    const double t = form.max_step_size(q0, q1);
    const Eigen::VectorXd qt = q0 + t * (q1 - q0);
    EXPECT_GT(t, 0.0) << trial;
    EXPECT_EQ(check.first_intersection(qt), "") << trial << ": step fraction " << t;
    EXPECT_FALSE(form.clearance(qt, kDHat).intersecting) << trial;
    EXPECT_GT(form.clearance(qt, 0.1).distance, 0.0) << trial;
    EXPECT_TRUE(form.is_step_valid(q0, qt)) << trial;
    if (crossing) {
      EXPECT_FALSE(form.is_step_valid(q0, q1)) << trial;
    }
  }
  std::printf("%d of %d random steps end intersecting\n", crossing_steps, trials);
  EXPECT_GE(crossing_steps, trials / 2);  // the test is not vacuous
}

// A tet's apex 0.5 mm above a 1 mm thick slab moves 0.3 m down in one step, through the slab.
TEST(BodyContactForm, CcdCatchesAFastThinCrossing) {
  TetMesh slab = test::box_mesh(1, 1, 1, 1.0);
  slab.V.col(0).array() = 0.2 * slab.V.col(0).array() - 0.1;
  slab.V.col(1).array() = 0.2 * slab.V.col(1).array() - 0.1;
  slab.V.col(2).array() = 1e-3 * slab.V.col(2).array() - 1e-3;
  const Bodies b = stack({slab, apex_down({0.003, -0.002, 5e-4})});
  const BodyContactForm form(b.mesh, b.body, kDHat, 1.0);
  const test::IntersectionCheck check(b.mesh, b.body, {}, {}, {});
  const Eigen::VectorXd q0 = test::positions(b.mesh);
  Eigen::VectorXd q1 = q0;
  for (int v = 0; v < b.mesh.num_vertices(); ++v) {
    if (b.body[v] == 1) q1[3 * v + 2] -= 0.3;
  }
  // Wholly beyond the slab: only CCD sees the crossing.
  EXPECT_EQ(check.first_intersection(q1), "");
  const double t = form.max_step_size(q0, q1);
  const Eigen::VectorXd qt = q0 + t * (q1 - q0);
  std::printf("fast thin crossing: step fraction %.3e, apex height afterwards %.3e m\n", t,
              qt[3 * 8 + 2]);
  EXPECT_GT(t, 0.0);
  EXPECT_LT(t * 0.3, 5e-4);
  EXPECT_GT(qt[3 * 8 + 2], 0.05 * 5e-4);  // no pair closes more than 90 % of its gap
  EXPECT_EQ(check.first_intersection(qt), "");
  EXPECT_FALSE(form.is_step_valid(q0, q1));
  EXPECT_TRUE(form.is_step_valid(q0, qt));
}

TEST(BodyContactForm, ClearanceAndInputErrorsNameTheBodies) {
  // Overlapping blocks: the error names both bodies.
  TetMesh lower = test::box_mesh(1, 1, 1, 0.01);
  TetMesh upper = test::box_mesh(1, 1, 1, 0.01, Eigen::Vector3d(0.003, 0.002, 0.005));
  Bodies b = stack({lower, upper});
  BodyContactForm form(b.mesh, b.body, kDHat, 1.0);
  const Eigen::VectorXd q = test::positions(b.mesh);
  EXPECT_TRUE(form.clearance(q, kDHat).intersecting);
  try {
    form.check_separated(q);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("bodies 0 and 1"), std::string::npos) << what;
    EXPECT_NE(what.find("overlapping"), std::string::npos) << what;
  }
  // A small block wholly inside the other: nothing crosses; the winding number finds it.
  b = stack({lower, test::box_mesh(1, 1, 1, 0.002, Eigen::Vector3d(0.004, 0.004, 0.004))});
  const BodyClearance inside =
      BodyContactForm(b.mesh, b.body, kDHat, 1.0).clearance(test::positions(b.mesh), kDHat);
  EXPECT_TRUE(inside.intersecting);
  EXPECT_EQ(inside.body_a, 1);
  EXPECT_EQ(inside.body_b, 0);
  // Apart by 2 mm: that distance, no error.
  b = stack({lower, test::box_mesh(1, 1, 1, 0.01, Eigen::Vector3d(0.003, 0.002, 0.012))});
  const BodyContactForm apart(b.mesh, b.body, kDHat, 1.0);
  const BodyClearance c = apart.clearance(test::positions(b.mesh), 0.01);
  EXPECT_FALSE(c.intersecting);
  EXPECT_NEAR(c.distance, 0.002, 1e-15);
  EXPECT_NO_THROW(apart.check_separated(test::positions(b.mesh)));
  // Body ids that do not fit the mesh.
  EXPECT_THROW(BodyContactForm(b.mesh, std::vector<int>(3, 0), kDHat, 1.0), InputError);
  std::vector<int> split = b.body;
  split[0] = 1;  // tet 0 of the lower block now spans both bodies
  EXPECT_THROW(BodyContactForm(b.mesh, split, kDHat, 1.0), InputError);
}

}  // namespace
}  // namespace rbaa
