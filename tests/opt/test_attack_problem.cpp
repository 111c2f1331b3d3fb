// build_attack_problem (issue 19, "One library function builds an attack problem"; issue 16 item
// 4, directed objectives on any body): on a single body it is the sequence the verbs used to
// write by hand, bit for bit; in a world of two balls the design covers the attacked ball only,
// the other ball keeps its material under any design, the objective scores the named ball, and
// the whole problem's gradient (forward, body-body contact, adjoint, masked design map) matches
// central differences per field (SPEC bar 1e-5).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "rbaa/diff/gradient_check.hpp"
#include "rbaa/error.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/mesh/grid_mesh.hpp"
#include "rbaa/mesh/topology.hpp"
#include "rbaa/opt/attack_problem.hpp"
#include "rbaa/scene/scene_mesh.hpp"
#include "rbaa/scene/scene_world.hpp"
#include "rbaa/sim/mass_matrix.hpp"
#include "rbaa/sim/observables.hpp"
#include "support/intersection_free.hpp"

namespace rbaa {
namespace {

// Two balls in free space, the object (r 5 cm, 409 tets) striking the target (r 6 cm) off-centre:
// a soft, wide barrier so that the contact spans four of the 12 steps, and a tight Newton
// tolerance so that central differences resolve Y and nu (their derivatives are 100x smaller
// than rho's).
const char* const kTwoBalls =
    "name: two_balls_free\n"
    "mesh: {shape: sphere, radius: 0.05, target_tets: 400}\n"
    "object: {position: [0, 0, 0], velocity: [2.0, 0, 0]}\n"
    "bodies:\n"
    "  - {name: target, mesh: {shape: sphere, radius: 0.06, target_tets: 150},\n"
    "     position: [0.12, 0.03, 0]}\n"
    "gravity: off\n"
    "time: {step: 0.001, duration: 0.012}\n"
    "contact: {kappa: 1.0e5, d_hat: 5.0e-3}\n"
    "newton: {tolerance: 1.0e-12}\n"
    "reference_material: {Y: 1.0e10, nu: 0.28, rho: 2500}\n"
    "material_bounds: {Y: [2.5e9, 2.0e10]}\n";

Scene two_balls(const std::vector<std::string>& overrides = {}) {
  return parse_scene(kTwoBalls, "two_balls.yaml", "", overrides);
}

const std::string kTargetY = "objective={body: target, kind: target, component: y, value: 0}";

// The problem's reference run, every position checked exactly ("" when none intersects).
std::string reference_intersection(const AttackProblem& p) {
  return test::first_intersection(p.world.mesh, p.settings, p.reference);
}

Eigen::VectorXd positions(const TetMesh& m) {
  return Eigen::Map<const Eigen::VectorXd>(m.V.data(), 3 * m.num_vertices());
}

TEST(AttackProblem, OnOneBodyItIsTheHandWrittenSequenceBitForBit) {
  const Scene scene = load_scene(RBAA_SOURCE_DIR "/configs/ball.yaml", {"mesh.target_tets=300"});
  const AttackProblem p = build_attack_problem(scene);

  // What gradcheck, attack, study and bench_gradient each wrote before.
  const TetMesh mesh = make_scene_mesh(scene);
  const double kappa = scene_barrier_stiffness(scene, mesh);
  const SimulationSettings settings = simulation_settings(scene, kappa);
  const Eigen::VectorXd q0 = positions(mesh);
  const Eigen::VectorXd v0 =
      rigid_velocities(q0, scene.position, scene.velocity, scene.angular_velocity);
  Simulator reference(mesh,
                      MaterialField::uniform(mesh.num_tets(), scene.reference_Y, scene.reference_nu,
                                             scene.reference_rho),
                      settings);
  const Trajectory ref = reference.run(q0, v0);
  EXPECT_EQ(test::first_intersection(mesh, settings, ref), "");
  EXPECT_EQ(reference_intersection(p), "");
  auto objective =
      UndirectedTrajectoryObjective::from_reference(mesh, scene.reference_rho, ref.q.back());
  const DesignSpace design(mesh, design_space_options(scene));
  TrajectoryGradientFunction f(mesh, settings, q0, v0, design, objective);

  EXPECT_EQ(p.world.mesh.V, mesh.V);
  EXPECT_EQ(p.world.mesh.T, mesh.T);
  EXPECT_EQ(p.body_mesh.V, mesh.V);
  EXPECT_EQ(p.kappa, kappa);
  EXPECT_TRUE(p.settings.bodies.empty());
  EXPECT_EQ(p.q0, q0);
  EXPECT_EQ(p.v0, v0);
  EXPECT_EQ(p.reference.q.back(), ref.q.back());
  EXPECT_EQ(p.reference_moments.as_vector(),
            compute_moments(mesh, Eigen::VectorXd::Constant(mesh.num_tets(), 2500.0)).as_vector());
  const Eigen::VectorXd theta = design.initial_theta(true);
  ASSERT_EQ(p.design->size(), design.size());
  EXPECT_EQ(p.design->initial_theta(true), theta);
  EXPECT_EQ(p.body_design->initial_theta(true), theta);
  Eigen::VectorXd g_problem, g_hand;
  const double c_problem = p.gradient->evaluate(theta, &g_problem);
  const double c_hand = f.evaluate(theta, &g_hand);
  std::printf("ball, 300 tets: C %.17g (problem) %.17g (by hand), |g| %.17g %.17g\n", c_problem,
              c_hand, g_problem.norm(), g_hand.norm());
  EXPECT_EQ(c_problem, c_hand);
  EXPECT_EQ(g_problem, g_hand);
}

TEST(AttackProblem, TheDesignCoversTheAttackedBallOnlyAndTheOtherKeepsItsMaterial) {
  for (const std::string attacked : {"object", "target"}) {
    AttackProblemOptions o;
    o.attacked_body = attacked;
    o.with_gradient = false;
    const AttackProblem p = build_attack_problem(two_balls(), o);
    ASSERT_EQ(p.world.bodies.size(), 2u);
    EXPECT_EQ(reference_intersection(p), "") << attacked;
    const Body& a = p.body();
    const Body& other = p.world.bodies[1 - p.attacked];
    EXPECT_EQ(p.attacked, attacked == "object" ? 0 : 1);
    EXPECT_EQ(p.settings.bodies.size(), 2u);
    // theta's size is the masked count: Y, nu, rho per element of A, alpha per interior one.
    const std::vector<char> boundary = boundary_elements(p.body_mesh, false);
    const int interior =
        a.num_elements() - static_cast<int>(std::count(boundary.begin(), boundary.end(), 1));
    EXPECT_EQ(p.design->size(), 3 * a.num_elements() + interior) << attacked;
    EXPECT_EQ(p.body_design->size(), p.design->size());
    EXPECT_EQ(p.design->designed().front(), a.element_begin);
    EXPECT_EQ(p.design->designed().back(), a.element_end - 1);
    EXPECT_EQ(p.body_mesh.num_tets(), a.num_elements());
    // The other ball's material never changes, whatever theta.
    std::mt19937_64 rng(1);
    std::normal_distribution<double> normal(0, 2);
    for (int trial = 0; trial < 3; ++trial) {
      Eigen::VectorXd theta(p.design->size());
      for (int i = 0; i < theta.size(); ++i) theta[i] = normal(rng);
      const MaterialField m = p.design->to_material(theta);
      for (int e = other.element_begin; e < other.element_end; ++e) {
        ASSERT_EQ(m.Y[e], p.reference_materials.Y[e]) << e;
        ASSERT_EQ(m.nu[e], p.reference_materials.nu[e]) << e;
        ASSERT_EQ(m.rho[e], p.reference_materials.rho[e]) << e;
        ASSERT_EQ(m.alpha[e], p.reference_materials.alpha[e]) << e;
      }
      EXPECT_EQ(p.body_materials(m).Y, p.body_design->to_material(theta).Y);
    }
    EXPECT_EQ(p.reference_materials.Y.minCoeff(), 1e10);
    EXPECT_EQ(p.reference_materials.Y.maxCoeff(), 1e10);
    // The moments are A's alone.
    EXPECT_NEAR(p.reference_moments.m0, compute_moments(p.body_mesh, 2500.0).m0, 1e-12);
  }
}

TEST(AttackProblem, TheObjectiveScoresTheNamedBall) {
  const AttackProblem p = build_attack_problem(two_balls({kTargetY}));
  ASSERT_EQ(p.scored, 1);
  EXPECT_EQ(reference_intersection(p), "");
  const Body& b = p.world.bodies[1];
  // Independently: the target's own mesh, its vertex masses and radius of gyration.
  TetMesh target;
  target.V = p.world.mesh.V.middleRows(b.vertex_begin, b.num_vertices());
  target.T = p.world.mesh.T.middleRows(b.element_begin, b.num_elements()).array() - b.vertex_begin;
  const Eigen::VectorXd q = p.reference.q.back().segment(3 * b.vertex_begin, 3 * b.num_vertices());
  const Eigen::Vector3d c = centre_of_mass(
      q, vertex_masses(target, Eigen::VectorXd::Constant(target.num_tets(), 2500.0)));
  const double L = radius_of_gyration(compute_moments(target, 2500.0));
  const double expected = c.y() * c.y() / (L * L);
  const double value = p.objective->evaluate(p.reference, p.reference_materials, nullptr);
  std::printf(
      "target objective at the reference: %.12e (by hand %.12e), c_B %.6f %.6f %.6f, L_B %.5f m\n",
      value, expected, c.x(), c.y(), c.z(), L);
  EXPECT_NEAR(value, expected, 1e-12 * expected);
  EXPECT_GT(c.y(), 0.03);  // the struck ball moved off its start sideways (off-centre impact)
  // The attacked ball's undirected gap is still what reports measure.
  EXPECT_EQ(p.gap->gap(p.reference.q.back()), 0.0);

  // kind away: zero at the reference run, negative elsewhere.
  const AttackProblem away =
      build_attack_problem(two_balls({"objective={body: target, kind: away}"}));
  EXPECT_EQ(away.objective->evaluate(away.reference, away.reference_materials, nullptr), 0.0);
  EXPECT_EQ(reference_intersection(away), "");
  // An unknown attacked body is one line naming the flag and the value.
  AttackProblemOptions ghost;
  ghost.attacked_body = "ghost";
  try {
    build_attack_problem(two_balls(), ghost);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "--body=ghost: the scene has no such body");
  }
}

// with_body puts a replacement of the attacked ball back in its place (the post-processing's
// final object without its voids): given the ball itself, it is the problem's own world, and
// without some of its vertices the reference positions follow vertex_origin.
TEST(AttackProblem, WithBodyPutsTheAttackedBallBackInItsPlace) {
  for (const std::string attacked : {"object", "target"}) {
    AttackProblemOptions o;
    o.attacked_body = attacked;
    o.with_gradient = false;
    const AttackProblem p = build_attack_problem(two_balls({kTargetY}), o);
    EXPECT_EQ(reference_intersection(p), "") << attacked;
    const Body& a = p.body();
    std::vector<int> identity(a.num_vertices());
    for (int v = 0; v < a.num_vertices(); ++v) identity[v] = v;
    const MaterialField mine = p.body_materials(p.reference_materials);
    const ReplacedWorld same = p.with_body(p.body_mesh, mine, identity);
    EXPECT_EQ(same.mesh.V, p.world.mesh.V) << attacked;
    EXPECT_EQ(same.mesh.T, p.world.mesh.T) << attacked;
    EXPECT_EQ(same.reference_final, p.reference.q.back()) << attacked;
    EXPECT_EQ(same.q0, p.q0);
    EXPECT_EQ(same.v0, p.v0);
    EXPECT_EQ(same.materials.Y, p.reference_materials.Y);
    EXPECT_EQ(same.objective->evaluate(p.reference, p.reference_materials, nullptr),
              p.objective->evaluate(p.reference, p.reference_materials, nullptr));
    EXPECT_EQ(same.gap->gap(p.reference.q.back()), 0.0);

    // The ball without its least used vertex and the elements around it (renumbered as
    // remove_void_elements does): the reference's final positions of the kept vertices, in the
    // new order. (The coarse target is a fan: every element uses its centre vertex.)
    std::vector<int> valence(a.num_vertices(), 0);
    for (int e = 0; e < p.body_mesh.num_tets(); ++e) {
      for (int k = 0; k < 4; ++k) ++valence[p.body_mesh.T(e, k)];
    }
    const int dropped =
        static_cast<int>(std::min_element(valence.begin(), valence.end()) - valence.begin());
    std::vector<int> kept;
    for (int v = 0; v < a.num_vertices(); ++v) {
      if (v != dropped) kept.push_back(v);
    }
    std::vector<int> slot(a.num_vertices(), -1);
    for (std::size_t i = 0; i < kept.size(); ++i) slot[kept[i]] = static_cast<int>(i);
    TetMesh cut;
    cut.V.resize(kept.size(), 3);
    for (std::size_t i = 0; i < kept.size(); ++i) cut.V.row(i) = p.body_mesh.V.row(kept[i]);
    std::vector<int> elements;
    for (int e = 0; e < p.body_mesh.num_tets(); ++e) {
      bool uses = false;
      for (int k = 0; k < 4; ++k) uses = uses || p.body_mesh.T(e, k) == dropped;
      if (!uses) elements.push_back(e);
    }
    cut.T.resize(elements.size(), 4);
    for (std::size_t i = 0; i < elements.size(); ++i) {
      for (int k = 0; k < 4; ++k) cut.T(i, k) = slot[p.body_mesh.T(elements[i], k)];
    }
    const ReplacedWorld smaller =
        p.with_body(cut, MaterialField::uniform(cut.num_tets(), 1e10, 0.28, 2500), kept);
    const Body& b = smaller.bodies[p.attacked];
    EXPECT_EQ(b.num_vertices(), a.num_vertices() - 1);
    EXPECT_EQ(b.num_elements(), a.num_elements() - valence[dropped]);
    EXPECT_GT(b.num_elements(), 0);
    const Eigen::VectorXd& q_ref = p.reference.q.back();
    for (std::size_t i = 0; i < kept.size(); ++i) {
      ASSERT_EQ(smaller.reference_final.segment<3>(3 * (b.vertex_begin + i)),
                q_ref.segment<3>(3 * (a.vertex_begin + kept[i])))
          << attacked << " vertex " << i;
    }
    const Body& other = smaller.bodies[1 - p.attacked];
    const Body& old_other = p.world.bodies[1 - p.attacked];
    EXPECT_EQ(smaller.reference_final.segment(3 * other.vertex_begin, 3 * other.num_vertices()),
              q_ref.segment(3 * old_other.vertex_begin, 3 * old_other.num_vertices()));
    EXPECT_EQ(smaller.materials.Y.segment(other.element_begin, other.num_elements()),
              p.reference_materials.Y.segment(old_other.element_begin, old_other.num_elements()));
  }
}

// The gradient check of the whole problem, per field: the struck ball's final y towards 0 (it
// moves sideways off the off-centre impact), the design on the striking ball.
TEST(AttackProblem, TwoBodyDirectedGradientMatchesFiniteDifferencesPerField) {
  for (const std::string& objective :
       {kTargetY, std::string("objective={body: target, kind: away}")}) {
    for (DesignField field :
         {DesignField::kY, DesignField::kNu, DesignField::kRho, DesignField::kAlpha}) {
      // The away objective once, on rho (the check of its seed; the target kind covers the rest).
      if (objective != kTargetY && field != DesignField::kRho) continue;
      AttackProblemOptions o;
      o.fields = {field};
      const AttackProblem p = build_attack_problem(two_balls({objective}), o);
      GradientCheckOptions check;
      check.directions = 2;
      // Richardson-extrapolated central differences at 0.1 in theta: nu moves C by ~1e-6 per
      // unit, and at the default 1e-2 four directions measured up to 1.0e-5 (one thread) and
      // 8.8e-6 (two) against the adjoint, Newton's round-off over the step; at 0.1, <= 4.6e-7.
      check.step = 0.1;
      const GradientCheckResult r =
          check_gradient(*p.gradient, p.design->initial_theta(true), check);
      std::printf("%s, field %-5s: C %.6e |g| %.3e, contact in %d steps, relative errors",
                  objective.c_str(), design_field_name(field), r.value, r.gradient_norm,
                  r.active_contact_steps);
      for (const DirectionCheck& d : r.directions) std::printf(" %.2e", d.relative_error);
      std::printf("\n");
      EXPECT_GE(r.active_contact_steps, 3);
      for (const DirectionCheck& d : r.directions) {
        EXPECT_NE(d.adjoint, 0.0);
        EXPECT_LE(d.relative_error, 1e-5) << design_field_name(field) << " " << objective;
      }
      EXPECT_EQ(reference_intersection(p), "");
      // The check's last run (a finite-difference one).
      EXPECT_EQ(test::first_intersection(p.world.mesh, p.settings, p.gradient->last().trajectory),
                "")
          << design_field_name(field) << " " << objective;
    }
  }
}

// A directed objective divides by the scored body's length L_B squared: a length that is zero,
// negative or not finite is refused by the body's name, in one line; a positive one builds it.
TEST(AttackProblem, ADirectedObjectiveRefusesALengthThatIsNotPositive) {
  const TetMesh mesh = box_tet_mesh({0, 0, 0}, {0.1, 0.1, 0.1}, 1, 1, 1);
  Body body;
  body.name = "bodies[0] (box)";
  body.vertex_end = mesh.num_vertices();
  body.element_end = mesh.num_tets();
  const Eigen::VectorXd final_positions = Eigen::Map<const Eigen::VectorXd>(
      Eigen::MatrixXd(mesh.V.transpose()).data(), 3 * mesh.num_vertices());
  for (const auto kind : {ObjectiveSpec::Kind::kTarget, ObjectiveSpec::Kind::kAway}) {
    ObjectiveSpec spec;
    spec.kind = kind;
    spec.component = 1;
    spec.value = 0.5;
    for (const double length : {0.0, -0.05, std::nan(""), HUGE_VAL}) {
      try {
        make_objective(spec, mesh, {body}, 0, 2500.0, final_positions,
                       Eigen::Vector3d::Constant(0.05), length);
        ADD_FAILURE() << objective_kind_name(kind) << ": length " << length << " was accepted";
      } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("body bodies[0] (box) has no positive radius of gyration"),
                  std::string::npos)
            << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
      }
    }
    EXPECT_NE(make_objective(spec, mesh, {body}, 0, 2500.0, final_positions,
                             Eigen::Vector3d::Constant(0.05), 0.04),
              nullptr);
  }
}

}  // namespace
}  // namespace rbaa
