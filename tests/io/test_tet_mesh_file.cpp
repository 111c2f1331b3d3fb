#include <gtest/gtest.h>

#include "io/io_test_support.hpp"
#include "rbaa/io/tet_mesh_file.hpp"

namespace rbaa {
namespace {

using test::input_error_message;
using test::ScratchDir;

TEST(TetMeshFile, EveryFormatRoundTripsThroughTheDispatcher) {
  ScratchDir dir;
  const TetMesh mesh = test::make_jittered_cube(2, 3);
  for (const char* name : {"a.msh", "a.mesh", "a.node", "b.ele"}) {
    SCOPED_TRACE(name);
    write_tet_mesh(dir.file(name), mesh);
    const TetMeshFile back = read_tet_mesh(dir.file(name));
    EXPECT_TRUE(test::bit_equal(back.mesh.V, mesh.V));
    EXPECT_EQ(back.mesh.T, mesh.T);
  }
  // TetGen's own naming: "mesh.1" stands for mesh.1.node + mesh.1.ele.
  write_tet_mesh(dir.file("t.1.node"), mesh);
  EXPECT_EQ(read_tet_mesh(dir.file("t.1")).mesh.T, mesh.T);
}

TEST(TetMeshFile, ElementDataTravelsThroughMshOnly) {
  ScratchDir dir;
  const TetMesh mesh = test::make_jittered_cube(1);
  const ElementData data = {{"alpha", Eigen::VectorXd::Constant(mesh.num_tets(), 0.5)}};
  write_tet_mesh(dir.file("d.msh"), mesh, data);
  EXPECT_EQ(read_tet_mesh(dir.file("d.msh")).element_data.at("alpha"), data.at("alpha"));
  const std::string msg =
      input_error_message([&] { write_tet_mesh(dir.file("d.mesh"), mesh, data); });
  EXPECT_NE(msg.find("d.mesh"), std::string::npos) << msg;
  EXPECT_NE(msg.find(".msh"), std::string::npos) << msg;
}

TEST(TetMeshFile, UnknownExtensionAndMissingFileNameTheFile) {
  ScratchDir dir;
  test::write_text(dir.file("mesh.stl"), "solid x\nendsolid x\n");
  std::string msg = input_error_message([&] { read_tet_mesh(dir.file("mesh.stl")); });
  EXPECT_NE(msg.find("mesh.stl"), std::string::npos) << msg;
  EXPECT_NE(msg.find("extension"), std::string::npos) << msg;

  msg = input_error_message([&] { read_tet_mesh(dir.file("absent.msh")); });
  EXPECT_NE(msg.find("absent.msh"), std::string::npos) << msg;
  EXPECT_NE(msg.find("cannot read"), std::string::npos) << msg;

  msg = input_error_message([&] { read_tet_mesh(dir.file("absent")); });
  EXPECT_NE(msg.find("absent"), std::string::npos) << msg;

  msg = input_error_message(
      [&] { write_tet_mesh(dir.file("out.vtk"), test::make_jittered_cube(1)); });
  EXPECT_NE(msg.find("out.vtk"), std::string::npos) << msg;

  msg = input_error_message([&] { read_tet_mesh(dir.path().string() + "/"); });
  EXPECT_NE(msg.find(dir.path().string()), std::string::npos) << msg;
}

TEST(TetMeshFile, DegenerateAndInvertedTetsAreRejectedWithTheFileNamed) {
  ScratchDir dir;
  TetMesh mesh = test::make_jittered_cube(1);
  std::swap(mesh.T(2, 0), mesh.T(2, 1));
  for (const char* name : {"inv.msh", "inv.mesh"}) {
    write_tet_mesh(dir.file(name), mesh);
    const std::string msg = input_error_message([&] { read_tet_mesh(dir.file(name)); });
    EXPECT_NE(msg.find(dir.file(name)), std::string::npos) << msg;
    EXPECT_NE(msg.find("inverted"), std::string::npos) << msg;
  }
  TetMesh flat = test::make_jittered_cube(1);
  flat.V.row(flat.T(0, 3)) = flat.V.row(flat.T(0, 0));
  write_tet_mesh(dir.file("flat.msh"), flat);
  const std::string msg = input_error_message([&] { read_tet_mesh(dir.file("flat.msh")); });
  EXPECT_NE(msg.find("flat.msh"), std::string::npos) << msg;
}

TEST(TetMeshFile, RemoveUnreferencedVerticesKeepsOrder) {
  TetMesh mesh;
  mesh.V.resize(6, 3);
  for (int i = 0; i < 6; ++i) mesh.V.row(i) = Eigen::RowVector3d::Constant(i);
  mesh.T.resize(1, 4);
  mesh.T << 5, 1, 3, 4;
  EXPECT_EQ(remove_unreferenced_vertices(mesh), 2);
  EXPECT_EQ(mesh.num_vertices(), 4);
  EXPECT_EQ(mesh.T, (Tets(1, 4) << 3, 0, 1, 2).finished());
  EXPECT_EQ(mesh.V(0, 0), 1.0);
  EXPECT_EQ(mesh.V(3, 0), 5.0);
}

}  // namespace
}  // namespace rbaa
