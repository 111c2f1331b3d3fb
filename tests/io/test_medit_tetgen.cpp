#include <gtest/gtest.h>

#include "io/io_test_support.hpp"
#include "rbaa/io/medit.hpp"
#include "rbaa/io/tetgen.hpp"

namespace rbaa {
namespace {

using test::input_error_message;
using test::ScratchDir;
using test::write_text;

TEST(Medit, RoundTripIsExact) {
  ScratchDir dir;
  const TetMesh mesh = test::make_jittered_cube(3, 11);
  write_medit(dir.file("cube.mesh"), mesh);
  const TetMesh back = read_medit(dir.file("cube.mesh"));
  EXPECT_TRUE(test::bit_equal(back.V, mesh.V));
  EXPECT_EQ(back.T, mesh.T);
}

TEST(Medit, ReadsFreeFormatWithCommentsAndSkippedSections) {
  ScratchDir dir;
  write_text(dir.file("hand.mesh"), R"(# written by hand
MeshVersionFormatted
1
Dimension 3
Vertices
6
0 0 0 1   1 0 0 1
0 1 0 1
0 0 1 1
5 5 5 0   # unused vertex, dropped
1 1 1 2
Edges 1
1 2 0
Triangles
2
1 2 3 1
2 3 4 1
Corners 1 1
tetrahedra
2
1 2 3 4 7
2 3 4 6 7
End
)");
  const TetMesh mesh = read_medit(dir.file("hand.mesh"));
  Vertices V(5, 3);
  V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1;
  EXPECT_EQ(mesh.V, V);
  Tets T(2, 4);
  T << 0, 1, 2, 3, 1, 2, 3, 4;
  EXPECT_EQ(mesh.T, T);
}

TEST(Medit, MalformedFilesGiveFileAndLine) {
  ScratchDir dir;
  const std::string head =
      "MeshVersionFormatted 2\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n";
  struct Case {
    const char* name;
    std::string text;
    const char* where;
    const char* expected;
  } cases[] = {
      {"truncated", head + "Tetrahedra\n1\n1 2 3\n", ":11:", "end of file"},
      {"index_out_of_range", head + "Tetrahedra\n1\n1 2 3 5 0\nEnd\n", ":11:", "vertex 5"},
      {"zero_index", head + "Tetrahedra\n1\n0 2 3 4 0\nEnd\n", ":11:", "start at 1"},
      {"non_numeric", head + "Tetrahedra\n1\n1 2 x 4 0\nEnd\n", ":11:", "'x'"},
      {"unknown_keyword", head + "Foo\n1\n", ":9:", "unknown keyword 'Foo'"},
      {"hexahedra", head + "Hexahedra\n0\n", ":9:", "not supported"},
      {"two_dimensional", "MeshVersionFormatted 2\nDimension 2\n", ":2:", "3-dimensional"},
      {"no_tetrahedra", head + "End\n", ":9:", "no Tetrahedra"},
      // Nothing may follow End; a skipped section's count is no promise (no overflow, no hang).
      {"text_after_end", head + "Tetrahedra\n1\n1 2 3 4 0\nEnd\ngarbage here 12\n", ":13:", "text after End"},
      {"huge_skipped_count", head + "Triangles 4611686018427387904\n", ":9:", "bad count"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = dir.file(std::string(c.name) + ".mesh");
    write_text(path, c.text);
    const std::string msg = input_error_message([&] { read_medit(path); });
    EXPECT_NE(msg.find(path + c.where), std::string::npos) << msg;
    EXPECT_NE(msg.find(c.expected), std::string::npos) << msg;
  }
}

TEST(Tetgen, RoundTripIsExactFromEitherFileOrTheBaseName) {
  ScratchDir dir;
  const TetMesh mesh = test::make_jittered_cube(3, 13);
  write_tetgen(dir.file("cube.1.node"), mesh);
  EXPECT_TRUE(std::filesystem::exists(dir.file("cube.1.ele")));
  for (const char* name : {"cube.1.node", "cube.1.ele", "cube.1"}) {
    SCOPED_TRACE(name);
    const TetMesh back = read_tetgen(dir.file(name));
    EXPECT_TRUE(test::bit_equal(back.V, mesh.V));
    EXPECT_EQ(back.T, mesh.T);
  }
}

TEST(Tetgen, DetectsZeroBasedIndicesAndIgnoresAttributesAndMarkers) {
  ScratchDir dir;
  write_text(dir.file("z.node"),
             "# zero based\n5 3 1 1\n0 0 0 0 9.5 1\n1 1 0 0 9.5 1\n2 0 1 0 9.5 0\n"
             "3 0 0 1 9.5 1\n4 1 1 1 9.5 1\n");
  write_text(dir.file("z.ele"), "2 4 1\n0 0 1 2 3 7\n1 1 2 3 4 7\n# end\n");
  const TetMesh mesh = read_tetgen(dir.file("z"));
  Tets T(2, 4);
  T << 0, 1, 2, 3, 1, 2, 3, 4;
  EXPECT_EQ(mesh.T, T);
  EXPECT_EQ(mesh.V.row(4), Eigen::RowVector3d(1, 1, 1));
}

TEST(Tetgen, FlipsAConsistentlyNegativeMeshAndKeepsCornersOfQuadraticTets) {
  ScratchDir dir;
  // 1-based; both tets negatively oriented; 10 nodes per tet, the mid-edge nodes (6..) dropped.
  std::string node = "7 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n6 0.5 0 0\n7 0 0.5 0\n";
  write_text(dir.file("q.node"), node);
  write_text(dir.file("q.ele"), "2 10\n1 1 2 4 3 6 6 6 6 6 6\n2 2 3 5 4 7 7 7 7 7 7\n");
  const TetMesh mesh = read_tetgen(dir.file("q.ele"));
  EXPECT_EQ(mesh.num_vertices(), 5);
  EXPECT_TRUE((tet_volumes(mesh).array() > 0).all());
  EXPECT_NO_THROW(validate_tet_mesh(mesh, "q"));
}

TEST(Tetgen, MalformedFilesGiveFileAndLine) {
  ScratchDir dir;
  const std::string node = "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n";
  struct Case {
    const char* name;
    std::string node;
    std::string ele;
    const char* where;
    const char* expected;
  } cases[] = {
      {"bad_first_index", "1 3 0 0\n5 0 0 0\n", "", ".node:2:", "must be 0 or 1"},
      {"gap_in_indices", "2 3 0 0\n1 0 0 0\n3 0 0 0\n", "", ".node:3:", "consecutive"},
      {"too_few_points", "3 3 0 0\n1 0 0 0\n", "", ".node:2:", "end of file"},
      {"too_many_points", "1 3 0 0\n1 0 0 0\n2 0 0 0\n", "", ".node:3:", "more points"},
      {"undeclared_attribute", "1 3 0 0\n1 0 0 0 7\n", "", ".node:2:", "unexpected '7'"},
      {"two_d", "1 2 0 0\n1 0 0\n", "", ".node:1:", "3D"},
      {"node_out_of_range", node, "1 4 0\n1 1 2 3 5\n", ".ele:2:", "node index 5"},
      {"too_few_tets", node, "2 4 0\n1 1 2 3 4\n", ".ele:2:", "end of file"},
      {"non_numeric", node, "1 4 0\n1 1 2 three 4\n", ".ele:2:", "'three'"},
      {"nodes_per_tet", node, "1 5 0\n1 1 2 3 4 1\n", ".ele:1:", "4 or 10"},
      // A header's count is no promise: 2e9 points or tets, one given, is a truncated file
      // (before, 48 GB and 32 GB were asked for first: std::bad_alloc, no file named).
      {"huge_point_count", "2000000000 3 0 0\n1 0 0 0\n", "", ".node:2:", "end of file"},
      {"huge_tet_count", node, "2000000000 4 0\n1 1 2 3 4\n", ".ele:2:", "end of file"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string base = dir.file(c.name);
    write_text(base + ".node", c.node);
    write_text(base + ".ele", c.ele);
    const std::string msg = input_error_message([&] { read_tetgen(base); });
    EXPECT_NE(msg.find(base + c.where), std::string::npos) << msg;
    EXPECT_NE(msg.find(c.expected), std::string::npos) << msg;
  }
}

TEST(Tetgen, MissingEleFileIsNamed) {
  ScratchDir dir;
  write_text(dir.file("lonely.node"), "1 3 0 0\n1 0 0 0\n");
  const std::string msg = input_error_message([&] { read_tetgen(dir.file("lonely.node")); });
  EXPECT_NE(msg.find("lonely.ele"), std::string::npos) << msg;
}

}  // namespace
}  // namespace rbaa
