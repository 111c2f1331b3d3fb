// Objectives of one body of a stacked mesh (issue 16 item 4: directed objectives on any body):
// the undirected term of body A and the centre of mass of body B read only their own body's
// vertices and elements, equal the single-body objectives of that body's own mesh, and their
// seeds (dC/dq and the direct material terms) match central differences.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "rbaa/diff/trajectory_objective.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/sim/mass_matrix.hpp"
#include "rbaa/sim/observables.hpp"
#include "sim/body_fixtures.hpp"

namespace rbaa {
namespace {

// A two-position trajectory whose final positions are `q`.
Trajectory ending_at(const Eigen::VectorXd& q0, const Eigen::VectorXd& q) {
  Trajectory t;
  t.time_step = 1e-3;
  t.q = {q0, q};
  t.steps.resize(1);
  return t;
}

// Body b's own mesh, cut out of the stacked one.
TetMesh own_mesh(const TetMesh& stacked, const Body& b) {
  TetMesh m;
  m.V = stacked.V.middleRows(b.vertex_begin, b.num_vertices());
  m.T = stacked.T.middleRows(b.element_begin, b.num_elements()).array() - b.vertex_begin;
  return m;
}

TEST(BodyObjectives, UndirectedTermOfOneBodyIsThatBodysOwn) {
  const test::TwoBalls t = test::two_balls();
  const Eigen::VectorXd q0 = test::positions(t.mesh);
  const Eigen::VectorXd q_ref = test::deformed(t.mesh, 0.02, 1);
  Eigen::VectorXd q = test::deformed(t.mesh, 0.02, 2);
  for (int i = 0; i < 2; ++i) {
    const Body& b = t.bodies[i];
    const Body& other = t.bodies[1 - i];
    const auto objective = UndirectedTrajectoryObjective::from_reference(t.mesh, 2500, q_ref, b);
    const TetMesh mine = own_mesh(t.mesh, b);
    const auto alone = UndirectedTrajectoryObjective::from_reference(
        mine, 2500, q_ref.segment(3 * b.vertex_begin, 3 * b.num_vertices()));
    const Trajectory run = ending_at(q0, q);
    TrajectorySeed seed;
    const double value = objective->evaluate(run, t.materials, &seed);
    const double expected =
        alone->evaluate(ending_at(q0.segment(3 * b.vertex_begin, 3 * b.num_vertices()),
                                  q.segment(3 * b.vertex_begin, 3 * b.num_vertices())),
                        t.materials, nullptr);
    std::printf("undirected term of body %s: %.12e (its own mesh: %.12e)\n", b.name.c_str(), value,
                expected);
    EXPECT_NEAR(value, expected, 1e-12 * std::abs(expected));
    EXPECT_NEAR(objective->m0_ref(), compute_moments(mine, 2500).m0, 1e-12);
    // The other body's vertices carry no weight, in the value and in the seed.
    Eigen::VectorXd moved = q;
    moved.segment(3 * other.vertex_begin, 3 * other.num_vertices()).array() += 0.3;
    EXPECT_EQ(objective->evaluate(ending_at(q0, moved), t.materials, nullptr), value);
    EXPECT_EQ(seed.dq[1].segment(3 * other.vertex_begin, 3 * other.num_vertices()).norm(), 0.0);
    EXPECT_GT(seed.dq[1].segment(3 * b.vertex_begin, 3 * b.num_vertices()).norm(), 0.0);
  }
}

TEST(BodyObjectives, CentreOfMassOfOneBodyReadsOnlyThatBody) {
  const test::TwoBalls t = test::two_balls();
  const Eigen::VectorXd q0 = test::positions(t.mesh);
  const Eigen::VectorXd q = test::deformed(t.mesh, 0.02, 3);
  MaterialField materials = t.materials;
  for (int e = 0; e < materials.size(); ++e) materials.alpha[e] = 0.6 + 0.4 * std::cos(e);
  for (int i = 0; i < 2; ++i) {
    const Body& b = t.bodies[i];
    const Body& other = t.bodies[1 - i];
    const Eigen::Vector3d direction(0.3, -1.0, 0.5);
    const CentreOfMassObservable com(t.mesh, b, direction);
    TrajectorySeed seed;
    const double value = com.evaluate(ending_at(q0, q), materials, &seed);
    // Independently: the body's vertex masses from sim/mass_matrix on its own mesh.
    const TetMesh mine = own_mesh(t.mesh, b);
    const Eigen::VectorXd density =
        materials.effective_density().segment(b.element_begin, b.num_elements());
    const Eigen::Vector3d c = centre_of_mass(q.segment(3 * b.vertex_begin, 3 * b.num_vertices()),
                                             vertex_masses(mine, density));
    EXPECT_NEAR(value, direction.dot(c), 1e-14);
    // Another body moving or changing its materials does not move it.
    Eigen::VectorXd moved = q;
    moved.segment(3 * other.vertex_begin, 3 * other.num_vertices()).array() += 0.3;
    MaterialField heavier = materials;
    heavier.rho.segment(other.element_begin, other.num_elements()) *= 3.0;
    EXPECT_EQ(com.evaluate(ending_at(q0, moved), heavier, nullptr), value);
    EXPECT_EQ(seed.dq[1].segment(3 * other.vertex_begin, 3 * other.num_vertices()).norm(), 0.0);
    EXPECT_EQ(seed.direct.rho.segment(other.element_begin, other.num_elements()).norm(), 0.0);
    EXPECT_EQ(seed.direct.alpha.segment(other.element_begin, other.num_elements()).norm(), 0.0);

    // The seed against central differences: along a random position change of every vertex, and
    // along the densities and occupancies of every element.
    const Eigen::VectorXd dq = test::deformed(t.mesh, 1.0, 4) - test::deformed(t.mesh, 0.0, 4);
    const double h = 1e-6;
    const double fd_q = (com.evaluate(ending_at(q0, q + h * dq), materials, nullptr) -
                         com.evaluate(ending_at(q0, q - h * dq), materials, nullptr)) /
                        (2 * h);
    const double ad_q = seed.dq[1].dot(dq);
    // Materials move the value by ~1e-6 per unit: a larger step keeps round-off (1e-17 / step)
    // and truncation (step^2 (drho / rho)^2) both below 1e-8 relative.
    const double hm = 1e-3;
    Eigen::VectorXd drho = Eigen::VectorXd::LinSpaced(materials.size(), 1.0, 2.0);
    drho = drho.array().sin() * 100.0;
    MaterialField up = materials, down = materials;
    up.rho += hm * drho;
    down.rho -= hm * drho;
    const double fd_rho = (com.evaluate(ending_at(q0, q), up, nullptr) -
                           com.evaluate(ending_at(q0, q), down, nullptr)) /
                          (2 * hm);
    const double ad_rho = seed.direct.rho.dot(drho);
    const Eigen::VectorXd dalpha = 0.1 * drho / 100.0;
    up = materials;
    down = materials;
    up.alpha += hm * dalpha;
    down.alpha -= hm * dalpha;
    const double fd_alpha = (com.evaluate(ending_at(q0, q), up, nullptr) -
                             com.evaluate(ending_at(q0, q), down, nullptr)) /
                            (2 * hm);
    const double ad_alpha = seed.direct.alpha.dot(dalpha);
    std::printf("com of body %s: dq %.3e vs %.3e, drho %.3e vs %.3e, dalpha %.3e vs %.3e\n",
                b.name.c_str(), ad_q, fd_q, ad_rho, fd_rho, ad_alpha, fd_alpha);
    EXPECT_NEAR(ad_q, fd_q, 1e-7 * std::abs(fd_q));
    EXPECT_NEAR(ad_rho, fd_rho, 1e-6 * std::abs(fd_rho));
    EXPECT_NEAR(ad_alpha, fd_alpha, 1e-6 * std::abs(fd_alpha));
  }
}

}  // namespace
}  // namespace rbaa
