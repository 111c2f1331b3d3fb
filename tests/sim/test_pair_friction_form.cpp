// Lagged friction on mesh pairs (pair_friction_form.hpp), against triangle-mesh obstacles (a
// tilted floor and a spike under a box: vertex-triangle, triangle-vertex and edge-edge pairs) and
// between two boxes (the upper one turned by 30 deg: crossing edges; by 1 deg: mollified nearly
// parallel edges): value, gradient and Hessian against central differences while sliding and
// sticking; the force is Coulomb's mu lambda with each mesh's own coefficient; friction between
// bodies sums to zero; the history terms the adjoint and the tangent use against central
// differences of the step equation in q_n and q_{n-1}.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cstdio>
#include <map>
#include <string>

#include "form_checks.hpp"
#include "mesh_fixtures.hpp"
#include "obstacle_fixtures.hpp"
#include "rbaa/contact/distance_type.hpp"
#include "rbaa/error.hpp"
#include "rbaa/sim/pair_friction_form.hpp"
#include "rbaa/sim/sparse_hessian.hpp"

namespace rbaa {
namespace {

constexpr double kDHat = 3e-3;
constexpr double kKappa = 50.0;
constexpr double kH = 1e-2;

// A contact configuration: the rest mesh (one or two bodies), lagged positions and the forms.
struct Contact {
  TetMesh mesh;
  std::vector<int> body;  // body id per vertex
  std::vector<ObstacleMesh> obstacles;
  std::vector<double> mesh_mu;
  Eigen::MatrixXd body_mu;
  Eigen::VectorXd q_n, q_prev;
};

// A 0.1 x 0.1 x 0.05 box 1 mm above a slightly tilted floor (mu 0.4), with a spike's apex 0.8 mm
// under its bottom face near a vertex (mu 0.7), sliding at (2, -1) mm per step.
Contact box_on_obstacles() {
  Contact s;
  s.mesh = test::box_mesh(2, 2, 1, 0.05, Eigen::Vector3d(0.013, -0.021, 0.0));
  s.body.assign(s.mesh.num_vertices(), 0);
  ObstacleMesh floor = test::square_obstacle(1.0, -1e-3);
  const Eigen::Matrix3d tilt =
      Eigen::AngleAxisd(0.01, Eigen::Vector3d(1, 2, 0).normalized()).toRotationMatrix();
  for (Eigen::Index v = 0; v < floor.V.rows(); ++v)
    floor.V.row(v) = (tilt * floor.V.row(v).transpose()).transpose();
  s.obstacles = {floor, test::spike_obstacle(Eigen::Vector3d(0.0645, 0.0296, -0.8e-3), 0.01, 0.01)};
  s.mesh_mu = {0.4, 0.7};
  s.q_n = test::positions(s.mesh);
  s.q_prev = s.q_n;
  for (int v = 0; v < s.mesh.num_vertices(); ++v)
    s.q_prev.segment<3>(3 * v) -= Eigen::Vector3d(2e-3, -1e-3, 0);
  return s;
}

// Box A (0.1 x 0.1 x 0.05) and above it box B (0.05 cube) turned by `angle_deg` about z, 1 mm
// apart, B's bottom edges (unturned) 0.2 mm beside A's top edges x = 0.05, 0.1 and y = 0, 0.05;
// B slides over A at (2, -1) mm per step, A at rest. mu 0.5 between them.
Contact stacked_boxes(double angle_deg) {
  Contact s;
  const TetMesh a = test::box_mesh(2, 2, 1, 0.05);
  TetMesh b = test::box_mesh(1, 1, 1, 0.05, Eigen::Vector3d(-0.025, -0.025, 0.0));
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(angle_deg * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  for (int v = 0; v < b.num_vertices(); ++v) {
    b.V.row(v) = (R * b.V.row(v).transpose() + Eigen::Vector3d(0.0752, 0.0248, 0.051)).transpose();
  }
  s.mesh.V.resize(a.num_vertices() + b.num_vertices(), 3);
  s.mesh.V << a.V, b.V;
  s.mesh.T.resize(a.num_tets() + b.num_tets(), 4);
  s.mesh.T << a.T, (b.T.array() + a.num_vertices()).matrix();
  s.body.assign(a.num_vertices(), 0);
  s.body.insert(s.body.end(), b.num_vertices(), 1);
  s.body_mu = Eigen::MatrixXd::Zero(2, 2);
  s.body_mu(0, 1) = s.body_mu(1, 0) = 0.5;
  s.q_n = test::positions(s.mesh);
  s.q_prev = s.q_n;
  for (int v = a.num_vertices(); v < s.mesh.num_vertices(); ++v) {
    s.q_prev.segment<3>(3 * v) -= Eigen::Vector3d(2e-3, -1e-3, 0);
  }
  return s;
}

// The contact forms and the friction form of a configuration, lagged from (q_n, q_prev).
struct Forms {
  std::unique_ptr<MeshObstacleForm> obstacles;
  std::unique_ptr<BodyContactForm> bodies;
  std::unique_ptr<PairFrictionForm> friction;
};

Forms make_forms(const Contact& s, double eps_v) {
  Forms f;
  if (!s.obstacles.empty())
    f.obstacles = std::make_unique<MeshObstacleForm>(s.mesh, s.obstacles, kDHat, kKappa);
  if (s.body_mu.size() > 0)
    f.bodies = std::make_unique<BodyContactForm>(s.mesh, s.body, kDHat, kKappa);
  f.friction = std::make_unique<PairFrictionForm>(f.obstacles.get(), s.mesh_mu, f.bodies.get(),
                                                  s.body_mu, eps_v, Integrator::kBdf2, kH);
  f.friction->lag(s.q_n, s.q_prev);
  return f;
}

std::map<std::string, int> type_counts(const PairFrictionForm& f) {
  std::map<std::string, int> counts;
  for (const LaggedFrictionPair& p : f.lagged_pairs()) {
    const char* name =
        p.points.edge_edge
            ? contact::to_string(static_cast<contact::EdgeEdgeDistanceType>(p.type))
            : contact::to_string(static_cast<contact::PointTriangleDistanceType>(p.type));
    ++counts[std::string(p.points.edge_edge        ? "EE "
                         : p.points.vertex[0] >= 0 ? "VT "
                                                   : "TV ") +
             name];
  }
  return counts;
}

std::string describe(const std::map<std::string, int>& counts) {
  std::string text;
  for (const auto& [k, n] : counts) text += k + " x" + std::to_string(n) + ", ";
  return text;
}

struct Case {
  const char* name;
  Contact contact;
};

std::vector<Case> cases() {
  return {{"box on floor and spike", box_on_obstacles()},
          {"boxes turned 30 deg", stacked_boxes(30)},
          {"boxes turned 1 deg", stacked_boxes(1)}};
}

TEST(PairFriction, PairsOfEveryKindAreLagged) {
  for (const Case& c : cases()) {
    const Forms f = make_forms(c.contact, 1e-3);
    const auto counts = type_counts(*f.friction);
    std::printf("%s: %d lagged pairs: %s\n", c.name, f.friction->num_lagged_pairs(),
                describe(counts).c_str());
    int vt = 0, tv = 0, ee = 0, mollified = 0, degenerate = 0;
    for (const LaggedFrictionPair& p : f.friction->lagged_pairs()) {
      vt += !p.points.edge_edge && p.points.vertex[0] >= 0;
      tv += !p.points.edge_edge && p.points.vertex[0] < 0;
      ee += p.points.edge_edge;
      mollified += p.points.edge_edge && pair_mollifier(p.points) < 1;
      degenerate += p.points.edge_edge
                        ? p.type != static_cast<int>(contact::EdgeEdgeDistanceType::EA_EB)
                        : p.type != static_cast<int>(contact::PointTriangleDistanceType::P_T);
      EXPECT_GT(p.normal_force, 0) << c.name;
    }
    EXPECT_GT(vt, 0) << c.name;
    EXPECT_GT(ee, 0) << c.name;
    if (std::string(c.name) == "box on floor and spike") {
      EXPECT_GT(tv, 0);
      EXPECT_GT(degenerate, 0);  // closest points on an edge or a corner
    }
    if (std::string(c.name) == "boxes turned 1 deg") {
      EXPECT_GT(mollified, 0);
      EXPECT_GT(degenerate, 0);
    }
  }
}

TEST(PairFriction, DerivativesMatchFiniteDifferencesSlidingAndSticking) {
  for (const Case& c : cases()) {
    // eps = eps_v 2h/3: sliding 1e-3 m/s (eps 6.7e-6 m) against steps of ~1e-3 m; sticking 10 m/s.
    for (double eps_v : {1e-3, 10.0}) {
      const Forms f = make_forms(c.contact, eps_v);
      ASSERT_GE(f.friction->num_lagged_pairs(), 4) << c.name;
      SparseHessian H(c.contact.mesh.T, c.contact.mesh.num_vertices());
      const Eigen::VectorXd x =
          test::deformed(c.contact.mesh, 1e-4, 3) + (c.contact.q_n - c.contact.q_prev);
      const test::FdErrors e = test::check_form(*f.friction, x, 1e-8, H);
      EXPECT_LT(e.gradient, 1e-6) << c.name << " eps_v " << eps_v;
      EXPECT_LT(e.hessian, 1e-5) << c.name << " eps_v " << eps_v;
      const Eigen::MatrixXd Hx = test::form_hessian(*f.friction, x, HessianKind::kExact, H);
      EXPECT_GE(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Hx).eigenvalues().minCoeff(),
                -1e-12 * Hx.norm())
          << c.name;
      // value_difference agrees with the difference of values where that does not cancel.
      const Eigen::VectorXd x1 = x + 1e-4 * (c.contact.q_n - c.contact.q_prev);
      EXPECT_NEAR(f.friction->value_difference(x, x1), f.friction->value(x1) - f.friction->value(x),
                  1e-9 * std::abs(f.friction->value(x)))
          << c.name;
    }
  }
}

// Sliding fast against the floor: each body vertex over a floor triangle's interior feels mu
// lambda of ITS mesh with lambda = -kappa b'(d) from its distance to the floor at q_n, and the
// pairs of the spike carry the spike's coefficient.
TEST(PairFriction, TheForceIsCoulombsWithEachMeshsCoefficient) {
  const Contact s = box_on_obstacles();
  const Forms f = make_forms(s, 1e-3);
  const contact::Barrier barrier(kDHat);
  const Eigen::Vector3d n =
      (s.obstacles[0].V.row(1) - s.obstacles[0].V.row(0))
          .transpose()
          .cross((s.obstacles[0].V.row(2) - s.obstacles[0].V.row(0)).transpose())
          .normalized();
  const Eigen::Vector3d o = s.obstacles[0].V.row(0).transpose();
  auto on_floor = [&](const Eigen::Vector3d& y) { return std::abs(n.dot(y - o)) < 1e-12; };
  const Eigen::VectorXd x = s.q_n + (s.q_n - s.q_prev);
  // The floor's friction alone, and how many of its pairs each vertex is in.
  PairFrictionForm one(f.obstacles.get(), {0.4, 0.0}, nullptr, {}, 1e-3, Integrator::kBdf2, kH);
  one.lag(s.q_n, s.q_prev);
  std::map<int, int> pairs_of_vertex;
  for (const LaggedFrictionPair& p : one.lagged_pairs()) {
    for (int v : p.points.vertex) {
      if (v >= 0) ++pairs_of_vertex[v];
    }
  }
  Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size());
  one.add_gradient(x, 1.0, g);
  int floor_pairs = 0, spike_pairs = 0;
  for (const LaggedFrictionPair& p : f.friction->lagged_pairs()) {
    bool floor = true;
    for (int i = 0; i < 4; ++i) {
      if (p.points.vertex[i] < 0) floor = floor && on_floor(p.points.x[i]);
    }
    EXPECT_EQ(p.mu, floor ? 0.4 : 0.7);
    spike_pairs += !floor;
    // A vertex over a floor triangle's interior, in no other floor pair (none of the box's
    // bottom edges crossing the floor's diagonal): the force on it is this pair's.
    if (!floor || p.points.edge_edge || p.points.vertex[0] < 0 ||
        p.type != static_cast<int>(contact::PointTriangleDistanceType::P_T) ||
        pairs_of_vertex[p.points.vertex[0]] != 1) {
      continue;
    }
    ++floor_pairs;
    const double d = n.dot(p.points.x[0] - o);
    const double lambda = -kKappa * barrier.first_derivative(d);
    EXPECT_NEAR(p.normal_force, lambda, 1e-12 * lambda);
    const Eigen::Vector3d gv = g.segment<3>(3 * p.points.vertex[0]);
    EXPECT_NEAR(gv.norm(), 0.4 * lambda, 1e-9 * lambda);
    EXPECT_NEAR(gv.dot(n), 0.0, 1e-12 * lambda);
    const Eigen::Vector3d step =
        x.segment<3>(3 * p.points.vertex[0]) - s.q_n.segment<3>(3 * p.points.vertex[0]);
    EXPECT_GT(gv.dot(step), 0);
  }
  EXPECT_GE(floor_pairs, 4);
  EXPECT_GE(spike_pairs, 1);
}

TEST(PairFriction, FrictionBetweenBodiesSumsToZero) {
  for (double angle : {30.0, 1.0}) {
    const Contact s = stacked_boxes(angle);
    const Forms f = make_forms(s, 1e-3);
    const Eigen::VectorXd x = test::deformed(s.mesh, 1e-4, 7) + (s.q_n - s.q_prev);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size());
    f.friction->add_gradient(x, 1.0, g);
    Eigen::Vector3d on_a = Eigen::Vector3d::Zero(), on_b = Eigen::Vector3d::Zero();
    for (int v = 0; v < s.mesh.num_vertices(); ++v)
      (s.body[v] == 0 ? on_a : on_b) += g.segment<3>(3 * v);
    std::printf(
        "boxes turned %.0f deg: friction on A (%.4e, %.4e, %.4e), on B (%.4e, %.4e, %.4e)\n", angle,
        on_a.x(), on_a.y(), on_a.z(), on_b.x(), on_b.y(), on_b.z());
    EXPECT_GT(on_b.norm(), 0);
    EXPECT_LT((on_a + on_b).norm(), 1e-12 * on_b.norm());
  }
}

// G_f(q_n, q_prev) = w grad D at x, lagged from (q_n, q_prev): its Jacobians in q_n and q_prev
// by central differences against add_history_adjoint (transposed) and add_history_tangent.
TEST(PairFriction, HistoryTermsMatchDifferencesOfTheStepEquation) {
  const double w = 4.0 / 9.0 * kH * kH;
  for (const Case& c : cases()) {
    for (double eps_v : {1e-3, 10.0}) {
      const Contact& s = c.contact;
      const Eigen::VectorXd x = test::deformed(s.mesh, 1e-4, 5) + 0.8 * (s.q_n - s.q_prev);
      auto G = [&](const Eigen::VectorXd& q_n, const Eigen::VectorXd& q_prev) {
        Contact t = s;
        t.q_n = q_n;
        t.q_prev = q_prev;
        const Forms f = make_forms(t, eps_v);
        Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size());
        f.friction->add_gradient(x, w, g);
        return g;
      };
      const Eigen::MatrixXd J_n =
          test::fd_jacobian([&](const Eigen::VectorXd& q) { return G(q, s.q_prev); }, s.q_n, 1e-9);
      const Eigen::MatrixXd J_p =
          test::fd_jacobian([&](const Eigen::VectorXd& q) { return G(s.q_n, q); }, s.q_prev, 1e-9);
      ASSERT_GT(J_n.norm(), 0);
      ASSERT_GT(J_p.norm(), 0);
      const Forms f = make_forms(s, eps_v);
      const Eigen::VectorXd a = Eigen::VectorXd::Random(x.size());
      Eigen::VectorXd bar_n = Eigen::VectorXd::Zero(x.size()), bar_p = bar_n;
      f.friction->add_history_adjoint(x, a, w, bar_n, bar_p);
      const double err_n = (bar_n + J_n.transpose() * a).norm() / (J_n.transpose() * a).norm();
      const double err_p = (bar_p + J_p.transpose() * a).norm() / (J_p.transpose() * a).norm();
      const Eigen::VectorXd dn = Eigen::VectorXd::Random(x.size()),
                            dp = Eigen::VectorXd::Random(x.size());
      Eigen::VectorXd t = Eigen::VectorXd::Zero(x.size());
      f.friction->add_history_tangent(x, dn, dp, w, t);
      const double err_t = (t - J_n * dn - J_p * dp).norm() / (J_n * dn + J_p * dp).norm();
      std::printf("%s, eps_v %g: history adjoint errors %.1e (q_n) %.1e (q_n-1), tangent %.1e\n",
                  c.name, eps_v, err_n, err_p, err_t);
      EXPECT_LT(err_n, 1e-6) << c.name << " " << eps_v;
      EXPECT_LT(err_p, 1e-6) << c.name << " " << eps_v;
      EXPECT_LT(err_t, 1e-6) << c.name << " " << eps_v;
    }
  }
}

TEST(PairFriction, BadCoefficientsAreRefused) {
  const Contact s = box_on_obstacles();
  const MeshObstacleForm obstacles(s.mesh, s.obstacles, kDHat, kKappa);
  EXPECT_THROW(PairFrictionForm(&obstacles, {0.4, -0.1}, nullptr, {}, 1e-3, Integrator::kBdf2, kH),
               InputError);
  EXPECT_THROW(PairFrictionForm(&obstacles, {0.4}, nullptr, {}, 1e-3, Integrator::kBdf2, kH),
               InputError);
  EXPECT_THROW(PairFrictionForm(&obstacles, {0.4, 0.1}, nullptr, {}, 0.0, Integrator::kBdf2, kH),
               InputError);
  Eigen::MatrixXd mu = Eigen::MatrixXd::Zero(2, 2);
  mu(0, 1) = mu(1, 0) = -0.5;
  EXPECT_THROW(PairFrictionForm(nullptr, {}, nullptr, mu, 1e-3, Integrator::kBdf2, kH), InputError);
}

}  // namespace
}  // namespace rbaa
