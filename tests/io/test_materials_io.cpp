#include <gtest/gtest.h>

#include "io/io_test_support.hpp"
#include "rbaa/io/materials_io.hpp"
#include "rbaa/io/msh.hpp"

namespace rbaa {
namespace {

using test::input_error_message;
using test::ScratchDir;
using test::write_text;

MaterialField varied_field(int n) {
  MaterialField f;
  f.Y = Eigen::VectorXd::LinSpaced(n, 2.5e9, 6.5e11);
  f.nu = Eigen::VectorXd::LinSpaced(n, 0.2, 0.4);
  f.rho = Eigen::VectorXd::LinSpaced(n, 800.0 / 3.0, 11300.0);
  f.alpha = Eigen::VectorXd::LinSpaced(n, 0.01, 1.0);
  return f;
}

void expect_same(const MaterialField& a, const MaterialField& b) {
  EXPECT_TRUE(test::bit_equal(a.Y, b.Y));
  EXPECT_TRUE(test::bit_equal(a.nu, b.nu));
  EXPECT_TRUE(test::bit_equal(a.rho, b.rho));
  EXPECT_TRUE(test::bit_equal(a.alpha, b.alpha));
}

TEST(Materials, CsvRoundTripIsExact) {
  ScratchDir dir;
  const MaterialField field = varied_field(17);
  write_materials_csv(dir.file("m.csv"), field);
  expect_same(read_materials(dir.file("m.csv"), 17), field);
}

TEST(Materials, CsvColumnsInAnyOrderAlphaOptionalOtherColumnsIgnored) {
  ScratchDir dir;
  write_text(dir.file("m.csv"),
             "# materials\nrho, element ,nu,\"Y\"\n2500,0,0.3,1e10\n\n1000,1,0.25,2e10\n");
  const MaterialField f = read_materials(dir.file("m.csv"), 2);
  EXPECT_EQ(f.Y, Eigen::Vector2d(1e10, 2e10));
  EXPECT_EQ(f.nu, Eigen::Vector2d(0.3, 0.25));
  EXPECT_EQ(f.rho, Eigen::Vector2d(2500, 1000));
  EXPECT_EQ(f.alpha, Eigen::Vector2d(1, 1));
}

TEST(Materials, CsvErrorsNameFileAndLine) {
  ScratchDir dir;
  struct Case {
    const char* name;
    const char* text;
    int tets;
    const char* where;
    const char* expected;
  } cases[] = {
      {"too_few_rows", "Y,nu,rho\n1e10,0.3,2500\n", 2, ":2:", "1 rows"},
      {"too_many_rows", "Y,nu,rho\n1e10,0.3,2500\n1e10,0.3,2500\n1e10,0.3,2500\n", 2,
       ":4:", "3 rows"},
      {"missing_column", "Y,nu,density\n1e10,0.3,2500\n", 1, ":1:", "missing column 'rho'"},
      {"nan", "Y,nu,rho\n1e10,0.3,2500\nnan,0.3,2500\n", 2, ":3:", "'Y' is nan"},
      {"non_numeric", "Y,nu,rho\n1e10,0.3,2500\n1e10,zero,2500\n", 2, ":3:", "'zero'"},
      {"empty_field", "Y,nu,rho\n1e10,,2500\n", 1, ":2:", "'nu' is empty"},
      {"wrong_field_count", "Y,nu,rho\n1e10,0.3\n", 1, ":2:", "2 fields"},
      {"duplicate_column", "Y,nu,Y,rho\n", 0, ":1:", "twice"},
      {"empty", "", 1, ":1:", "end of file"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = dir.file(std::string(c.name) + ".csv");
    write_text(path, c.text);
    const std::string msg = input_error_message([&] { read_materials(path, c.tets); });
    EXPECT_NE(msg.find(path + c.where), std::string::npos) << msg;
    EXPECT_NE(msg.find(c.expected), std::string::npos) << msg;
  }
}

TEST(Materials, OutOfRangeValuesAreRejectedByValidation) {
  ScratchDir dir;
  write_text(dir.file("bad.csv"), "Y,nu,rho,alpha\n1e10,0.7,2500,1\n");
  const std::string msg = input_error_message([&] { read_materials(dir.file("bad.csv"), 1); });
  EXPECT_NE(msg.find("bad.csv"), std::string::npos) << msg;
  EXPECT_NE(msg.find("nu"), std::string::npos) << msg;
}

TEST(Materials, PoissonRatioOfOneHalfIsRefusedWithTheOpenInterval) {
  ScratchDir dir;
  write_text(dir.file("half.csv"), "Y,nu,rho,alpha\n1e10,0.3,2500,1\n1e10,0.5,2500,1\n");
  EXPECT_EQ(input_error_message([&] { read_materials(dir.file("half.csv"), 2); }),
            dir.file("half.csv") + ": material field 'nu' of element 1 is 0.5, outside (-1, 0.5)");
}

TEST(Materials, MshElementDataRoundTrip) {
  ScratchDir dir;
  const TetMesh mesh = test::make_jittered_cube(2);
  const MaterialField field = varied_field(mesh.num_tets());
  write_msh(dir.file("adv.msh"), mesh, material_element_data(field));
  expect_same(read_materials(dir.file("adv.msh"), mesh.num_tets()), field);
}

TEST(Materials, MshErrors) {
  ScratchDir dir;
  const TetMesh mesh = test::make_jittered_cube(1);
  const int nt = mesh.num_tets();
  MaterialField field = varied_field(nt);
  write_msh(dir.file("adv.msh"), mesh, material_element_data(field));
  std::string msg = input_error_message([&] { read_materials(dir.file("adv.msh"), nt + 1); });
  EXPECT_NE(msg.find("adv.msh"), std::string::npos) << msg;
  EXPECT_NE(msg.find(std::to_string(nt + 1)), std::string::npos) << msg;

  write_msh(dir.file("no_rho.msh"), mesh, {{"Y", field.Y}, {"nu", field.nu}});
  msg = input_error_message([&] { read_materials(dir.file("no_rho.msh"), nt); });
  EXPECT_NE(msg.find("no_rho.msh"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'rho'"), std::string::npos) << msg;

  msg = input_error_message([&] { read_materials(dir.file("m.json"), nt); });
  EXPECT_NE(msg.find("m.json"), std::string::npos) << msg;

  // Against a mesh, not only its count: the same mesh moved is its mesh, one of the same count
  // with other tets (the cube's tets 0 and 1 swapped) is not.
  TetMesh moved = mesh;
  moved.V.rowwise() += Eigen::RowVector3d(0.3, -2, 5);
  expect_same(read_materials(dir.file("adv.msh"), moved), field);
  TetMesh other = mesh;
  other.T.row(0).swap(other.T.row(1));
  msg = input_error_message([&] { read_materials(dir.file("adv.msh"), other); });
  EXPECT_NE(msg.find("adv.msh: the file's mesh is not the mesh: its tet 0 has vertices ("),
            std::string::npos)
      << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  // A .csv names no tets: its row count is all there is to check.
  write_materials_csv(dir.file("m.csv"), field);
  expect_same(read_materials(dir.file("m.csv"), other), field);
}

TEST(Materials, AlphaDefaultsToOneInMsh) {
  ScratchDir dir;
  const TetMesh mesh = test::make_jittered_cube(1);
  const MaterialField field = varied_field(mesh.num_tets());
  write_msh(dir.file("a.msh"), mesh, {{"Y", field.Y}, {"nu", field.nu}, {"rho", field.rho}},
            MshVersion::kV22);
  EXPECT_TRUE((read_materials(dir.file("a.msh"), mesh.num_tets()).alpha.array() == 1.0).all());
}

}  // namespace
}  // namespace rbaa
