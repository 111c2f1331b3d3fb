#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <cstdio>
#include <random>

#include "rbaa/error.hpp"
#include "rbaa/geometry/laplacian.hpp"
#include "rbaa/geometry/smoothing.hpp"
#include "rbaa/mesh/grid_mesh.hpp"
#include "rbaa/mesh/topology.hpp"

namespace rbaa {
namespace {

constexpr int kNx = 6, kNy = 5, kNz = 4;

// A graded box: cell widths grow quadratically along every axis (the first cell is 11 times
// thinner than the last along x), so element volumes vary by more than two orders of magnitude.
TetMesh graded_mesh() {
  TetMesh mesh = box_tet_mesh({0, 0, 0}, {1, 1, 1}, kNx, kNy, kNz);
  const Eigen::Vector3d size(1.2, 0.9, 0.7);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    for (int c = 0; c < 3; ++c) mesh.V(v, c) = size[c] * mesh.V(v, c) * mesh.V(v, c);
  }
  return mesh;
}

// box_tet_mesh numbers the six tets of cell (i, j, k) from 6 (i + nx (j + ny k)).
Eigen::VectorXd checkerboard(const TetMesh& mesh) {
  Eigen::VectorXd f(mesh.num_tets());
  for (int e = 0; e < mesh.num_tets(); ++e) {
    const int cell = e / 6, i = cell % kNx, j = (cell / kNx) % kNy, k = cell / (kNx * kNy);
    f[e] = ((i + j + k) % 2 == 0) ? 1.0 : -1.0;
  }
  return f;
}

double a_norm(const Eigen::VectorXd& f, const Eigen::VectorXd& A) {
  return std::sqrt(f.cwiseProduct(f).dot(A));
}

// Removes the A-weighted mean (the constant mode, which smoothing keeps).
Eigen::VectorXd zero_mean(Eigen::VectorXd f, const Eigen::VectorXd& A) {
  f.array() -= f.dot(A) / A.sum();
  return f;
}

TEST(Laplacian, MatchesTheCotangentFormulaOnOneTet) {
  TetMesh tet;
  tet.V.resize(4, 3);
  tet.V << 0.1, 0.0, 0.0,  //
      1.3, 0.2, 0.1,       //
      0.3, 0.9, -0.1,      //
      0.2, 0.4, 1.1;
  tet.T.resize(1, 4);
  tet.T << 0, 1, 2, 3;
  ASSERT_GT(tet_volumes(tet)[0], 0.0);
  const Eigen::MatrixXd L = Eigen::MatrixXd(cotangent_laplacian(tet));
  auto p = [&](int i) { return Eigen::Vector3d(tet.V.row(i).transpose()); };
  // libigl: L_ij = l_kl cot(theta_kl) / 6, theta_kl the dihedral angle at the opposite edge kl.
  for (int i = 0; i < 4; ++i) {
    for (int j = i + 1; j < 4; ++j) {
      int k = -1, l = -1;
      for (int m = 0; m < 4; ++m) {
        if (m == i || m == j) continue;
        (k < 0 ? k : l) = m;
      }
      const Eigen::Vector3d edge = p(l) - p(k);
      // Face normals of the faces (k, l, i) and (k, l, j), their angle is the dihedral angle.
      const Eigen::Vector3d ni = edge.cross(p(i) - p(k)), nj = edge.cross(p(j) - p(k));
      const double cos_t = ni.dot(nj) / (ni.norm() * nj.norm());
      const double theta = std::acos(cos_t);
      const double expected = edge.norm() / std::tan(theta) / 6.0;
      EXPECT_NEAR(L(i, j), expected, 1e-13) << i << j;
      EXPECT_DOUBLE_EQ(L(i, j), L(j, i));
    }
    EXPECT_NEAR(L.row(i).sum(), 0.0, 1e-14);
    EXPECT_LT(L(i, i), 0.0);
  }
}

TEST(Laplacian, NegativeSemiDefiniteAndLinearPrecision) {
  const TetMesh mesh = graded_mesh();
  const Eigen::SparseMatrix<double> L = cotangent_laplacian(mesh);
  const Eigen::MatrixXd D(L);
  EXPECT_LT((D - D.transpose()).cwiseAbs().maxCoeff(), 1e-15 * D.cwiseAbs().maxCoeff());
  const Eigen::VectorXd eig = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(D).eigenvalues();
  EXPECT_LT(eig.maxCoeff(), 1e-12 * D.cwiseAbs().maxCoeff());
  // Exactly one zero eigenvalue (connected mesh): the second largest is clearly negative.
  EXPECT_LT(eig[eig.size() - 2], -1e-6 * D.cwiseAbs().maxCoeff());
  // Linear functions are harmonic at interior vertices.
  const std::vector<int> bv = boundary_vertices(mesh);
  std::vector<char> on(mesh.num_vertices(), 0);
  for (int v : bv) on[v] = 1;
  for (int c = 0; c < 3; ++c) {
    const Eigen::VectorXd Lx = L * mesh.V.col(c);
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      if (!on[v]) {
        EXPECT_NEAR(Lx[v], 0.0, 1e-13) << "vertex " << v;
      }
    }
  }
}

TEST(Laplacian, MeanEdgeLengthCountsEveryDistinctEdgeOnce) {
  // Two tets on the face (0, 1, 2): 9 distinct edges, the face's 3 shared. Lengths 1, 2, 3 on
  // the axes, sqrt 5, sqrt 10, sqrt 13 across, and apex 4 at (0, 0, -4): 4, sqrt 17, sqrt 20.
  TetMesh mesh;
  mesh.V.resize(5, 3);
  mesh.V << 0, 0, 0,  //
      1, 0, 0,        //
      0, 2, 0,        //
      0, 0, 3,        //
      0, 0, -4;
  mesh.T.resize(2, 4);
  mesh.T << 0, 1, 2, 3,  //
      0, 2, 1, 4;
  const double sum = 1 + 2 + 3 + std::sqrt(5.0) + std::sqrt(10.0) + std::sqrt(13.0) + 4 +
                     std::sqrt(17.0) + std::sqrt(20.0);
  EXPECT_NEAR(mean_edge_length(mesh), sum / 9, 1e-15);
  EXPECT_EQ(mean_edge_length(TetMesh{}), 0.0);
}

TEST(Smoothing, BarycentricSubdivisionKeepsVolumeAndOrientation) {
  const TetMesh mesh = graded_mesh();
  const TetMesh sub = false_barycentric_subdivision(mesh);
  ASSERT_EQ(sub.num_vertices(), mesh.num_vertices() + mesh.num_tets());
  ASSERT_EQ(sub.num_tets(), 4 * mesh.num_tets());
  const Eigen::VectorXd v = tet_volumes(mesh), vs = tet_volumes(sub);
  for (int e = 0; e < mesh.num_tets(); ++e) {
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(vs[4 * e + k], v[e] / 4, 1e-15);
  }
}

TEST(Smoothing, InvariantsOnAGradedMesh) {
  const TetMesh mesh = graded_mesh();
  const GradientSmoother S(mesh, 1.0);
  const Eigen::VectorXd& A = S.volumes();
  std::printf("graded mesh: %d tets, volumes %.3g .. %.3g m^3, gamma = %.4g m^2\n",
              mesh.num_tets(), A.minCoeff(), A.maxCoeff(), S.gamma());
  ASSERT_GT(A.maxCoeff() / A.minCoeff(), 100.0);

  // A 1 -> 1.
  const Eigen::VectorXd one = S.apply(A);
  const double err_one = (one.array() - 1.0).abs().maxCoeff();
  std::printf("N K^-1 N^T (A 1) - 1: max %.2e\n", err_one);
  EXPECT_LT(err_one, 1e-12);

  // sum(A g_smooth) = sum(g) for a random gradient.
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal;
  Eigen::VectorXd g(mesh.num_tets());
  for (int e = 0; e < g.size(); ++e) g[e] = normal(rng) * A[e] + 0.3 * A[e];
  const Eigen::VectorXd gs = S.apply(g);
  const double err_sum = std::abs(A.dot(gs) - g.sum()) / g.cwiseAbs().sum();
  std::printf("sum(A g_smooth) - sum(g): relative %.2e\n", err_sum);
  EXPECT_LT(err_sum, 1e-13);
  // ... and smoothing did change the gradient.
  EXPECT_GT((gs - g.cwiseQuotient(A)).norm(), 0.1 * g.cwiseQuotient(A).norm());

  // Symmetric and positive definite: x^T S y = y^T S x, x^T S x > 0 on random vectors.
  double worst_sym = 0.0, min_rayleigh = 1e300;
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::VectorXd x(g.size()), y(g.size());
    for (int e = 0; e < g.size(); ++e) {
      x[e] = normal(rng);
      y[e] = normal(rng);
    }
    const Eigen::VectorXd Sx = S.apply(x), Sy = S.apply(y);
    worst_sym = std::max(worst_sym, std::abs(x.dot(Sy) - y.dot(Sx)) / (x.norm() * Sy.norm()));
    min_rayleigh = std::min(min_rayleigh, x.dot(Sx) / x.squaredNorm());
  }
  std::printf("symmetry |x^T S y - y^T S x| / (|x| |S y|): max %.2e; min x^T S x / x^T x %.3e\n",
              worst_sym, min_rayleigh);
  EXPECT_LT(worst_sym, 1e-13);
  EXPECT_GT(min_rayleigh, 0.0);

  // The paper's N K^-1 N^T A is not symmetric on this graded mesh (SPEC section 4), so the
  // symmetry check above can tell the two apart.
  Eigen::VectorXd x(g.size()), y(g.size());
  for (int e = 0; e < g.size(); ++e) {
    x[e] = normal(rng);
    y[e] = normal(rng);
  }
  const double paper_asym = std::abs(x.dot(S.apply(A.cwiseProduct(y))) - y.dot(S.apply(A.cwiseProduct(x)))) /
                            (x.norm() * S.apply(A.cwiseProduct(y)).norm());
  std::printf("the paper's N K^-1 N^T A: relative asymmetry %.2e\n", paper_asym);
  EXPECT_GT(paper_asym, 1e-3);
}

TEST(Smoothing, LimitsInGamma) {
  const TetMesh mesh = graded_mesh();
  std::mt19937_64 rng(9);
  std::normal_distribution<double> normal;
  const Eigen::VectorXd A = tet_volumes(mesh);
  Eigen::VectorXd g(mesh.num_tets());
  for (int e = 0; e < g.size(); ++e) g[e] = A[e] * (normal(rng) + 0.5);
  const Eigen::VectorXd f = g.cwiseQuotient(A);

  // gamma -> 0: A^-1 g, with an error proportional to gamma (about 300 gamma here: gamma is
  // relative to the mean edge length squared, and the smallest cells are 11 times thinner).
  double previous = 0.0;
  for (double gamma : {1e-5, 1e-7, 1e-9, 1e-11}) {
    const double err = (GradientSmoother(mesh, gamma).apply(g) - f).norm() / f.norm();
    std::printf("gamma = %.0e: |S g - A^-1 g| / |A^-1 g| = %.2e\n", gamma, err);
    if (previous > 0) {
      EXPECT_LT(err, 0.02 * previous);
    }
    previous = err;
  }
  EXPECT_LT(previous, 1e-7);

  // gamma -> infinity: the constant sum(g) / sum(A), error proportional to 1 / gamma.
  const double c = g.sum() / A.sum();
  previous = 0.0;
  for (double gamma : {1e3, 1e5, 1e7}) {
    const Eigen::VectorXd s = GradientSmoother(mesh, gamma).apply(g);
    const double err = (s.array() - c).abs().maxCoeff() / std::abs(c);
    std::printf("gamma = %.0e: max |S g - sum(g)/sum(A)| / |sum(g)/sum(A)| = %.2e\n", gamma, err);
    if (previous > 0) {
      EXPECT_LT(err, 0.02 * previous);
    }
    previous = err;
  }
  EXPECT_LT(previous, 1e-5);
}

TEST(Smoothing, CheckerboardIsDampedMoreAsGammaGrows) {
  const TetMesh mesh = graded_mesh();
  const Eigen::VectorXd A = tet_volumes(mesh);
  const Eigen::VectorXd board = zero_mean(checkerboard(mesh), A);
  Eigen::VectorXd smooth_field(mesh.num_tets());
  for (int e = 0; e < mesh.num_tets(); ++e) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int k = 0; k < 4; ++k) c += mesh.V.row(mesh.T(e, k)).transpose() / 4;
    smooth_field[e] = c.x() / 1.2;
  }
  smooth_field = zero_mean(smooth_field, A);

  // Damping factor of a field f (per unit volume): |S (A f)|_A / |f|_A, 1 without smoothing.
  auto damping = [&](const GradientSmoother& S, const Eigen::VectorXd& f) {
    return a_norm(S.apply(A.cwiseProduct(f)), A) / a_norm(f, A);
  };
  double previous = 1.0;
  for (double gamma : {0.01, 0.1, 1.0, 10.0, 100.0}) {
    const GradientSmoother S(mesh, gamma);
    const double db = damping(S, board), ds = damping(S, smooth_field);
    std::printf("gamma = %6.2f (relative): checkerboard damped to %.4f, linear field to %.4f\n",
                gamma, db, ds);
    EXPECT_LT(db, previous);
    EXPECT_LT(db, ds);  // a low-pass filter: the alternating field loses more
    previous = db;
    if (gamma == 1.0) {
      std::printf("checkerboard damping factor at the default gamma = 1: %.4f\n", db);
      EXPECT_LT(db, 0.5);
      EXPECT_GT(ds, 0.5);
    }
  }
}

TEST(Smoothing, InteriorScatterAndGather) {
  const TetMesh mesh = graded_mesh();
  const GradientSmoother S(mesh, 1.0);
  const std::vector<char> boundary = boundary_elements(mesh, false);
  std::vector<int> interior;
  for (int e = 0; e < mesh.num_tets(); ++e) {
    if (!boundary[e]) interior.push_back(e);
  }
  ASSERT_FALSE(interior.empty());
  Eigen::VectorXd g = Eigen::VectorXd::LinSpaced(static_cast<int>(interior.size()), -1, 2);
  Eigen::VectorXd full = Eigen::VectorXd::Zero(mesh.num_tets());
  for (size_t i = 0; i < interior.size(); ++i) full[interior[i]] = g[i];
  const Eigen::VectorXd expected_full = S.apply(full);
  const Eigen::VectorXd got = S.apply_interior(interior, g);
  for (size_t i = 0; i < interior.size(); ++i) EXPECT_EQ(got[i], expected_full[interior[i]]);
  EXPECT_THROW(S.apply_interior(interior, Eigen::VectorXd::Zero(3)), InputError);
  EXPECT_THROW(GradientSmoother(mesh, 0.0), InputError);
}

}  // namespace
}  // namespace rbaa
