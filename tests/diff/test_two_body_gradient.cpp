// The adjoint through contact between bodies: the two colliding balls of the several-bodies tests
// (sim/body_fixtures.hpp) with soft materials, every element of both in the design space. The
// gradient with respect to each body's materials, per field, against central differences (SPEC
// bar 1e-5) and the tangent-linear model (1e-10). Nothing in the adjoint knows about the bodies:
// it uses the exact Hessian of the body-contact form, whose blocks extend the pattern.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "rbaa/diff/gradient_check.hpp"
#include "rbaa/diff/trajectory_gradient.hpp"
#include "rbaa/diff/trajectory_objective.hpp"
#include "sim/body_fixtures.hpp"
#include "support/intersection_free.hpp"

namespace rbaa {
namespace {

DesignSpaceOptions soft_design(std::vector<DesignField> fields) {
  DesignSpaceOptions o;
  o.fields = std::move(fields);
  o.Y_min = 2e7;
  o.Y_max = 2e9;
  o.reference_rho = 1000;
  o.seed = 5;
  o.perturbation = 0.5;
  return o;
}

std::shared_ptr<UndirectedTrajectoryObjective> reference_objective(const test::TwoBalls& t,
                                                                   const Eigen::VectorXd& q0,
                                                                   const Eigen::VectorXd& v0) {
  Simulator ref(t.mesh, MaterialField::uniform(t.mesh.num_tets(), 5e9, 0.28, 1000), t.settings);
  const Trajectory reference = ref.run(q0, v0);
  EXPECT_EQ(test::first_intersection(t.mesh, t.settings, reference), "");
  return UndirectedTrajectoryObjective::from_reference(t.mesh, 1000, reference.q.back());
}

TEST(TwoBodyGradient, AdjointMatchesFiniteDifferencesPerFieldAndBody) {
  const test::TwoBalls t = test::two_balls();
  const Eigen::VectorXd q0 = test::positions(t.mesh);
  const Eigen::VectorXd v0 = initial_velocities(q0, t.bodies);
  const auto objective = reference_objective(t, q0, v0);
  for (DesignField field : {DesignField::kY, DesignField::kNu, DesignField::kRho, DesignField::kAlpha}) {
    DesignSpace ds(t.mesh, soft_design({field}));
    TrajectoryGradientFunction f(t.mesh, t.settings, q0, v0, ds, objective);
    for (const Body& body : t.bodies) {
      GradientCheckOptions o;
      o.step = 1e-2;  // test_adjoint.cpp explains the step
      o.directions = 2;
      o.element_begin = body.element_begin;
      o.element_end = body.element_end;
      const GradientCheckResult r = check_gradient(f, ds.initial_theta(true), o);
      std::printf("two bodies, %-5s of %s: |g| %.3e contact steps %d, relative errors",
                  design_field_name(field), body.name.c_str(), r.gradient_norm,
                  r.active_contact_steps);
      for (const DirectionCheck& d : r.directions) {
        std::printf(" %.2e (at 4x the step %.2e, %s)", d.relative_error, d.coarse_relative_error,
                    d.noise_dominated ? "noise" : "not noise");
      }
      std::printf("\n");
      EXPECT_GE(r.active_contact_steps, 3);
      for (const DirectionCheck& d : r.directions) EXPECT_NE(d.adjoint, 0.0);
      // Along the body's own gradient (issue 19: check along the gradient direction too) the
      // slope is the largest the body's entries allow, so central differences resolve it for
      // every field, nu included: SPEC's bar, no exception.
      {
        const Eigen::VectorXd theta = ds.initial_theta(true);
        Eigen::VectorXd g;
        f.evaluate(theta, &g);
        Eigen::VectorXd d = Eigen::VectorXd::Zero(g.size());
        // theta holds #T entries (Y, nu, rho) or one per interior element (alpha).
        for (int i = 0; i < g.size(); ++i) {
          const int e = field == DesignField::kAlpha ? ds.interior()[i] : i;
          if (e >= body.element_begin && e < body.element_end) d[i] = g[i];
        }
        ASSERT_GT(d.norm(), 0.0);
        const double slope = d.norm();
        d /= slope;
        // Along the gradient C curves most: at s = 1e-2 the O(s^2) truncation measured 4e-6 ..
        // 2.7e-5; at 1e-3 it is 100x smaller while the slope s (>= 6e-10) stays far above C's
        // noise (~4e-16, below).
        const double s = 1e-3;
        const double fd = (f.evaluate(theta + s * d, nullptr) - f.evaluate(theta - s * d, nullptr)) / (2 * s);
        const double error = std::abs(fd - slope) / std::max(std::abs(fd), slope);
        std::printf("two bodies, %-5s of %s along its gradient: slope %.6e, relative error %.2e\n",
                    design_field_name(field), body.name.c_str(), slope, error);
        EXPECT_LE(error, 1e-5) << design_field_name(field) << " of " << body.name;
        // The last run (theta - s d).
        EXPECT_EQ(test::first_intersection(t.mesh, t.settings, f.last().trajectory), "");
      }
      // Random directions: Y, rho and alpha meet SPEC's 1e-5 (<= 2.3e-7 per body). One random
      // direction of nu of A measures 1.3e-3 at s = 1e-2 and 1.6e-5 at 4 s: noise-dominated, and
      // measured why (2026-11-26): its slope is 5.6e-11, 9e-5 of A's nu gradient (6.2e-7: the
      // direction is nearly orthogonal to it), so s x slope = 5.6e-13 against C's noise of
      // ~4e-16 (C scanned over s = -0.02 .. 0.02 is a symmetric quadratic to that level; the
      // noise follows Newton's tolerance: 1.7e-14 at 1e-10, 4e-16 at 1e-12). Such a direction
      // is accepted only as noise-dominated; the gradient-direction check above holds nu to
      // SPEC's bar without exception.
      for (const DirectionCheck& d : r.directions) {
        if (field != DesignField::kNu) {
          EXPECT_LE(d.relative_error, 1e-5) << design_field_name(field) << " of " << body.name;
        } else {
          EXPECT_TRUE(d.relative_error <= 1e-5 || d.noise_dominated)
              << "nu of " << body.name << ": " << d.relative_error;
        }
      }
    }
  }
}

TEST(TwoBodyGradient, AdjointMatchesTheTangentLinearModel) {
  const test::TwoBalls t = test::two_balls();
  const Eigen::VectorXd q0 = test::positions(t.mesh);
  const Eigen::VectorXd v0 = initial_velocities(q0, t.bodies);
  const auto objective = reference_objective(t, q0, v0);
  DesignSpace ds(t.mesh, soft_design({DesignField::kY, DesignField::kNu, DesignField::kRho,
                                      DesignField::kAlpha}));
  TrajectoryGradientFunction f(t.mesh, t.settings, q0, v0, ds, objective);
  GradientCheckOptions o;
  o.method = GradientCheckMethod::kTangent;
  o.directions = 3;
  const GradientCheckResult r = check_gradient(f, ds.initial_theta(true), o);
  std::printf("two bodies tangent: |g| %.3e, contact steps %d, errors", r.gradient_norm,
              r.active_contact_steps);
  for (const DirectionCheck& d : r.directions) std::printf(" %.2e", d.tangent_relative_error);
  std::printf("\n");
  EXPECT_GE(r.active_contact_steps, 3);
  EXPECT_LE(r.max_tangent_relative_error, 1e-10);
  EXPECT_EQ(test::first_intersection(t.mesh, t.settings, f.last().trajectory), "");
}

}  // namespace
}  // namespace rbaa
