#include <gtest/gtest.h>

#include <regex>

#include "io/io_test_support.hpp"
#include "rbaa/io/vtu.hpp"

namespace rbaa {
namespace {

using test::ScratchDir;

// Number of whitespace-separated values between the opening DataArray tag named `name` and its
// closing tag; -1 if there is no such array.
int values_in_array(const std::string& xml, const std::string& name) {
  const std::size_t tag = xml.find("Name=\"" + name + "\"");
  if (tag == std::string::npos) return -1;
  const std::size_t begin = xml.find('>', tag) + 1;
  const std::size_t end = xml.find("</DataArray>", begin);
  std::istringstream in(xml.substr(begin, end - begin));
  int count = 0;
  std::string word;
  while (in >> word) ++count;
  return count;
}

std::string attribute(const std::string& xml, const std::string& name) {
  std::smatch m;
  if (!std::regex_search(xml, m, std::regex(name + "=\"([^\"]*)\""))) return "";
  return m[1];
}

TEST(Vtu, HoldsTheMeshAndEveryField) {
  ScratchDir dir;
  const TetMesh mesh = test::make_jittered_cube(2);
  const int nv = mesh.num_vertices();
  const int nt = mesh.num_tets();
  VtuFields point_data = {{"displacement", Eigen::MatrixXd::Random(nv, 3)},
                          {"temperature", Eigen::VectorXd::Ones(nv)}};
  VtuFields cell_data = {{"Y", Eigen::VectorXd::Constant(nt, 1e10)},
                         {"alpha", Eigen::VectorXd::Constant(nt, 0.5)}};
  write_vtu(dir.file("m.vtu"), mesh, point_data, cell_data);
  const std::string xml = test::read_text(dir.file("m.vtu"));
  EXPECT_NE(xml.find("type=\"UnstructuredGrid\""), std::string::npos);
  EXPECT_EQ(attribute(xml, "NumberOfPoints"), std::to_string(nv));
  EXPECT_EQ(attribute(xml, "NumberOfCells"), std::to_string(nt));
  EXPECT_EQ(values_in_array(xml, "Points"), 3 * nv);
  EXPECT_EQ(values_in_array(xml, "connectivity"), 4 * nt);
  EXPECT_EQ(values_in_array(xml, "offsets"), nt);
  EXPECT_EQ(values_in_array(xml, "types"), nt);
  EXPECT_EQ(values_in_array(xml, "displacement"), 3 * nv);
  EXPECT_EQ(values_in_array(xml, "temperature"), nv);
  EXPECT_EQ(values_in_array(xml, "Y"), nt);
  EXPECT_EQ(values_in_array(xml, "alpha"), nt);
  // Point fields sit inside PointData, cell fields inside CellData.
  const std::size_t pd = xml.find("<PointData>"), cd = xml.find("<CellData>");
  ASSERT_NE(pd, std::string::npos);
  ASSERT_NE(cd, std::string::npos);
  EXPECT_LT(pd, xml.find("displacement"));
  EXPECT_LT(xml.find("displacement"), cd);
  EXPECT_LT(cd, xml.find("Name=\"Y\""));
  EXPECT_NE(xml.find("NumberOfComponents=\"3\" format"), std::string::npos);
  EXPECT_NE(xml.find("type=\"Float64\""), std::string::npos);
}

TEST(Vtu, FieldOfTheWrongSizeIsRefusedByName) {
  ScratchDir dir;
  const TetMesh mesh = test::make_jittered_cube(1);
  const std::string msg = test::input_error_message([&] {
    write_vtu(dir.file("bad.vtu"), mesh, {}, {{"rho", Eigen::VectorXd::Ones(mesh.num_tets() - 1)}});
  });
  EXPECT_NE(msg.find("bad.vtu"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'rho'"), std::string::npos) << msg;
  EXPECT_FALSE(std::filesystem::exists(dir.file("bad.vtu")));
}

TEST(Vtu, NamesAreEscaped) {
  ScratchDir dir;
  const TetMesh mesh = test::make_jittered_cube(1);
  write_vtu(dir.file("e.vtu"), mesh, {}, {{"a<b & \"c\"", Eigen::VectorXd::Ones(mesh.num_tets())}});
  EXPECT_NE(test::read_text(dir.file("e.vtu")).find("a&lt;b &amp; &quot;c&quot;"),
            std::string::npos);
}

TEST(Pvd, ListsEveryFrameInOrder) {
  ScratchDir dir;
  write_pvd(dir.file("series.pvd"),
            {{0.0, "frame_0000.vtu"}, {0.01, "frame_0001.vtu"}, {0.02, "frame_0002.vtu"}});
  const std::string xml = test::read_text(dir.file("series.pvd"));
  EXPECT_NE(xml.find("type=\"Collection\""), std::string::npos);
  std::regex dataset("<DataSet timestep=\"([^\"]*)\"[^>]*file=\"([^\"]*)\"");
  std::vector<std::pair<std::string, std::string>> found;
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), dataset);
       it != std::sregex_iterator(); ++it) {
    found.emplace_back((*it)[1], (*it)[2]);
  }
  ASSERT_EQ(found.size(), 3u);
  EXPECT_EQ(found[1].first, "0.01");
  EXPECT_EQ(found[2].second, "frame_0002.vtu");
}

}  // namespace
}  // namespace rbaa
