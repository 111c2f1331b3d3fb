#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "mesh_fixtures.hpp"
#include "rbaa/error.hpp"
#include "rbaa/sim/observables.hpp"
#include "rbaa/sim/simulator.hpp"

namespace rbaa {
namespace {

// Centre of mass, linear and angular momentum of a deformed, moving body with random per-element
// rho and alpha, through the simulator's vertex masses and mass matrix, against sums over the
// element masses m_e = rho_e alpha_e V_e computed here: for linear fields and the consistent mass,
// int rho x = sum_e m_e mean_a x_a, int rho v likewise, and
// int rho x cross v = sum_e m_e / 20 [(sum_a x_a) cross (sum_b v_b) + sum_a x_a cross v_a].
TEST(Observables, NonUniformMaterialsMatchElementMassSums) {
  const TetMesh mesh = test::ball_mesh(0.1, 3);
  const int nt = mesh.num_tets(), nv = mesh.num_vertices();
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  MaterialField m = MaterialField::uniform(nt, 1e10, 0.3, 2500);
  for (int e = 0; e < nt; ++e) {
    m.rho[e] = 800 + 10500 * unit(rng);
    m.alpha[e] = unit(rng) < 0.3 ? 1e-3 : 0.2 + 0.8 * unit(rng);
  }
  SimulationSettings settings;
  Simulator sim(mesh, m, settings);
  const Eigen::VectorXd q = test::deformed(mesh, 0.05, 4);
  Eigen::VectorXd v(3 * nv);
  for (Eigen::Index i = 0; i < v.size(); ++i) v[i] = 2 * unit(rng) - 1;

  double m0 = 0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero(), p = Eigen::Vector3d::Zero(),
                  L = Eigen::Vector3d::Zero();
  for (int e = 0; e < nt; ++e) {
    Eigen::Matrix3d D;
    for (int a = 1; a < 4; ++a) D.col(a - 1) = (mesh.V.row(mesh.T(e, a)) - mesh.V.row(mesh.T(e, 0))).transpose();
    const double me = m.rho[e] * m.alpha[e] * std::abs(D.determinant()) / 6.0;
    Eigen::Vector3d sx = Eigen::Vector3d::Zero(), sv = Eigen::Vector3d::Zero(), cross = Eigen::Vector3d::Zero();
    for (int a = 0; a < 4; ++a) {
      const Eigen::Vector3d x = q.segment<3>(3 * mesh.T(e, a)), va = v.segment<3>(3 * mesh.T(e, a));
      sx += x;
      sv += va;
      cross += x.cross(va);
    }
    m0 += me;
    first += me * sx / 4;
    p += me * sv / 4;
    L += me / 20 * (sx.cross(sv) + cross);
  }
  const Eigen::VectorXd Mv = sim.inertia_form().multiply(v);
  const Eigen::Vector3d com = centre_of_mass(q, sim.vertex_masses());
  EXPECT_NEAR(sim.vertex_masses().sum(), m0, 1e-13 * m0);
  EXPECT_LE((com - first / m0).norm(), 1e-13);
  EXPECT_LE((linear_momentum(Mv) - p).norm(), 1e-12 * p.norm());
  EXPECT_LE((angular_momentum(q, Mv) - L).norm(), 1e-12 * L.norm());
  // Non-uniform indeed: the mass-weighted centre is far from the plain vertex average.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int i = 0; i < nv; ++i) mean += q.segment<3>(3 * i) / nv;
  EXPECT_GT((com - mean).norm(), 1e-4);
}

// A bounce off z = 0 at steps 3-4 whose outgoing velocity settles like BDF-2's parasitic mode
// (deviation x 1/3 per step) towards 4 m/s, under gravity -10 m/s^2 at h = 0.01.
TEST(Observables, BounceReadsTheSettledOutgoingVelocity) {
  const double h = 0.01, g = -10;
  std::vector<std::vector<double>> distances;
  std::vector<Eigen::Vector3d> velocity;
  for (int k = 0; k < 14; ++k) {
    distances.push_back({(k == 3 || k == 4) ? 5e-4 : 0.1});
    double vz = -3.0;
    if (k >= 5) vz = 4.0 - 1.0 * std::pow(1.0 / 3.0, k - 5) + g * h * (k - 5);
    velocity.emplace_back(0, 0, vz);
  }
  const std::vector<Bounce> b = find_bounces(distances, velocity, {Plane{Eigen::Vector3d::UnitZ(), 0.0}}, 1e-3,
                                             Eigen::Vector3d(0, 0, g), h, 5);
  ASSERT_EQ(b.size(), 1u);
  EXPECT_EQ(b[0].kind, BounceKind::kBounce);
  // Read 5 steps later: the deviation is 1/3^5 = 0.4 % of its first value; gravity is taken out.
  EXPECT_NEAR(b[0].restitution, 4.0 / 3.0, 1.0 / 243.0 / 3.0 + 1e-12);
  // Reading at the first step after the contact would have given 3/3 = 1.
  const std::vector<Bounce> early = find_bounces(distances, velocity, {Plane{Eigen::Vector3d::UnitZ(), 0.0}}, 1e-3,
                                                 Eigen::Vector3d(0, 0, g), h, 0);
  EXPECT_NEAR(early[0].restitution, 1.0, 1e-12);
}

// Contact with the floor (steps 3-4) overlapping contact with a wall (steps 4-5): one corner
// episode, both planes named, no restitution. Measured per plane, the wall's "in" velocity would
// be read inside the floor contact and the floor's "out" inside the wall contact.
TEST(Observables, TwoPlanesInOneEpisodeAreACornerWithoutRestitution) {
  const std::vector<Plane> planes = {Plane{Eigen::Vector3d::UnitZ(), 0.0},
                                     Plane{Eigen::Vector3d::UnitY(), 0.0}};
  std::vector<std::vector<double>> distances;
  std::vector<Eigen::Vector3d> velocity;
  for (int k = 0; k < 12; ++k) {
    distances.push_back({(k == 3 || k == 4) ? 5e-4 : 0.1, (k == 4 || k == 5) ? 5e-4 : 0.1});
    // Tilted into the corner: the floor turns the wall-normal velocity around too.
    velocity.emplace_back(0, k < 3 ? -1.0 : (k < 6 ? 0.2 : 0.4), k < 3 ? -1.0 : 0.3);
  }
  const std::vector<Bounce> b =
      find_bounces(distances, velocity, planes, 1e-3, Eigen::Vector3d::Zero(), 0.01, 0);
  ASSERT_EQ(b.size(), 1u);
  EXPECT_EQ(b[0].kind, BounceKind::kCorner);
  EXPECT_STREQ(bounce_kind_name(b[0].kind), "corner");
  EXPECT_EQ(b[0].planes, (std::vector<int>{0, 1}));
  EXPECT_EQ(b[0].first_step, 3);
  EXPECT_EQ(b[0].last_step, 5);
  EXPECT_EQ(b[0].normal_velocity_in, (std::vector<double>{-1.0, -1.0}));
  EXPECT_EQ(b[0].normal_velocity_out, (std::vector<double>{0.3, 0.4}));
  EXPECT_TRUE(std::isnan(b[0].restitution));
  EXPECT_NE(b[0].note.find("planes 0 and 1"), std::string::npos) << b[0].note;
}

// A one-plane contact whose normal velocity does not reverse (the body grazes the plane and
// keeps approaching it more slowly until the run ends, or was already leaving) is no bounce; one
// still in contact at the end has no outgoing velocity yet.
TEST(Observables, ContactsWithoutReversalOrEndAreNotBounces) {
  const std::vector<Plane> floor = {Plane{Eigen::Vector3d::UnitZ(), 0.0}};
  std::vector<std::vector<double>> distances;
  std::vector<Eigen::Vector3d> velocity;
  for (int k = 0; k < 10; ++k) {
    // Grazes at step 2 and keeps approaching, slower, to the end without touching again.
    distances.push_back({k == 2 ? 5e-4 : 0.1});
    velocity.emplace_back(0, 0, k < 2 ? -1.0 : -0.43);
  }
  const std::vector<Bounce> graze =
      find_bounces(distances, velocity, floor, 1e-3, Eigen::Vector3d::Zero(), 0.01, 0);
  ASSERT_EQ(graze.size(), 1u);
  EXPECT_EQ(graze[0].kind, BounceKind::kNoReversal);
  EXPECT_TRUE(std::isnan(graze[0].restitution));
  EXPECT_NE(graze[0].note.find("did not reverse"), std::string::npos) << graze[0].note;

  // Leaves the plane at step 4 (moving away), lands again at step 8 and is in contact at the end.
  for (int k = 0; k < 10; ++k) {
    distances[k] = {(k == 2 || k == 8 || k == 9) ? 5e-4 : 0.1};
    velocity[k] = Eigen::Vector3d(0, 0, k < 2 ? -1.0 : k < 4 ? -0.43 : k < 6 ? 0.3 : k < 9 ? -0.43 : -0.2);
  }
  const std::vector<Bounce> b =
      find_bounces(distances, velocity, floor, 1e-3, Eigen::Vector3d::Zero(), 0.01, 0);
  ASSERT_EQ(b.size(), 2u);
  EXPECT_EQ(b[0].kind, BounceKind::kNoReversal);
  EXPECT_EQ(b[0].last_step, 2);
  EXPECT_EQ(b[1].kind, BounceKind::kUnfinished);
  EXPECT_FALSE(b[1].complete());
  // Its outgoing velocity so far is the last state's (not one past the end).
  EXPECT_EQ(b[1].normal_velocity_out, (std::vector<double>{-0.2}));
  EXPECT_EQ(b[1].normal_velocity_in, (std::vector<double>{-0.43}));
  EXPECT_TRUE(std::isnan(b[1].restitution));
}

// A tumbling body's impact at a fine step: its first corner slows it (-11.2 -> -0.8 m/s, the
// bunny of configs/demos/bunny_bin.yaml at h = 1.5625e-4 s), it leaves d_hat still approaching
// and its next corner sends it up (+8.2 m/s). One bounce, rebound 8.2 / 11.2: read per contact
// the second would have been 8.2 / 0.8 = 10.3, the first no bounce (the rigid twin's restitution
// was then fitted to 10.3, clamped at 3).
TEST(Observables, ContactsWhileStillApproachingAreOneImpact) {
  const std::vector<Plane> floor = {Plane{Eigen::Vector3d::UnitZ(), 0.0}};
  std::vector<std::vector<double>> distances;
  std::vector<Eigen::Vector3d> velocity;
  for (int k = 0; k < 16; ++k) {
    distances.push_back({(k == 3 || k == 4 || k == 9) ? 5e-4 : 0.1});
    velocity.emplace_back(0.5, 0, k < 3 ? -11.2 : k < 9 ? -0.8 : 8.2);
  }
  const std::vector<Bounce> b =
      find_bounces(distances, velocity, floor, 1e-3, Eigen::Vector3d::Zero(), 0.01, 3);
  ASSERT_EQ(b.size(), 1u);
  EXPECT_EQ(b[0].kind, BounceKind::kBounce);
  EXPECT_EQ(b[0].first_step, 3);
  EXPECT_EQ(b[0].last_step, 9);
  EXPECT_NEAR(b[0].restitution, 8.2 / 11.2, 1e-15);
  // Turning away in between (at step 5, the first out of contact) makes them two contacts again.
  velocity[5].z() = 0.1;
  const std::vector<Bounce> two =
      find_bounces(distances, velocity, floor, 1e-3, Eigen::Vector3d::Zero(), 0.01, 3);
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(two[0].kind, BounceKind::kNoReversal);
  EXPECT_EQ(two[1].kind, BounceKind::kBounce);
}

// A caller slicing one body out of a several-body vector must pass exactly that body's
// coordinates: a longer slice used to be read silently up to the masses' length (and past the
// vector's end when the body came last).
TEST(Observables, CentreOfMassRefusesCoordinatesThatAreNotTheMasses) {
  const Eigen::VectorXd m = Eigen::VectorXd::Constant(2, 0.5);
  Eigen::VectorXd q(6);
  q << 0, 0, 0, 2, 4, 6;
  EXPECT_TRUE(centre_of_mass(q, m).isApprox(Eigen::Vector3d(1, 2, 3)));
  for (const int n : {3, 9}) {
    try {
      centre_of_mass(Eigen::VectorXd::Zero(n), m);
      ADD_FAILURE() << n << " coordinates for two masses were accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(std::to_string(n) + " coordinates for 2 vertex masses"),
                std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace rbaa
