#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "rbaa/error.hpp"
#include "rbaa/mesh/grid_mesh.hpp"
#include "rbaa/mesh/topology.hpp"

namespace rbaa {
namespace {

TEST(Topology, BoxBoundaryIsClosedAndOutward) {
  const TetMesh mesh = box_tet_mesh({0, 0, 0}, {2, 1, 1}, 2, 1, 1);
  const Faces F = boundary_faces(mesh);
  // Two cells: each square face of the box surface is two triangles; 10 squares.
  EXPECT_EQ(F.rows(), 20);
  // Divergence theorem: the outward surface encloses the mesh's volume.
  double enclosed = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = mesh.V.row(F(f, 0)), b = mesh.V.row(F(f, 1)), c = mesh.V.row(F(f, 2));
    enclosed += a.dot(b.cross(c)) / 6.0;
  }
  EXPECT_NEAR(enclosed, 2.0, 1e-12);
  EXPECT_EQ(boundary_vertices(mesh).size(), 12u);
}

TEST(Topology, AdjacencyIsSymmetric) {
  const TetMesh mesh = box_tet_mesh({0, 0, 0}, {1, 1, 1}, 2, 2, 2);
  const Tets adj = face_adjacency(mesh);
  int interior_faces = 0;
  for (int e = 0; e < mesh.num_tets(); ++e) {
    for (int k = 0; k < 4; ++k) {
      const int n = adj(e, k);
      if (n < 0) continue;
      ++interior_faces;
      EXPECT_TRUE((adj.row(n).array() == e).any());
    }
  }
  EXPECT_EQ(interior_faces + boundary_faces(mesh).rows(), 4 * mesh.num_tets());
}

TEST(Topology, BoundaryElementsByFaceAndByVertex) {
  const TetMesh mesh = box_tet_mesh({0, 0, 0}, {1, 1, 1}, 3, 3, 3);
  const auto by_face = boundary_elements(mesh, false);
  const auto by_vertex = boundary_elements(mesh, true);
  int nf = 0, nv = 0;
  for (int e = 0; e < mesh.num_tets(); ++e) {
    nf += by_face[e];
    nv += by_vertex[e];
    if (by_face[e]) {
      EXPECT_TRUE(by_vertex[e]);
    }
  }
  EXPECT_GT(nf, 0);
  EXPECT_GT(nv, nf);
  EXPECT_LT(nv, mesh.num_tets());  // the centre cell touches no boundary vertex
}

TEST(Topology, ComponentsOfASubset) {
  const TetMesh mesh = box_tet_mesh({0, 0, 0}, {3, 1, 1}, 3, 1, 1);
  EXPECT_EQ(count_components(mesh), 1);
  std::vector<char> flags(mesh.num_tets(), 0);
  for (int e = 0; e < 6; ++e) flags[e] = 1;         // first cell
  for (int e = 12; e < 18; ++e) flags[e] = 1;       // third cell
  EXPECT_EQ(count_components(mesh, flags), 2);
}

TEST(Topology, NonManifoldTetMeshIsRejected) {
  TetMesh mesh;
  mesh.V.resize(6, 3);
  mesh.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 1, 1, 1;
  mesh.T.resize(3, 4);
  mesh.T << 0, 1, 2, 3, 0, 2, 1, 4, 0, 1, 2, 5;  // face (0,1,2) used three times
  EXPECT_THROW(face_adjacency(mesh), InputError);
}

TEST(TetMesh, ValidationNamesTheFault) {
  TetMesh mesh = box_tet_mesh({0, 0, 0}, {1, 1, 1}, 1, 1, 1);
  EXPECT_NO_THROW(validate_tet_mesh(mesh, "box"));
  TetMesh inverted = mesh;
  std::swap(inverted.T(2, 0), inverted.T(2, 1));
  try {
    validate_tet_mesh(inverted, "inverted.msh");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("inverted.msh: tet 2 is inverted"), std::string::npos) << e.what();
  }
  TetMesh flat = mesh;
  flat.V.row(flat.T(0, 3)) = flat.V.row(flat.T(0, 0));  // collapse: zero volume
  EXPECT_THROW(validate_tet_mesh(flat, "flat.msh"), InputError);
  TetMesh out_of_range = mesh;
  out_of_range.T(0, 0) = 99;
  try {
    validate_tet_mesh(out_of_range, "bad.msh");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("vertex 99"), std::string::npos) << e.what();
  }
  // A tet given twice (its moments would count twice: m0 7/6 of the cube's) and a tet on the
  // same side of a face as its neighbour (the cube's tet 0 mirrored through one of its faces
  // would be the neighbour; through the face's plane but kept on its side it overlaps tet 0).
  TetMesh repeated = mesh;
  repeated.T.conservativeResize(mesh.num_tets() + 1, 4);
  repeated.T.row(mesh.num_tets()) = mesh.T.row(0);
  try {
    validate_tet_mesh(repeated, "repeated.ele");
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("repeated.ele: face ("), std::string::npos) << what;
    EXPECT_NE(what.find("has tets 0 and " + std::to_string(mesh.num_tets()) +
                        " on the same side: they overlap"),
              std::string::npos)
        << what;
  }
  TetMesh on_one_side;
  on_one_side.V.resize(5, 3);
  on_one_side.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0.2, 0.2, 2;
  on_one_side.T.resize(2, 4);
  on_one_side.T << 0, 1, 2, 3, 0, 1, 2, 4;  // both above the face (0, 1, 2)
  EXPECT_GT(tet_volumes(on_one_side).minCoeff(), 0);
  EXPECT_THROW(validate_tet_mesh(on_one_side, "overlap.msh"), InputError);
  on_one_side.V(4, 2) = -2;  // below it: neighbours
  on_one_side.T.row(1) << 0, 2, 1, 4;
  EXPECT_GT(tet_volumes(on_one_side).minCoeff(), 0);
  EXPECT_NO_THROW(validate_tet_mesh(on_one_side, "neighbours.msh"));
  // Three tets on one face.
  TetMesh three;
  three.V.resize(6, 3);
  three.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0.1, 0.1, 2;
  three.T.resize(3, 4);
  three.T << 0, 1, 2, 3, 0, 2, 1, 4, 0, 1, 2, 5;
  try {
    validate_tet_mesh(three, "three.msh");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("three.msh: face (0, 1, 2) is shared by 3 tetrahedra"),
              std::string::npos)
        << e.what();
  }
}

TEST(TetMesh, RestShapeInvertsEdgeMatrices) {
  const TetMesh mesh = box_tet_mesh({0, 0, 0}, {1, 2, 3}, 1, 1, 1);
  const RestShape rest = compute_rest_shape(mesh);
  EXPECT_NEAR(rest.volume.sum(), 6.0, 1e-12);
  for (int e = 0; e < mesh.num_tets(); ++e) {
    Eigen::Matrix3d Dm;
    for (int k = 0; k < 3; ++k) Dm.col(k) = (mesh.V.row(mesh.T(e, k + 1)) - mesh.V.row(mesh.T(e, 0))).transpose();
    EXPECT_LT((Dm * rest.Dm_inv[e] - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  }
}

}  // namespace
}  // namespace rbaa
