#include <gtest/gtest.h>

#include <cstdio>

#include "rbaa/error.hpp"
#include "rbaa/mesh/grid_mesh.hpp"
#include "rbaa/mesh/topology.hpp"
#include "rbaa/opt/occupancy.hpp"

namespace rbaa {
namespace {

constexpr int kN = 8;
int cell_of(int e) { return e / 6; }  // box_tet_mesh: six tets per cell, cells x-fastest
int cell_index(int i, int j, int k) { return i + kN * (j + kN * k); }

std::vector<char> occupied_flags(const Eigen::VectorXd& alpha) {
  std::vector<char> f(alpha.size());
  for (Eigen::Index e = 0; e < alpha.size(); ++e) f[e] = alpha[e] == 1.0;
  return f;
}

TEST(Occupancy, RoundingKeepsTheBoundaryAndUsesTheThreshold) {
  const TetMesh mesh = box_tet_mesh({0, 0, 0}, {1, 1, 1}, 3, 3, 3);
  const std::vector<char> boundary = boundary_elements(mesh);
  Eigen::VectorXd alpha = Eigen::VectorXd::LinSpaced(mesh.num_tets(), 1e-3, 0.999);
  const Eigen::VectorXd r = round_occupancy(alpha, boundary, 0.7);
  for (int e = 0; e < mesh.num_tets(); ++e) {
    EXPECT_EQ(r[e], (boundary[e] || alpha[e] >= 0.7) ? 1.0 : 0.0);
    if (boundary[e]) {
      EXPECT_EQ(r[e], 1.0);
    }
  }
  EXPECT_THROW(round_occupancy(alpha, boundary, 1.0), InputError);
  EXPECT_THROW(round_occupancy(alpha, boundary, 0.0), InputError);  // the range is open: (0, 1)
}

// Void inside, except the shell (`boundary`) and four solid one-cell islands.
Eigen::VectorXd shell_and_islands(const TetMesh& mesh, const std::vector<char>& boundary) {
  const std::vector<int> islands = {cell_index(3, 3, 3), cell_index(5, 2, 4), cell_index(2, 5, 5),
                                    cell_index(4, 4, 2)};
  Eigen::VectorXd alpha = Eigen::VectorXd::Zero(mesh.num_tets());
  for (int e = 0; e < mesh.num_tets(); ++e) {
    if (boundary[e]) alpha[e] = 1.0;
    for (int c : islands) {
      if (cell_of(e) == c) alpha[e] = 1.0;
    }
  }
  return alpha;
}

void expect_repaired(const TetMesh& mesh, const std::vector<char>& boundary, Eigen::VectorXd& alpha,
                     const ConnectivityReport& report, const Eigen::VectorXd& before) {
  EXPECT_EQ(report.components_after, 1);
  EXPECT_EQ(count_components(mesh, occupied_flags(alpha)), 1);
  int changed = 0;
  for (int e = 0; e < mesh.num_tets(); ++e) {
    if (before[e] == 1.0) {
      EXPECT_EQ(alpha[e], 1.0);  // nothing occupied is removed
    }
    changed += alpha[e] != before[e];
  }
  EXPECT_EQ(changed, report.elements_added);
  // Repairing a connected field changes nothing.
  const Eigen::VectorXd repaired = alpha;
  const ConnectivityReport again = repair_connectivity(mesh, boundary, alpha);
  EXPECT_EQ(again.components_before, 1);
  EXPECT_EQ(again.elements_added, 0);
  EXPECT_EQ(alpha, repaired);
}

TEST(Occupancy, IslandsAreJoinedToTheShell) {
  // Shell by vertex: every tet of the outer layer of cells, one connected component.
  const TetMesh mesh = box_tet_mesh({0, 0, 0}, {1, 1, 1}, kN, kN, kN);
  const std::vector<char> boundary = boundary_elements(mesh, true);
  ASSERT_EQ(count_components(mesh, boundary), 1);
  Eigen::VectorXd alpha = shell_and_islands(mesh, boundary);
  const Eigen::VectorXd before = alpha;
  EXPECT_EQ(count_components(mesh, occupied_flags(alpha)), 5);

  const ConnectivityReport report = repair_connectivity(mesh, boundary, alpha);
  std::printf("connectivity repair (vertex shell + 4 islands): %d components -> %d, %d elements "
              "(%.4g m^3) filled\n",
              report.components_before, report.components_after, report.elements_added,
              report.volume_added);
  EXPECT_EQ(report.components_before, 5);
  expect_repaired(mesh, boundary, alpha, report, before);
  // A tree, not a fill: every island is at most 2 cells from the shell, and a shortest path
  // crosses at most 6 tets per cell, so the 4 paths need at most 4 * 2 * 6 elements.
  EXPECT_GT(report.elements_added, 0);
  EXPECT_LE(report.elements_added, 4 * 2 * 6);
}

TEST(Occupancy, FragmentedFaceShellIsJoinedToo) {
  // Elements with a boundary face are not face-connected to each other on this grid (the two
  // boundary tets of a cell touch the next cell's boundary tets only through interior tets), so
  // the shell alone is many components; the repair joins all of them and the islands.
  const TetMesh mesh = box_tet_mesh({0, 0, 0}, {1, 1, 1}, kN, kN, kN);
  const std::vector<char> boundary = boundary_elements(mesh, false);
  const int shell_components = count_components(mesh, boundary);
  Eigen::VectorXd alpha = shell_and_islands(mesh, boundary);
  const Eigen::VectorXd before = alpha;
  const ConnectivityReport report = repair_connectivity(mesh, boundary, alpha);
  std::printf("connectivity repair (face shell in %d pieces + 4 islands): %d components -> %d, %d "
              "elements (%.4g m^3) filled\n",
              shell_components, report.components_before, report.components_after,
              report.elements_added, report.volume_added);
  EXPECT_GT(shell_components, 1);
  EXPECT_EQ(report.components_before, shell_components + 4);
  expect_repaired(mesh, boundary, alpha, report, before);
}

TEST(Occupancy, RepairRejectsUnroundedOrVoidBoundary) {
  const TetMesh mesh = box_tet_mesh({0, 0, 0}, {1, 1, 1}, 3, 3, 3);
  const std::vector<char> boundary = boundary_elements(mesh);
  Eigen::VectorXd alpha = Eigen::VectorXd::Constant(mesh.num_tets(), 0.6);
  EXPECT_THROW(repair_connectivity(mesh, boundary, alpha), InputError);
  alpha.setZero();
  EXPECT_THROW(repair_connectivity(mesh, boundary, alpha), InputError);
}

}  // namespace
}  // namespace rbaa
