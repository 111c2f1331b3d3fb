#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

#include "io/io_test_support.hpp"
#include "rbaa/io/msh.hpp"
#include "rbaa/io/tet_mesh_file.hpp"

namespace rbaa {
namespace {

using test::input_error_message;
using test::ScratchDir;
using test::write_text;

class MshRoundTrip : public ::testing::TestWithParam<MshVersion> {};

TEST_P(MshRoundTrip, CoordinatesAndConnectivityAreExact) {
  ScratchDir dir;
  const TetMesh mesh = test::make_jittered_cube(3);
  ASSERT_NO_THROW(validate_tet_mesh(mesh, "generated"));
  const std::string path = dir.file("cube.msh");
  write_msh(path, mesh, {}, GetParam());
  const TetMeshFile back = read_msh(path);
  EXPECT_TRUE(test::bit_equal(back.mesh.V, mesh.V));
  EXPECT_EQ(back.mesh.T, mesh.T);
  EXPECT_TRUE(back.element_data.empty());
}

TEST_P(MshRoundTrip, ElementDataIsExactAndOrderedLikeTheTets) {
  ScratchDir dir;
  const TetMesh mesh = test::make_jittered_cube(2);
  const int nt = mesh.num_tets();
  ElementData data;
  data["Y"] = Eigen::VectorXd::LinSpaced(nt, 2.5e9, 6.5e11);
  data["nu"] = Eigen::VectorXd::Random(nt) * (1.0 / 3.0);
  Eigen::VectorXd odd = Eigen::VectorXd::Constant(nt, 1.0 / 7.0);
  odd[0] = -0.0;
  odd[1] = std::numeric_limits<double>::denorm_min();
  odd[2] = std::numeric_limits<double>::max();
  odd[3] = -std::numeric_limits<double>::min();
  data["name with spaces"] = odd;
  const std::string path = dir.file("data.msh");
  write_msh(path, mesh, data, GetParam());
  const TetMeshFile back = read_msh(path);
  ASSERT_EQ(back.element_data.size(), data.size());
  for (const auto& [name, values] : data) {
    ASSERT_TRUE(back.element_data.count(name)) << name;
    EXPECT_TRUE(test::bit_equal(back.element_data.at(name), values)) << name;
  }
}

INSTANTIATE_TEST_SUITE_P(Versions, MshRoundTrip,
                         ::testing::Values(MshVersion::kV22, MshVersion::kV41),
                         [](const auto& info) {
                           return info.param == MshVersion::kV22 ? "v22" : "v41";
                         });

TEST(Msh, WriterDefaultsToVersion41) {
  ScratchDir dir;
  write_msh(dir.file("a.msh"), test::make_jittered_cube(1));
  EXPECT_NE(test::read_text(dir.file("a.msh")).find("4.1 0 8"), std::string::npos);
}

TEST(Msh, WriterRefusesElementDataOfTheWrongLength) {
  ScratchDir dir;
  const TetMesh mesh = test::make_jittered_cube(1);
  const std::string msg = input_error_message([&] {
    write_msh(dir.file("bad.msh"), mesh, {{"Y", Eigen::VectorXd::Ones(mesh.num_tets() + 1)}});
  });
  EXPECT_NE(msg.find("bad.msh"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'Y'"), std::string::npos) << msg;
  EXPECT_FALSE(std::filesystem::exists(dir.file("bad.msh")));
}

// Two tets sharing a face; node tags are scattered, node 50 belongs to no tet, and a triangle,
// a line and a point sit among the elements.
const char* const kMsh22 = R"($MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
1
3 1 "solid"
$EndPhysicalNames
$Nodes
6
10 0 0 0
20 1 0 0
35 0 1 0
50 9 9 9
7 0 0 1
99 1 1 1
$EndNodes
$Elements
5
3 15 2 0 1 10
8 1 2 0 1 10 20
100 4 2 1 1 10 20 35 7
4 2 2 0 1 10 20 35
101 4 2 1 1 20 35 7 99
$EndElements
$ElementData
1
"rho"
1
0.0
3
0
1
3
101 2000.5
100 1000.25
4 77
$EndElementData
)";

const char* const kMsh41 = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$Entities
1 0 1 1
1 0 0 0 0
1 0 0 0 1 1 0 0 0
1 0 0 0 1 1 1 0 1 1
$EndEntities
$Nodes
3 6 7 99
0 1 0 1
10
0 0 0
2 1 1 2
20
35
1 0 0 0.5 0.5
0 1 0 0.25 0.75
3 1 0 3
50
7
99
9 9 9
0 0 1
1 1 1
$EndNodes
$Elements
3 4 4 101
0 1 15 1
3 10
2 1 2 1
4 10 20 35
3 1 4 2
100 10 20 35 7
101 20 35 7 99
$EndElements
$ElementData
1
"rho"
1
0
3
0
1
2
100 1000.25
101 2000.5
$EndElementData
)";

void expect_two_tets(const TetMeshFile& file) {
  // File order of the nodes the tets use: 10, 20, 35, 7, 99 (50 is dropped).
  Vertices V(5, 3);
  V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1;
  EXPECT_EQ(file.mesh.V, V);
  Tets T(2, 4);
  T << 0, 1, 2, 3, 1, 2, 3, 4;
  EXPECT_EQ(file.mesh.T, T);
  ASSERT_EQ(file.element_data.count("rho"), 1u);
  EXPECT_EQ(file.element_data.at("rho"), Eigen::Vector2d(1000.25, 2000.5));
}

TEST(Msh, ReadsHandWrittenVersion22) {
  ScratchDir dir;
  write_text(dir.file("hand.msh"), kMsh22);
  expect_two_tets(read_msh(dir.file("hand.msh")));
}

TEST(Msh, ReadsHandWrittenVersion41WithParametricNodes) {
  ScratchDir dir;
  write_text(dir.file("hand.msh"), kMsh41);
  expect_two_tets(read_msh(dir.file("hand.msh")));
}

TEST(Msh, ReadsWindowsLineEndings) {
  ScratchDir dir;
  std::string crlf;
  for (char c : std::string(kMsh41)) {
    if (c == '\n') crlf += '\r';
    crlf += c;
  }
  write_text(dir.file("crlf.msh"), crlf);
  expect_two_tets(read_msh(dir.file("crlf.msh")));
}

// A small valid 2.2 file, lines numbered for the malformed cases below.
const char* const kValid22 =
    "$MeshFormat\n"        // 1
    "2.2 0 8\n"            // 2
    "$EndMeshFormat\n"     // 3
    "$Nodes\n"             // 4
    "5\n"                  // 5
    "1 0 0 0\n"            // 6
    "2 1 0 0\n"            // 7
    "3 0 1 0\n"            // 8
    "4 0 0 1\n"            // 9
    "5 1 1 1\n"            // 10
    "$EndNodes\n"          // 11
    "$Elements\n"          // 12
    "2\n"                  // 13
    "1 4 2 1 1 1 2 3 4\n"  // 14
    "2 4 2 1 1 2 3 4 5\n"  // 15
    "$EndElements\n"       // 16
    "$ElementData\n"       // 17
    "1\n"                  // 18
    "\"Y\"\n"              // 19
    "1\n"                  // 20
    "0\n"                  // 21
    "3\n"                  // 22
    "0\n"                  // 23
    "1\n"                  // 24
    "2\n"                  // 25
    "1 5e9\n"              // 26
    "2 6e9\n"              // 27
    "$EndElementData\n";   // 28

std::string replace_line(const std::string& text, int line, const std::string& replacement) {
  std::string out;
  std::istringstream in(text);
  std::string l;
  for (int i = 1; std::getline(in, l); ++i) {
    if (i == line) {
      out += replacement;  // may be empty (line removed) or hold several lines
      if (!replacement.empty()) out += '\n';
    } else {
      out += l + '\n';
    }
  }
  return out;
}

std::string first_lines(const std::string& text, int count) {
  std::string out;
  std::istringstream in(text);
  std::string l;
  for (int i = 0; i < count && std::getline(in, l); ++i) out += l + '\n';
  return out;
}

std::string lines_between(const std::string& text, int first, int last) {
  std::string out;
  std::istringstream in(text);
  std::string l;
  for (int i = 1; std::getline(in, l); ++i) {
    if (i >= first && i <= last) out += l + '\n';
  }
  return out;
}

struct MalformedCase {
  const char* name;
  std::string content;
  int line;
  const char* expected;  // a piece of the message
};

std::vector<MalformedCase> malformed_cases() {
  const std::string v = kValid22;
  return {
      {"empty_file", "", 1, "empty file"},
      {"no_mesh_format", replace_line(v, 1, "$Nodes"), 1, "$MeshFormat"},
      {"missing_end_mesh_format", replace_line(v, 3, ""), 3, "$EndMeshFormat"},
      {"binary", replace_line(v, 2, "2.2 1 8"), 2, "binary"},
      {"unsupported_version", replace_line(v, 2, "3.0 0 8"), 2, "unsupported .msh version"},
      {"version_4_0", replace_line(v, 2, "4 0 8"), 2, "unsupported .msh version"},
      {"missing_nodes", first_lines(v, 3) + "$Foo\nbar\n$EndFoo\n" + lines_between(v, 12, 16), 11,
       "no $Nodes section"},
      {"missing_elements", first_lines(v, 11), 11, "no $Elements section"},
      {"node_count_too_high", replace_line(v, 5, "6"), 11, "after 5 of the 6"},
      {"node_count_too_low", replace_line(v, 5, "4"), 10, "expected $EndNodes"},
      {"negative_count", replace_line(v, 5, "-5"), 5, "negative"},
      {"non_numeric_coordinate", replace_line(v, 8, "3 0 1x 0"), 8, "'1x'"},
      {"non_numeric_count", replace_line(v, 5, "five"), 5, "'five'"},
      {"short_node_line", replace_line(v, 7, "2 1 0"), 7, "line ends"},
      {"long_node_line", replace_line(v, 7, "2 1 0 0 0"), 7, "unexpected '0'"},
      {"duplicate_node_tag", replace_line(v, 7, "1 1 0 0"), 7, "appears twice"},
      {"truncated_in_nodes", first_lines(v, 8), 8,
       "file ends inside the $Nodes section (expected 5 nodes, read 3)"},
      {"truncated_in_elements", first_lines(v, 14), 14,
       "file ends inside the $Elements section (expected 2 elements, read 1)"},
      {"missing_node", replace_line(v, 15, "2 4 2 1 1 2 3 4 6"), 15, "node 6"},
      {"short_tet_line", replace_line(v, 15, "2 4 2 1 1 2 3 4"), 15, "line ends"},
      {"element_count_too_high", replace_line(v, 13, "3"), 16, "after 2 of the 3"},
      {"hexahedron", replace_line(v, 15, "2 5 2 1 1 1 2 3 4 5 1 2 3"), 15, "hexahedron"},
      {"quadratic_tet", replace_line(v, 15, "2 11 2 1 1 1 2 3 4 5 1 2 3 4 5"), 15, "higher-order"},
      // A type Gmsh does not define, and an order-5 tetrahedron (Gmsh's 71), were dropped.
      {"unknown_type", replace_line(v, 15, "2 999 2 1 1 2 3 4 5"), 15, "element type 999"},
      {"order_5_tet", replace_line(v, 15, "2 71 2 1 1 2 3 4 5"), 15, "element type 71"},
      // A second block of the same name replaced the first without a word.
      {"data_name_twice", v + lines_between(v, 17, 28), 29, "'Y' is given a second time"},
      // A node block's count is no promise: 2e9 nodes, one tag given (16 GB were asked for).
      {"huge_node_block", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2000000000 1 2000000000\n"
                          "3 1 0 2000000000\n1\n$EndNodes\n", 8, "of the 2000000000"},
      {"data_count_too_high", replace_line(v, 25, "3"), 28, "after 2 of the 3"},
      {"data_count_too_low", replace_line(replace_line(v, 27, ""), 25, "1"), 17,
       "values for 1 of the 2"},
      {"data_duplicate", replace_line(v, 27, "1 6e9"), 27, "second value"},
      {"data_unknown_element", replace_line(v, 27, "9 6e9"), 27, "element 9"},
      {"data_non_numeric", replace_line(v, 27, "2 six"), 27, "'six'"},
      {"data_vector", replace_line(v, 24, "3"), 24, "3 components"},
      {"data_truncated", first_lines(v, 26), 26,
       "file ends inside the $ElementData section (expected 2 values of 'Y', read 1)"},
      {"unterminated_unknown_section", v + "$Comments\nhello\n", 30, "$EndComments"},
      {"stray_end", replace_line(v, 12, "$EndNodes\n$Elements"), 12, "without a matching"},
      {"garbage_between_sections", replace_line(v, 12, "hello\n$Elements"), 12, "section header"},
  };
}

TEST(Msh, MalformedFilesGiveFileAndLine) {
  ScratchDir dir;
  for (const MalformedCase& c : malformed_cases()) {
    SCOPED_TRACE(c.name);
    const std::string path = dir.file(std::string(c.name) + ".msh");
    write_text(path, c.content);
    const std::string msg = input_error_message([&] { read_msh(path); });
    const std::string prefix = path + ":" + std::to_string(c.line) + ": ";
    EXPECT_EQ(msg.rfind(prefix, 0), 0u) << msg << "\n  expected prefix: " << prefix;
    EXPECT_NE(msg.find(c.expected), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
}

// A file cut anywhere inside an element's line (a copy or download that stopped) is reported as
// truncated at its last line, whatever the cut leaves: "1" from "16 ..." is no duplicate tag 1,
// and "16 4 2 1 1 a b c 1" from "... 19" is no element. Cut right after a line break, the
// elements before the cut count as read.
class MshTruncated : public ::testing::TestWithParam<MshVersion> {};

TEST_P(MshTruncated, CutInsideAnElementNamesTheFileLineAndCounts) {
  ScratchDir dir;
  const TetMesh mesh = test::make_jittered_cube(2);  // 48 tets
  ASSERT_EQ(mesh.num_tets(), 48);
  const std::string full_path = dir.file("full.msh");
  write_msh(full_path, mesh, {{"rho", Eigen::VectorXd::Constant(48, 2500.0)}}, GetParam());
  const std::string full = test::read_text(full_path);
  // The line of element 16 in the $Elements section, and its line number.
  const std::size_t section = full.find("$Elements\n");
  const std::string tag_prefix = GetParam() == MshVersion::kV22 ? "\n16 4 " : "\n16 ";
  const std::size_t begin = full.find(tag_prefix, section) + 1;
  const std::size_t end = full.find('\n', begin);
  const int line = 1 + static_cast<int>(std::count(full.begin(), full.begin() + begin, '\n'));
  int cuts = 0;
  for (std::size_t cut = begin + 1; cut <= end + 1; ++cut) {
    SCOPED_TRACE("cut after " + std::to_string(cut - begin) + " characters of '" +
                 full.substr(begin, end - begin) + "'");
    const std::string path = dir.file("cut.msh");
    write_text(path, full.substr(0, cut));
    const std::string msg = input_error_message([&] { read_msh(path); });
    const bool whole_line = cut == end + 1;
    const std::string expected =
        path + ":" + std::to_string(line) + ": file ends inside the $Elements section (expected " +
        "48 elements, read " + (whole_line ? "16" : "15") + "): the file is truncated";
    EXPECT_EQ(msg, expected);
    ++cuts;
  }
  EXPECT_GT(cuts, 8);
  // The same inside the element data and the nodes.
  const std::size_t data = full.find("\n7 2500\n", full.find("$ElementData")) + 1;
  write_text(dir.file("data.msh"), full.substr(0, data + 4));
  const int data_line = 1 + static_cast<int>(std::count(full.begin(), full.begin() + data, '\n'));
  EXPECT_EQ(input_error_message([&] { read_msh(dir.file("data.msh")); }),
            dir.file("data.msh") + ":" + std::to_string(data_line) +
                ": file ends inside the $ElementData section (expected 48 values of 'rho', read "
                "6): the file is truncated");
  const std::size_t nodes = full.find("$Nodes\n");
  const std::size_t node_cut = full.find('\n', full.find('\n', nodes) + 1) + 3;
  write_text(dir.file("nodes.msh"), full.substr(0, node_cut));
  const std::string node_msg = input_error_message([&] { read_msh(dir.file("nodes.msh")); });
  EXPECT_NE(node_msg.find("file ends inside the $Nodes section (expected 27 nodes, read 0)"),
            std::string::npos)
      << node_msg;
}

INSTANTIATE_TEST_SUITE_P(Versions, MshTruncated,
                         ::testing::Values(MshVersion::kV22, MshVersion::kV41),
                         [](const auto& info) {
                           return info.param == MshVersion::kV22 ? "v22" : "v41";
                         });

TEST(Msh, TheValidBaseOfTheMalformedCasesReads) {
  ScratchDir dir;
  write_text(dir.file("valid.msh"), kValid22);
  const TetMeshFile file = read_tet_mesh(dir.file("valid.msh"));
  EXPECT_EQ(file.mesh.num_tets(), 2);
  EXPECT_EQ(file.element_data.at("Y"), Eigen::Vector2d(5e9, 6e9));
}

TEST(Msh, Version41BlockCountsAreChecked) {
  ScratchDir dir;
  std::string text = kMsh41;
  text.replace(text.find("3 6 7 99"), 8, "3 7 7 99");
  write_text(dir.file("count.msh"), text);
  const std::string msg = input_error_message([&] { read_msh(dir.file("count.msh")); });
  EXPECT_NE(msg.find("count.msh:11: "), std::string::npos) << msg;
  EXPECT_NE(msg.find("blocks hold 6"), std::string::npos) << msg;
}

TEST(Msh, InvertedTetIsRejectedWithTheFileNamed) {
  ScratchDir dir;
  write_text(dir.file("inverted.msh"), replace_line(kValid22, 15, "2 4 2 1 1 3 2 4 5"));
  const std::string msg = input_error_message([&] { read_tet_mesh(dir.file("inverted.msh")); });
  EXPECT_NE(msg.find("inverted.msh"), std::string::npos) << msg;
  EXPECT_NE(msg.find("inverted"), std::string::npos) << msg;
}

}  // namespace
}  // namespace rbaa
