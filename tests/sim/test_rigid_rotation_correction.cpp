// The finite-rotation correction of Newton steps, per stiff cluster: clusters from the material
// field, and a linearised rotation of each cluster turned into its exact finite rotation.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <Eigen/SparseCore>

#include "rbaa/sim/rigid_rotation_correction.hpp"

namespace rbaa {
namespace {

// Three tets: 0 and 2 stiff and disjoint, 1 soft and sharing a face with each.
TetMesh three_tets() {
  TetMesh m;
  m.V.resize(8, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1,  //
      3, 0, 0, 4, 0, 0, 3, 1, 0, 3, 0, 1;
  m.T.resize(3, 4);
  m.T << 0, 1, 2, 3,  //
      1, 4, 2, 3,     //
      4, 5, 6, 7;
  return m;
}

MaterialField soft_middle() {
  MaterialField f = MaterialField::uniform(3, 6.5e11, 0.3, 2500);
  f.alpha[1] = 3e-3;  // alpha^3 Y = 1.8e4 Pa
  return f;
}

double max_distance_change(const Eigen::VectorXd& x, const Eigen::VectorXd& y, int from, int to) {
  double worst = 0;
  for (int i = from; i < to; ++i) {
    for (int j = i + 1; j < to; ++j) {
      const double before = (x.segment<3>(3 * i) - x.segment<3>(3 * j)).norm();
      const double after = (y.segment<3>(3 * i) - y.segment<3>(3 * j)).norm();
      worst = std::max(worst, std::abs(after - before));
    }
  }
  return worst;
}

TEST(RigidRotationCorrection, StiffElementsFormClustersThroughSharedFaces) {
  const TetMesh m = three_tets();
  const RigidClusters soft = stiff_clusters(m, soft_middle());
  EXPECT_EQ(soft.count, 2);
  EXPECT_EQ(soft.cluster, (std::vector<int>{0, 0, 0, 0, 1, 1, 1, 1}));
  EXPECT_TRUE(soft.hinge[0].empty() && soft.hinge[1].empty());
  // Uniform: tets 0 and 1 share a face (one cluster, the heavier), tet 2 touches them only at
  // vertex 4: a flap of its own, hinged there; vertex 4 belongs to the heavier cluster.
  const RigidClusters uniform = stiff_clusters(m, MaterialField::uniform(3, 6.5e11, 0.3, 2500));
  EXPECT_EQ(uniform.count, 2);
  EXPECT_EQ(uniform.cluster, (std::vector<int>{0, 0, 0, 0, 0, 1, 1, 1}));
  EXPECT_TRUE(uniform.hinge[0].empty());
  EXPECT_EQ(uniform.hinge[1], std::vector<int>{4});
  // Heaviest first: with tet 2 dense enough it is cluster 0 and the pair hinges on it.
  MaterialField dense_flap = MaterialField::uniform(3, 6.5e11, 0.3, 2500);
  dense_flap.rho[2] = 11300;
  const RigidClusters heavy = stiff_clusters(m, dense_flap);
  EXPECT_EQ(heavy.cluster, (std::vector<int>{1, 1, 1, 1, 0, 0, 0, 0}));
  EXPECT_EQ(heavy.hinge[1], std::vector<int>{4});
  // A material 1000x softer than the stiffest still counts as stiff; 1e4x softer does not.
  MaterialField mixed = MaterialField::uniform(3, 6.5e11, 0.3, 2500);
  mixed.Y[1] = 6.5e8 * 1.01;
  EXPECT_EQ(stiff_clusters(m, mixed).cluster, uniform.cluster);
  mixed.Y[1] = 6.5e7;
  EXPECT_EQ(stiff_clusters(m, mixed).cluster, soft.cluster);
}

// A flap turns about its hinge: the hinge vertex moves with the heavier cluster's finite rotation
// and the flap's own vertices turn about it by the flap's whole (composed) rotation, so both stay
// rigid; as one cluster (the old grouping through shared vertices) the flap stays stretched.
TEST(RigidRotationCorrection, AFlapTurnsAboutItsHinge) {
  const TetMesh m = three_tets();
  const Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(m.V.data(), 24);
  Eigen::VectorXd masses(8);
  masses << 0.5, 1.0, 0.25, 2.0, 0.75, 0.5, 1.5, 1.0;
  const RigidClusters clusters = stiff_clusters(m, MaterialField::uniform(3, 6.5e11, 0.3, 2500));
  ASSERT_EQ(clusters.hinge[1], std::vector<int>{4});
  const Eigen::Vector3d w0(0.05, -0.1, 0.2), w1(-0.2, 0.1, 0.15), t0(0.01, 0.02, -0.03);
  Eigen::Vector3d c0 = Eigen::Vector3d::Zero();
  double m0 = 0;
  for (int i = 0; i < 5; ++i) {
    c0 += masses[i] * x.segment<3>(3 * i);
    m0 += masses[i];
  }
  c0 /= m0;
  Eigen::VectorXd dq(24);
  for (int i = 0; i < 5; ++i) dq.segment<3>(3 * i) = t0 + w0.cross(x.segment<3>(3 * i) - c0);
  const Eigen::Vector3d hinge = x.segment<3>(12);
  for (int i = 5; i < 8; ++i) {
    dq.segment<3>(3 * i) = dq.segment<3>(12) + (w0 + w1).cross(x.segment<3>(3 * i) - hinge);
  }
  ASSERT_GT(max_distance_change(x, x + dq, 4, 8), 1e-2);
  const Eigen::VectorXd y = x + rigid_rotation_correction(x, dq, masses, clusters);
  EXPECT_LT(max_distance_change(x, y, 0, 5), 1e-14);
  EXPECT_LT(max_distance_change(x, y, 4, 8), 1e-14);
  const Eigen::Matrix3d R0 = Eigen::AngleAxisd(w0.norm(), w0.normalized()).toRotationMatrix();
  EXPECT_LT((y.segment<3>(12) - (c0 + t0 + R0 * (hinge - c0))).norm(), 1e-14);
  const Eigen::Vector3d w = w0 + w1;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
  for (int i = 5; i < 8; ++i) {
    EXPECT_LT((y.segment<3>(3 * i) - (y.segment<3>(12) + R * (x.segment<3>(3 * i) - hinge))).norm(), 1e-14);
  }
  const Eigen::VectorXd one = rigid_rotation_correction(x, dq, masses, RigidClusters::whole(8));
  EXPECT_GT(max_distance_change(x, x + one, 4, 8), 1e-3);
}

TEST(RigidRotationCorrection, EachClusterTurnsItsLinearisedRotationIntoAFiniteOne) {
  const TetMesh m = three_tets();
  const Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(m.V.data(), 24);
  const Eigen::VectorXd masses = Eigen::VectorXd::Constant(8, 0.5);
  // Cluster 0 turns by w0 about its centre and moves by t0, cluster 1 turns by w1 (linearised).
  const Eigen::Vector3d w0(0.0, 0.0, 0.2), w1(0.1, -0.15, 0.05), t0(0.01, 0.02, -0.03);
  Eigen::VectorXd dq(24);
  Eigen::Vector3d c0 = Eigen::Vector3d::Zero(), c1 = Eigen::Vector3d::Zero();
  for (int i = 0; i < 4; ++i) c0 += x.segment<3>(3 * i) / 4;
  for (int i = 4; i < 8; ++i) c1 += x.segment<3>(3 * i) / 4;
  for (int i = 0; i < 4; ++i) dq.segment<3>(3 * i) = t0 + w0.cross(x.segment<3>(3 * i) - c0);
  for (int i = 4; i < 8; ++i) dq.segment<3>(3 * i) = w1.cross(x.segment<3>(3 * i) - c1);
  const double linear_stretch = max_distance_change(x, x + dq, 0, 4);
  EXPECT_GT(linear_stretch, 1e-2);  // the linearised rotation stretches by ~theta^2 / 2

  const RigidClusters clusters = stiff_clusters(m, soft_middle());
  const Eigen::VectorXd corrected = rigid_rotation_correction(x, dq, masses, clusters);
  const Eigen::VectorXd y = x + corrected;
  EXPECT_LT(max_distance_change(x, y, 0, 4), 1e-14);
  EXPECT_LT(max_distance_change(x, y, 4, 8), 1e-14);
  const Eigen::Matrix3d R0 = Eigen::AngleAxisd(w0.norm(), w0.normalized()).toRotationMatrix();
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d expected = c0 + t0 + R0 * (x.segment<3>(3 * i) - c0);
    EXPECT_LT((y.segment<3>(3 * i) - expected).norm(), 1e-14);
  }
  // One cluster for the whole mesh: a single best-fit rotation, which cannot undo two different
  // rotations; the tets stay stretched.
  const Eigen::VectorXd whole = rigid_rotation_correction(x, dq, masses, RigidClusters::whole(8));
  EXPECT_GT(max_distance_change(x, x + whole, 0, 4), 1e-3);
  // Vertices outside every cluster keep their linear step.
  RigidClusters none;
  none.cluster.assign(8, -1);
  EXPECT_TRUE(rigid_rotation_correction(x, dq, masses, none) == dq);
}

// The rigid predictor moves the previous shape onto a guess by its centre of mass and best-fit
// (Kabsch) rotation: for a guess that is an exact rigid motion it reproduces it; for a chord
// extrapolation (a linearised rotation, which stretches the body) it stays rigid, with the
// guess's centre of mass, and turns by the angle the chords describe.
TEST(RigidPredictor, RecoversRigidMotionsAndStaysRigidOnChords) {
  const TetMesh m = three_tets();
  const Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(m.V.data(), 24);
  Eigen::VectorXd masses(8);
  masses << 0.5, 1.0, 0.25, 2.0, 0.75, 0.5, 1.5, 1.0;  // uneven: the centre is mass-weighted
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int i = 0; i < 8; ++i) c += masses[i] * x.segment<3>(3 * i);
  c /= masses.sum();
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  const Eigen::Vector3d t(0.3, -0.1, 2.0);
  Eigen::VectorXd moved(24), chord(24);
  const Eigen::Vector3d w(0.0, 0.25, 0.1);  // a quarter radian, linearised
  for (int i = 0; i < 8; ++i) {
    moved.segment<3>(3 * i) = c + t + R * (x.segment<3>(3 * i) - c);
    chord.segment<3>(3 * i) = x.segment<3>(3 * i) + t + w.cross(x.segment<3>(3 * i) - c);
  }
  const Eigen::VectorXd p = rigid_predictor(x, moved, masses);
  EXPECT_LT((p - moved).lpNorm<Eigen::Infinity>(), 1e-14);
  ASSERT_GT(max_distance_change(x, chord, 0, 8), 1e-2);  // the chords stretch
  const Eigen::VectorXd q = rigid_predictor(x, chord, masses);
  EXPECT_LT(max_distance_change(x, q, 0, 8), 1e-14);
  Eigen::Vector3d cq = Eigen::Vector3d::Zero();
  for (int i = 0; i < 8; ++i) cq += masses[i] * q.segment<3>(3 * i);
  EXPECT_LT((cq / masses.sum() - (c + t)).norm(), 1e-14);
  // It turned towards the chords: closer to them (mass-weighted) than the translation alone.
  double turned = 0, translated = 0;
  for (int i = 0; i < 8; ++i) {
    turned += masses[i] * (q.segment<3>(3 * i) - chord.segment<3>(3 * i)).squaredNorm();
    translated += masses[i] * (x.segment<3>(3 * i) + t - chord.segment<3>(3 * i)).squaredNorm();
  }
  EXPECT_LT(turned, 0.05 * translated);
  // And it is the best-fit rotation over every vertex: at the optimum of
  // sum m |q_i - chord_i|^2 over rotations about the centre, the torque
  // sum m (q_i - c) x (chord_i - c) vanishes (Kabsch's stationarity).
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();
  double scale = 0;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d a = q.segment<3>(3 * i) - (c + t), b = chord.segment<3>(3 * i) - (c + t);
    torque += masses[i] * a.cross(b);
    scale += masses[i] * a.norm() * b.norm();
  }
  EXPECT_LT(torque.norm(), 1e-14 * scale);
}

// The rigid sub-step is Newton restricted to the six rigid motions: on a quadratic energy
// 1/2 (y - y*)^T K (y - y*) with K = diag(masses) (each 3 times) and y* a small rigid motion of x,
// its translation is exact, its rotation exact to first order (applied as a finite rotation), and
// with a non-rigid part in y* it still lowers the energy.
TEST(RigidNewtonStep, SolvesTheRigidPartOfAQuadratic) {
  const TetMesh m = three_tets();
  const Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(m.V.data(), 24);
  Eigen::VectorXd masses(8);
  masses << 0.5, 1.0, 0.25, 2.0, 0.75, 0.5, 1.5, 1.0;
  Eigen::SparseMatrix<double> K(24, 24);
  for (int i = 0; i < 24; ++i) K.insert(i, i) = masses[i / 3];
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int i = 0; i < 8; ++i) c += masses[i] * x.segment<3>(3 * i);
  c /= masses.sum();
  const Eigen::Vector3d t(1e-3, -2e-3, 5e-4), w(2e-4, -1e-4, 3e-4);
  Eigen::VectorXd target(24);
  for (int i = 0; i < 8; ++i) target.segment<3>(3 * i) = x.segment<3>(3 * i) + t + w.cross(x.segment<3>(3 * i) - c);
  const Eigen::VectorXd g = K * (x - target);
  const Eigen::VectorXd ds = rigid_newton_step(x, g, K, masses);
  ASSERT_EQ(ds.size(), 24);
  // Finite rotation vs the linearised target: they differ by at most |w|^2 |r| / 2.
  double r_max = 0;
  for (int i = 0; i < 8; ++i) r_max = std::max(r_max, (x.segment<3>(3 * i) - c).norm());
  const double second_order = 0.5 * w.squaredNorm() * r_max;
  EXPECT_LT((x + ds - target).lpNorm<Eigen::Infinity>(), 1.01 * second_order);
  EXPECT_GT((x + ds - target).lpNorm<Eigen::Infinity>(), 0.1 * second_order);  // it is finite
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int i = 0; i < 8; ++i) mean += masses[i] * ds.segment<3>(3 * i);
  EXPECT_LT((mean / masses.sum() - t).norm(), 1e-15);
  EXPECT_LT(max_distance_change(x, x + ds, 0, 8), 1e-15);  // a rigid step
  // A non-rigid target: the step still descends and lowers the energy.
  Eigen::VectorXd bent = target;
  bent[5] += 3e-3;
  const Eigen::VectorXd g2 = K * (x - bent);
  const Eigen::VectorXd ds2 = rigid_newton_step(x, g2, K, masses);
  auto energy = [&](const Eigen::VectorXd& y) { return 0.5 * (y - bent).dot(K * (y - bent)); };
  EXPECT_LT(g2.dot(ds2), 0);
  EXPECT_LT(energy(x + ds2), energy(x));
  // A Hessian with no stiffness along the rigid motions gives no step.
  const Eigen::SparseMatrix<double> zero(24, 24);
  EXPECT_EQ(rigid_newton_step(x, g, zero, masses).size(), 0);
}

}  // namespace
}  // namespace rbaa
