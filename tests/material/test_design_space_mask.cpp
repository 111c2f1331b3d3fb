// The design space's element mask (issue 19: attack body A, score body B): two boxes stacked into
// one mesh, the design covering the first box only. theta's size is the masked count, the other
// box keeps its material under any theta, its gradient entries are dropped, the chain rule holds
// on the masked map, and the masked layout is the one the first box's own design space has.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "rbaa/error.hpp"
#include "rbaa/material/design_space.hpp"
#include "rbaa/mesh/grid_mesh.hpp"
#include "rbaa/mesh/topology.hpp"

namespace rbaa {
namespace {

struct TwoBoxes {
  TetMesh a, b, stacked;
  std::vector<char> mask;  // the first box's elements
};

// Box A (3 x 3 x 4 cells, with interior elements) and box B beside it, stacked A then B; with
// b_first, B then A (the attacked body need not be the first in the mesh).
TwoBoxes two_boxes(bool b_first = false) {
  TwoBoxes t;
  t.a = box_tet_mesh({0.3, -0.2, 0.5}, {1.1, 0.4, 1.4}, 3, 3, 4);
  t.b = box_tet_mesh({2.0, 0.0, 0.0}, {2.5, 0.5, 0.5}, 2, 2, 2);
  const TetMesh& first = b_first ? t.b : t.a;
  const TetMesh& second = b_first ? t.a : t.b;
  t.stacked.V.resize(first.num_vertices() + second.num_vertices(), 3);
  t.stacked.V << first.V, second.V;
  t.stacked.T.resize(first.num_tets() + second.num_tets(), 4);
  t.stacked.T << first.T, (second.T.array() + first.num_vertices()).matrix();
  t.mask.assign(t.stacked.num_tets(), 0);
  const int begin = b_first ? t.b.num_tets() : 0;
  std::fill(t.mask.begin() + begin, t.mask.begin() + begin + t.a.num_tets(), 1);
  return t;
}

// A material for the whole stacked mesh, distinct per element (B's values must survive exactly).
MaterialField distinct_field(int nt) {
  MaterialField m = MaterialField::uniform(nt, 1e10, 0.3, 3000, 1.0);
  for (int e = 0; e < nt; ++e) {
    m.Y[e] = 1e10 + 1e7 * e;
    m.nu[e] = 0.25 + 1e-4 * e;
    m.rho[e] = 3000 + e;
    m.alpha[e] = 1.0 - 1e-4 * (e % 7);
  }
  return m;
}

TEST(DesignSpaceMask, ThetaCoversOnlyTheMaskedElements) {
  for (bool b_first : {false, true}) {
    const TwoBoxes t = two_boxes(b_first);
    const int na = t.a.num_tets();
    const std::vector<char> boundary = boundary_elements(t.a, false);
    const int interior_a = na - static_cast<int>(std::count(boundary.begin(), boundary.end(), 1));
    ASSERT_GT(interior_a, 0);

    const DesignSpace masked(t.stacked, DesignSpaceOptions{}, t.mask);
    EXPECT_EQ(masked.num_designed(), na);
    EXPECT_EQ(masked.size(), 3 * na + interior_a) << "b_first " << b_first;
    EXPECT_EQ(masked.block_size(DesignField::kY), na);
    EXPECT_EQ(masked.block_size(DesignField::kAlpha), interior_a);
    for (int e : masked.designed()) EXPECT_TRUE(t.mask[e]);
    for (int e : masked.interior()) EXPECT_TRUE(t.mask[e]);
    EXPECT_EQ(masked.num_tets(), t.stacked.num_tets());

    // The same layout and the same draws as the first box's own design space: the attacked
    // body's design does not depend on what else is in the world.
    const DesignSpace own(t.a, DesignSpaceOptions{});
    ASSERT_EQ(own.size(), masked.size());
    EXPECT_EQ(own.initial_theta(true), masked.initial_theta(true));
    const MaterialField mw = masked.to_material(masked.initial_theta(true));
    const MaterialField mo = own.to_material(own.initial_theta(true));
    const int begin = masked.designed().front();
    EXPECT_EQ(mw.Y.segment(begin, na), mo.Y);
    EXPECT_EQ(mw.nu.segment(begin, na), mo.nu);
    EXPECT_EQ(mw.rho.segment(begin, na), mo.rho);
    EXPECT_EQ(mw.alpha.segment(begin, na), mo.alpha);
  }
}

TEST(DesignSpaceMask, MaskedOutElementsKeepTheirMaterialUnderAnyTheta) {
  for (bool b_first : {false, true}) {
    const TwoBoxes t = two_boxes(b_first);
    const int nt = t.stacked.num_tets();
    const MaterialField fixed = distinct_field(nt);
    DesignSpace design(t.stacked, DesignSpaceOptions{}, t.mask);
    design.hold_fixed_elements(fixed);
    std::mt19937_64 rng(3);
    std::normal_distribution<double> normal(0.0, 3.0);
    for (int trial = 0; trial < 5; ++trial) {
      Eigen::VectorXd theta(design.size());
      for (int i = 0; i < theta.size(); ++i) theta[i] = normal(rng);
      const MaterialField m = design.to_material(theta);
      int moved = 0;
      for (int e = 0; e < nt; ++e) {
        if (t.mask[e]) {
          moved += m.Y[e] != fixed.Y[e];
          continue;
        }
        EXPECT_EQ(m.Y[e], fixed.Y[e]) << e;
        EXPECT_EQ(m.nu[e], fixed.nu[e]) << e;
        EXPECT_EQ(m.rho[e], fixed.rho[e]) << e;
        EXPECT_EQ(m.alpha[e], fixed.alpha[e]) << e;
      }
      EXPECT_EQ(moved, t.a.num_tets());
    }
    // to_theta reads only the designed elements: the fixed field's own theta is the design's.
    const MaterialField back =
        design.to_material(design.to_theta(design.to_material(design.initial_theta())));
    for (int e = 0; e < nt; ++e) {
      if (!t.mask[e]) {
        EXPECT_EQ(back.rho[e], fixed.rho[e]) << e;
      }
    }
  }
}

TEST(DesignSpaceMask, ChainRuleOnTheMaskedMapMatchesFiniteDifferences) {
  const TwoBoxes t = two_boxes(true);  // the designed box second: offsets are not zero
  const int nt = t.stacked.num_tets();
  DesignSpaceOptions o;
  o.seed = 3;
  o.perturbation = 0.5;
  DesignSpace design(t.stacked, o, t.mask);
  design.hold_fixed_elements(distinct_field(nt));
  const Eigen::VectorXd theta = design.initial_theta();

  // A nonlinear objective of every element's material, the fixed ones included.
  const Eigen::VectorXd w = Eigen::VectorXd::LinSpaced(nt, -1.0, 2.0);
  auto C = [&](const MaterialField& m) {
    double c = 0.0;
    for (int e = 0; e < nt; ++e) {
      c += w[e] * (m.Y[e] / 1e11) * (m.Y[e] / 1e11) + std::sin(3 * m.nu[e] + w[e]) +
           std::sqrt(m.rho[e]) * 0.01 + w[e] * m.alpha[e] * m.alpha[e] * m.alpha[e];
    }
    return c;
  };
  const MaterialField m = design.to_material(theta);
  MaterialGradient g;
  g.Y = (2 * w.array() * m.Y.array() / 1e22).matrix();
  g.nu = (3 * (3 * m.nu.array() + w.array()).cos()).matrix();
  g.rho = (0.005 / m.rho.array().sqrt()).matrix();
  g.alpha = (3 * w.array() * m.alpha.array().square()).matrix();
  const Eigen::VectorXd analytic = design.chain_gradient(theta, g);

  const double eps = 1e-4;
  Eigen::VectorXd fd(design.size());
  for (int i = 0; i < design.size(); ++i) {
    Eigen::VectorXd tp = theta, tm = theta;
    tp[i] += eps;
    tm[i] -= eps;
    fd[i] = (C(design.to_material(tp)) - C(design.to_material(tm))) / (2 * eps);
  }
  for (DesignField f :
       {DesignField::kY, DesignField::kNu, DesignField::kRho, DesignField::kAlpha}) {
    const auto a = analytic.segment(design.offset(f), design.block_size(f));
    const auto n = fd.segment(design.offset(f), design.block_size(f));
    const double err = (a - n).norm() / n.norm();
    std::printf("masked chain rule, field %-5s: relative error against central differences %.2e\n",
                design_field_name(f), err);
    EXPECT_LT(err, 1e-7) << design_field_name(f);
  }
  // The fixed elements' gradient is dropped, not folded in anywhere.
  MaterialGradient only_fixed;
  for (Eigen::VectorXd* v : {&only_fixed.Y, &only_fixed.nu, &only_fixed.rho, &only_fixed.alpha}) {
    *v = Eigen::VectorXd::Zero(nt);
    for (int e = 0; e < nt; ++e) (*v)[e] = t.mask[e] ? 0.0 : 1.0;
  }
  EXPECT_EQ(design.chain_gradient(theta, only_fixed).norm(), 0.0);
}

TEST(DesignSpaceMask, RejectsAMaskOfTheWrongSizeOrSelectingNothing) {
  const TwoBoxes t = two_boxes();
  EXPECT_THROW(DesignSpace(t.stacked, DesignSpaceOptions{}, std::vector<char>(3, 1)), InputError);
  EXPECT_THROW(
      DesignSpace(t.stacked, DesignSpaceOptions{}, std::vector<char>(t.stacked.num_tets(), 0)),
      InputError);
  DesignSpace ok(t.stacked, DesignSpaceOptions{}, t.mask);
  EXPECT_THROW(ok.hold_fixed_elements(MaterialField::uniform(3, 1e10, 0.3, 2500)), InputError);
}

// Solid vertices (a driven body's driven vertices): every element touching one is held solid like
// a boundary element (alpha not designed, 1 at any theta); the rest of the interior stays designed.
TEST(DesignSpaceMask, ElementsOfSolidVerticesAreHeldSolid) {
  const TetMesh mesh = box_tet_mesh({0, 0, 0}, {1, 1, 1}, 4, 4, 4);
  const std::vector<char> boundary = boundary_elements(mesh);
  // An interior vertex: on no boundary element.
  std::vector<char> on_boundary(mesh.num_vertices(), 0);
  for (int e = 0; e < mesh.num_tets(); ++e) {
    if (boundary[e]) {
      for (int a = 0; a < 4; ++a) on_boundary[mesh.T(e, a)] = 1;
    }
  }
  const int v = static_cast<int>(std::find(on_boundary.begin(), on_boundary.end(), 0) - on_boundary.begin());
  ASSERT_LT(v, mesh.num_vertices());
  DesignSpaceOptions o;
  o.perturbation = 0.5;
  const DesignSpace plain(mesh, o);
  o.solid_vertices = {v};
  const DesignSpace held(mesh, o);
  int touching = 0;
  for (int e = 0; e < mesh.num_tets(); ++e) {
    bool touches = false;
    for (int a = 0; a < 4; ++a) touches = touches || mesh.T(e, a) == v;
    touching += touches;
    EXPECT_EQ(held.boundary()[e] != 0, boundary[e] != 0 || touches) << e;
  }
  ASSERT_GT(touching, 0);
  EXPECT_EQ(held.num_interior(), plain.num_interior() - touching);
  const MaterialField m = held.to_material(held.initial_theta(true));
  for (int e = 0; e < mesh.num_tets(); ++e) {
    for (int a = 0; a < 4; ++a) {
      if (mesh.T(e, a) == v) {
        EXPECT_EQ(m.alpha[e], 1.0) << e;
      }
    }
  }
  o.solid_vertices = {mesh.num_vertices()};
  EXPECT_THROW(DesignSpace(mesh, o), InputError);
}

}  // namespace
}  // namespace rbaa
