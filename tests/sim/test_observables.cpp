#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "mesh_fixtures.hpp"
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
  EXPECT_TRUE(b[0].complete);
  // Read 5 steps later: the deviation is 1/3^5 = 0.4 % of its first value; gravity is taken out.
  EXPECT_NEAR(b[0].restitution, 4.0 / 3.0, 1.0 / 243.0 / 3.0 + 1e-12);
  // Reading at the first step after the contact would have given 3/3 = 1.
  const std::vector<Bounce> early = find_bounces(distances, velocity, {Plane{Eigen::Vector3d::UnitZ(), 0.0}}, 1e-3,
                                                 Eigen::Vector3d(0, 0, g), h, 0);
  EXPECT_NEAR(early[0].restitution, 1.0, 1e-12);
}

}  // namespace
}  // namespace rbaa
