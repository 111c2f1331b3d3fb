// Broad phase: the BVH's candidates equal a brute-force test of every pair's swept boxes on random
// meshes, and every pair that actually comes within the inflation distance (at the start, the end
// or any sampled time of the step) is among them.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <set>
#include <utility>

#include "contact_checks.hpp"
#include "rbaa/contact/broad_phase.hpp"
#include "rbaa/contact/bvh.hpp"
#include "rbaa/contact/edge_edge.hpp"
#include "rbaa/contact/point_triangle.hpp"

namespace rbaa::contact {
namespace {

struct Mesh {
  Eigen::MatrixXd V0, V1;
  Eigen::MatrixXi F, E;
};

Eigen::MatrixXi unique_edges(const Eigen::MatrixXi& F) {
  std::set<std::pair<int, int>> edges;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      edges.insert({std::min(a, b), std::max(a, b)});
    }
  Eigen::MatrixXi E(edges.size(), 2);
  int i = 0;
  for (const auto& [a, b] : edges) E.row(i++) << a, b;
  return E;
}

// Two jittered height-field sheets (n x n vertices each) a little apart, one sliding over the
// other during the step: a mesh with shared edges and many near pairs, of varied triangle sizes.
Mesh two_sheets(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> u(-1, 1);
  Mesh m;
  const int nv = 2 * n * n;
  m.V0.resize(nv, 3);
  m.V1.resize(nv, 3);
  std::vector<Eigen::Vector3i> tris;
  for (int s = 0; s < 2; ++s) {
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const int v = s * n * n + i * n + j;
        // Cells shrink towards one corner so triangle sizes vary by a factor ~5.
        const double x = std::pow(double(i) / (n - 1), 1.5), y = std::pow(double(j) / (n - 1), 1.5);
        m.V0.row(v) << x + 0.002 * u(rng), y + 0.002 * u(rng), 0.02 * s + 0.005 * u(rng);
        m.V1.row(v) = m.V0.row(v) + Eigen::RowVector3d(s * 0.05, 0, -s * 0.015) +
                      0.003 * Eigen::RowVector3d(u(rng), u(rng), u(rng));
      }
    for (int i = 0; i + 1 < n; ++i)
      for (int j = 0; j + 1 < n; ++j) {
        const int a = s * n * n + i * n + j, b = a + 1, c = a + n, d = c + 1;
        tris.emplace_back(a, b, d);
        tris.emplace_back(a, d, c);
      }
  }
  m.F.resize(tris.size(), 3);
  for (std::size_t f = 0; f < tris.size(); ++f) m.F.row(f) = tris[f].transpose();
  m.E = unique_edges(m.F);
  return m;
}

// A soup of random triangles over random vertices with random motions: long, overlapping
// triangles whose boxes cover much of the domain, the hard case for any box hierarchy.
Mesh random_soup(std::mt19937& rng, int nv, int nf) {
  std::uniform_int_distribution<int> pick(0, nv - 1);
  Mesh m;
  m.V0.resize(nv, 3);
  m.V1.resize(nv, 3);
  for (int v = 0; v < nv; ++v) {
    m.V0.row(v) = test::random_point(rng).transpose();
    m.V1.row(v) = m.V0.row(v) + 0.05 * test::random_point(rng).transpose();
  }
  m.F.resize(nf, 3);
  for (int f = 0; f < nf; ++f) {
    int a = pick(rng), b = pick(rng), c = pick(rng);
    while (b == a) b = pick(rng);
    while (c == a || c == b) c = pick(rng);
    m.F.row(f) << a, b, c;
  }
  m.E = unique_edges(m.F);
  return m;
}

Aabb box_of(const Mesh& m, std::initializer_list<int> vertices, double r) {
  Aabb box;
  for (int v : vertices) {
    box.extend(Eigen::Vector3d(m.V0.row(v).transpose()));
    box.extend(Eigen::Vector3d(m.V1.row(v).transpose()));
  }
  box.inflate(r / 2);
  return box;
}

void expect_matches_brute_force(const Mesh& m, double inflation) {
  const auto vt = vertex_triangle_candidates(m.V0, m.V1, m.F, inflation);
  std::vector<VertexTriangleCandidate> vt_brute;
  for (int v = 0; v < m.V0.rows(); ++v)
    for (int f = 0; f < m.F.rows(); ++f) {
      if (v == m.F(f, 0) || v == m.F(f, 1) || v == m.F(f, 2)) continue;
      if (box_of(m, {v}, inflation)
              .overlaps(box_of(m, {m.F(f, 0), m.F(f, 1), m.F(f, 2)}, inflation)))
        vt_brute.push_back({v, f});
    }
  EXPECT_EQ(vt, vt_brute);

  const auto ee = edge_edge_candidates(m.V0, m.V1, m.E, inflation);
  std::vector<EdgeEdgeCandidate> ee_brute;
  for (int a = 0; a < m.E.rows(); ++a)
    for (int b = a + 1; b < m.E.rows(); ++b) {
      if (m.E(a, 0) == m.E(b, 0) || m.E(a, 0) == m.E(b, 1) || m.E(a, 1) == m.E(b, 0) ||
          m.E(a, 1) == m.E(b, 1))
        continue;
      if (box_of(m, {m.E(a, 0), m.E(a, 1)}, inflation)
              .overlaps(box_of(m, {m.E(b, 0), m.E(b, 1)}, inflation)))
        ee_brute.push_back({a, b});
    }
  EXPECT_EQ(ee, ee_brute);
  std::printf(
      "%lld vertices, %lld triangles, %lld edges: %zu vertex-triangle and %zu edge-edge "
      "candidates\n",
      (long long)m.V0.rows(), (long long)m.F.rows(), (long long)m.E.rows(), vt.size(), ee.size());
}

TEST(ContactBroadPhase, MatchesBruteForce) {
  std::mt19937 rng(51);
  expect_matches_brute_force(two_sheets(rng, 16), 0.01);
  expect_matches_brute_force(two_sheets(rng, 12), 0.0);
  expect_matches_brute_force(random_soup(rng, 300, 200), 0.02);
  // Static (V1 = V0): plain inflated boxes.
  Mesh m = random_soup(rng, 200, 150);
  m.V1 = m.V0;
  expect_matches_brute_force(m, 0.05);
}

// The candidates are conservative: every pair closer than the inflation at t = 0, 1 or any of 20
// intermediate times is reported (the exact distance, not boxes).
TEST(ContactBroadPhase, ReportsEveryPairThatComesClose) {
  std::mt19937 rng(52);
  const Mesh m = two_sheets(rng, 14);
  const double inflation = 0.015;
  const auto vt = vertex_triangle_candidates(m.V0, m.V1, m.F, inflation);
  const auto ee = edge_edge_candidates(m.V0, m.V1, m.E, inflation);
  const std::set<std::pair<int, int>> vt_set = [&] {
    std::set<std::pair<int, int>> s;
    for (const auto& c : vt) s.insert({c.vertex, c.triangle});
    return s;
  }();
  const std::set<std::pair<int, int>> ee_set = [&] {
    std::set<std::pair<int, int>> s;
    for (const auto& c : ee) s.insert({c.edge_a, c.edge_b});
    return s;
  }();
  int close_vt = 0, close_ee = 0;
  for (int k = 0; k <= 20; ++k) {
    const double t = k / 20.0;
    const Eigen::MatrixXd V = (1 - t) * m.V0 + t * m.V1;
    const auto x = [&](int v) -> Eigen::Vector3d { return V.row(v).transpose(); };
    for (int v = 0; v < V.rows(); ++v)
      for (int f = 0; f < m.F.rows(); ++f) {
        if (v == m.F(f, 0) || v == m.F(f, 1) || v == m.F(f, 2)) continue;
        if (point_triangle_distance(x(v), x(m.F(f, 0)), x(m.F(f, 1)), x(m.F(f, 2))) <
            inflation * inflation) {
          ++close_vt;
          EXPECT_TRUE(vt_set.count({v, f})) << v << " " << f << " at t = " << t;
        }
      }
    for (int a = 0; a < m.E.rows(); ++a)
      for (int b = a + 1; b < m.E.rows(); ++b) {
        if (m.E(a, 0) == m.E(b, 0) || m.E(a, 0) == m.E(b, 1) || m.E(a, 1) == m.E(b, 0) ||
            m.E(a, 1) == m.E(b, 1))
          continue;
        if (edge_edge_distance(x(m.E(a, 0)), x(m.E(a, 1)), x(m.E(b, 0)), x(m.E(b, 1))) <
            inflation * inflation) {
          ++close_ee;
          EXPECT_TRUE(ee_set.count({a, b})) << a << " " << b << " at t = " << t;
        }
      }
  }
  EXPECT_GT(close_vt, 100);
  EXPECT_GT(close_ee, 100);
}

// Groups drop exactly the pairs within one group: here the two sheets are two bodies. A third
// grouping (alternating rows) checks pairs spread over several groups.
TEST(ContactBroadPhase, GroupsDropPairsWithinAGroup) {
  std::mt19937 rng(54);
  const int n = 10;
  const Mesh m = two_sheets(rng, n);
  for (int grouping = 0; grouping < 2; ++grouping) {
    std::vector<int> groups(m.V0.rows());
    for (int v = 0; v < m.V0.rows(); ++v) groups[v] = grouping == 0 ? v / (n * n) : (v / n) % 3;
    const auto vt_all = vertex_triangle_candidates(m.V0, m.V1, m.F, 0.01);
    const auto vt = vertex_triangle_candidates(m.V0, m.V1, m.F, 0.01, groups);
    std::vector<VertexTriangleCandidate> vt_expected;
    for (const auto& c : vt_all)
      if (groups[c.vertex] != groups[m.F(c.triangle, 0)]) vt_expected.push_back(c);
    EXPECT_EQ(vt, vt_expected);
    EXPECT_LT(vt.size(), vt_all.size());
    EXPECT_FALSE(vt.empty());
    const auto ee_all = edge_edge_candidates(m.V0, m.V1, m.E, 0.01);
    const auto ee = edge_edge_candidates(m.V0, m.V1, m.E, 0.01, groups);
    std::vector<EdgeEdgeCandidate> ee_expected;
    for (const auto& c : ee_all)
      if (groups[m.E(c.edge_a, 0)] != groups[m.E(c.edge_b, 0)]) ee_expected.push_back(c);
    EXPECT_EQ(ee, ee_expected);
    EXPECT_FALSE(ee.empty());
  }
  EXPECT_THROW(vertex_triangle_candidates(m.V0, m.V1, m.F, 0.01, std::vector<int>(3, 0)),
               std::invalid_argument);
}

// The simulator's stacked coordinates q = (x0, y0, z0, x1, ...) map onto row-major positions.
TEST(ContactBroadPhase, TakesStackedCoordinates) {
  std::mt19937 rng(55);
  const Mesh m = two_sheets(rng, 8);
  const Positions P0 = m.V0, P1 = m.V1;
  const Eigen::VectorXd q0 = Eigen::Map<const Eigen::VectorXd>(P0.data(), P0.size());
  const Eigen::VectorXd q1 = Eigen::Map<const Eigen::VectorXd>(P1.data(), P1.size());
  const Eigen::Map<const Positions> V0(q0.data(), q0.size() / 3, 3),
      V1(q1.data(), q1.size() / 3, 3);
  EXPECT_EQ(vertex_triangle_candidates(V0, V1, m.F, 0.01),
            vertex_triangle_candidates(m.V0, m.V1, m.F, 0.01));
  EXPECT_EQ(edge_edge_candidates(V0, V1, m.E, 0.01), edge_edge_candidates(m.V0, m.V1, m.E, 0.01));
  EXPECT_EQ(q0[3], m.V0(1, 0));
}

TEST(ContactBroadPhase, BvhQueryVisitsEachOverlapOnce) {
  std::mt19937 rng(53);
  std::vector<Aabb> boxes(1000);
  for (auto& b : boxes) {
    b.extend(test::random_point(rng));
    b.extend(b.min + 0.1 * test::random_point(rng).cwiseAbs());
  }
  const Bvh bvh(boxes);
  for (int q = 0; q < 100; ++q) {
    Aabb query;
    query.extend(test::random_point(rng));
    query.inflate(0.1);
    std::vector<int> found;
    bvh.query(query, [&](int i) { found.push_back(i); });
    std::sort(found.begin(), found.end());
    std::vector<int> expected;
    for (int i = 0; i < 1000; ++i)
      if (boxes[i].overlaps(query)) expected.push_back(i);
    EXPECT_EQ(found, expected);
  }
  EXPECT_TRUE(Bvh().empty());
  int visits = 0;
  Bvh().query(Aabb(), [&](int) { ++visits; });
  EXPECT_EQ(visits, 0);
}

}  // namespace
}  // namespace rbaa::contact
