// demonstration.object_copies in `rbaa evaluate`: a body named there is a copy of each run's
// object, deformable and rigid: the adversarial run's copy has the adversarial object's mesh and
// materials. Two small cubes without gravity: the object (turned 45 deg about x, as the cube
// stack's striker) hits `target` head on.

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "rbaa/eval/evaluation.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/scene/scene.hpp"
#include "rbaa/scene/scene_mesh.hpp"

namespace rbaa {
namespace {

// The object's right face at x = -0.035 m, the target's left face at -0.025: they meet at
// t ~ 0.01 s. The target is traced (evaluation.body).
Scene two_cubes(const std::vector<std::string>& overrides = {}) {
  return parse_scene(
      "mesh: {shape: cube, side: 0.05, target_tets: 100}\n"
      "object: {position: [-0.06, 0, 0], velocity: [1, 0, 0], rotation: {axis: [1, 0, 0], "
      "angle_deg: 45}}\n"
      "bodies:\n"
      "  - {name: target, mesh: {shape: cube, side: 0.05, target_tets: 100}, position: [0, 0, 0]}\n"
      "gravity: off\n"
      "time: {step: 0.002, duration: 0.04}\n"
      "evaluation: {time_step: 0.002, duration: 0.04, body: target}\n"
      "reference_material: {Y: 1.0e10, nu: 0.3, rho: 1000}\n"
      "demonstration:\n"
      "  predicate: {kind: stands, bodies: [object, target], min_height: -1}\n"
      "  object_copies: [target]\n",
      "two_cubes.yaml", "", overrides);
}

EvaluationOptions options_for(const Scene& scene) {
  EvaluationOptions o;
  o.time_step = scene.time_step;
  o.soft_control = false;
  return o;
}

double final_speed(const RunTrace& t) { return t.velocity.back().x(); }

// The adversarial object four times as dense as the reference: with copies the target is as heavy
// as the striker and stops it (as the reference does); without, the light target flies off at
// ~1.6 times the striker's speed, which keeps going.
TEST(EvaluationObjectCopies, TheAdversarialRunsCopiesAreTheAdversarialObject) {
  const Scene with = two_cubes();
  const Scene without = two_cubes({"demonstration.object_copies=[]"});
  const TetMesh mesh = make_scene_mesh(with);
  const MaterialField heavy =
      MaterialField::uniform(mesh.num_tets(), 1e10, 0.3, 4 * with.reference_rho, 1.0);
  const Evaluation a = evaluate(with, mesh, mesh, heavy, options_for(with));
  const Evaluation b = evaluate(without, mesh, mesh, heavy, options_for(without));

  // The runs' own materials: the copy's mass and inertia are the object's in each run.
  ASSERT_EQ(a.reference_body_moments.size(), 2u);
  ASSERT_EQ(a.adversarial_body_moments.size(), 2u);
  const auto principal = [](const Moments& m) {
    return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(m.inertia_about_centre()).eigenvalues();
  };
  for (const auto* run : {&a.reference_body_moments, &a.adversarial_body_moments}) {
    const Moments& object = (*run)[0];
    const Moments& copy = (*run)[1];
    EXPECT_NEAR(copy.m0 / object.m0, 1.0, 1e-12);
    EXPECT_LT((principal(copy) - principal(object)).norm(), 1e-12 * principal(object).norm());
    EXPECT_LT(copy.centre_of_mass().norm(), 1e-15);  // the target's position
  }
  EXPECT_NEAR(a.adversarial_body_moments[1].m0 / a.reference_body_moments[1].m0, 4.0, 1e-12);
  // Without copies the target keeps the reference material in every run.
  EXPECT_NEAR(b.adversarial_body_moments[1].m0 / b.reference_body_moments[1].m0, 1.0, 1e-12);
  EXPECT_NEAR(b.adversarial_body_moments[0].m0 / b.reference_body_moments[0].m0, 4.0, 1e-12);

  // The reference runs do not change (the target's own mesh is the object's shape), ...
  EXPECT_NEAR(final_speed(a.deformable_reference), final_speed(b.deformable_reference), 1e-3);
  EXPECT_NEAR(final_speed(a.rigid_reference), final_speed(b.rigid_reference), 1e-3);
  // ... the adversarial ones do, deformable and rigid.
  std::printf("target's final speed (m/s): reference deformable %.4f rigid %.4f; adversarial with "
              "copies deformable %.4f rigid %.4f, without %.4f and %.4f\n",
              final_speed(a.deformable_reference), final_speed(a.rigid_reference),
              final_speed(a.deformable_adversarial), final_speed(a.rigid_adversarial),
              final_speed(b.deformable_adversarial), final_speed(b.rigid_adversarial));
  EXPECT_GT(final_speed(a.deformable_reference), 0.5);  // the collision happened
  EXPECT_NEAR(final_speed(a.deformable_adversarial), final_speed(a.deformable_reference), 0.1);
  EXPECT_NEAR(final_speed(a.rigid_adversarial), final_speed(a.rigid_reference), 0.05);
  EXPECT_GT(final_speed(b.deformable_adversarial) - final_speed(a.deformable_adversarial), 0.3);
  EXPECT_GT(final_speed(b.rigid_adversarial) - final_speed(a.rigid_adversarial), 0.3);
}

// An adversarial object with the reference's moments (random densities with the moment-changing
// part projected out, random stiffness): its copies have the same moments too, so the rigid
// reference and adversarial runs agree, every body, as they do for the object alone.
TEST(EvaluationObjectCopies, RigidTwinsOfMomentMatchedCopiesAgree) {
  const Scene scene = two_cubes();
  const TetMesh mesh = make_scene_mesh(scene);
  MaterialField adv = MaterialField::uniform(mesh.num_tets(), 5e9, 0.3, scene.reference_rho, 1.0);
  const Eigen::MatrixXd S = moment_operator(mesh);
  std::srand(5);
  const Eigen::VectorXd r = Eigen::VectorXd::Random(mesh.num_tets()) * 300.0;
  adv.rho += r - S.transpose() * (S * S.transpose()).ldlt().solve(S * r);
  for (int e = 0; e < mesh.num_tets(); ++e) adv.Y[e] = (e % 3 == 0) ? 5e9 : 6.5e11;
  const Evaluation ev = evaluate(scene, mesh, mesh, adv, options_for(scene));

  EXPECT_NEAR((ev.reference_moments.as_vector() - ev.adversarial_moments.as_vector()).norm() /
                  ev.reference_moments.m0, 0.0, 1e-10);
  // The copy in the adversarial run carries the adversarial densities: not the reference's
  // uniform ones, element by element, but the same mass.
  EXPECT_NEAR(ev.adversarial_body_moments[1].m0 / ev.reference_body_moments[1].m0, 1.0, 1e-10);
  EXPECT_LT(ev.rigid_vs_rigid.max_position_gap, 1e-9);  // the target's
  EXPECT_LT(ev.rigid_vs_rigid.orientation_gap_deg, 1e-6);
  ASSERT_GE(ev.demonstration_runs.size(), 2u);
  const DemonstrationRun& ref = ev.demonstration_runs[0];
  const DemonstrationRun& adv_run = ev.demonstration_runs[1];
  ASSERT_EQ(ref.object, "reference");
  ASSERT_EQ(adv_run.object, "adversarial");
  ASSERT_EQ(ref.paths.size(), 2u);
  ASSERT_EQ(adv_run.paths.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    double gap = 0;
    for (size_t k = 0; k < ref.paths[i].centre.size(); ++k) {
      gap = std::max(gap, (ref.paths[i].centre[k] - adv_run.paths[i].centre[k]).norm());
    }
    EXPECT_LT(gap, 1e-9) << ref.paths[i].name;
    std::printf("rigid reference vs adversarial, body '%s': largest gap %.3g m\n",
                ref.paths[i].name.c_str(), gap);
  }
  // The target moved (the collision happened in the twins).
  EXPECT_GT(ev.rigid_reference.centre.back().x(), 0.01);
}

}  // namespace
}  // namespace rbaa
