// End-to-end checks of the rbaa program: outputs round-trip, bad input exits non-zero with a
// one-line message naming the input.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include "rbaa/geometry/moments.hpp"
#include "rbaa/io/tet_mesh_file.hpp"
#include "rbaa/mesh/tet_mesh.hpp"

#include "cli/cli_fixture.hpp"

namespace {

using rbaa_cli_test::Cli;
using rbaa_cli_test::Result;

TEST_F(Cli, MeshingIsByteIdenticalRunToRun) {
  // A probe saw the cube's tet count change from run to run before CGAL's seed was fixed.
  ASSERT_EQ(run("mesh --shape=cube --target_tets=4000 --out=" + path("a.msh")).exit_code, 0);
  ASSERT_EQ(run("mesh --shape=cube --target_tets=4000 --out=" + path("b.msh")).exit_code, 0);
  const std::string a = slurp(path("a.msh")), b = slurp(path("b.msh"));
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, b);
}

// --help promises a count within 5 % of --target_tets; when the surface cannot give that (the
// star's sharp edges keep about 580 tets at any cell size), one warning line on stderr says so,
// with the target, the count obtained and why, and the summary line reports both.
TEST_F(Cli, MeshingWarnsWhenTheTargetCountCannotBeMet) {
  const Result r = run("mesh --shape=star --target_tets=200 --out=" + path("star.msh"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const int tets = rbaa::read_tet_mesh(path("star.msh")).mesh.num_tets();
  ASSERT_GT(tets, 210);
  std::istringstream lines(r.err);
  std::vector<std::string> warnings;
  std::string summary;
  for (std::string line; std::getline(lines, line);) {
    if (line.find("warning") != std::string::npos) warnings.push_back(line);
    if (line.find(" tets") != std::string::npos && line.find("->") != std::string::npos) summary = line;
  }
  ASSERT_EQ(warnings.size(), 1u) << r.err;
  const std::string& w = warnings[0];
  EXPECT_NE(w.find("target of 200 tets"), std::string::npos) << w;
  EXPECT_NE(w.find("got " + std::to_string(tets)), std::string::npos) << w;
  EXPECT_NE(w.find("floor"), std::string::npos) << w;
  EXPECT_NE(summary.find(std::to_string(tets) + " tets (target 200)"), std::string::npos) << r.err;

  // A target the star can meet: no warning.
  const Result met = run("mesh --shape=star --target_tets=1506 --out=" + path("star_met.msh"));
  ASSERT_EQ(met.exit_code, 0) << met.err;
  const int met_tets = rbaa::read_tet_mesh(path("star_met.msh")).mesh.num_tets();
  EXPECT_NEAR(met_tets / 1506.0, 1.0, 0.05);
  EXPECT_EQ(met.err.find("warning"), std::string::npos) << met.err;
}

TEST_F(Cli, MomentsOfAMeshedShapeAsJson) {
  ASSERT_EQ(run("mesh --shape=star --out=" + path("star.mesh")).exit_code, 0);
  const Result r = run("moments --mesh=" + path("star.mesh"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_TRUE(j.contains("m0") && j["m1"].size() == 3 && j["m2"].size() == 6) << r.out;
  EXPECT_NEAR(j["m0"].get<double>() / 881.1, 1.0, 0.01);
  EXPECT_NEAR(j["m2"][0].get<double>() / 217.8, 1.0, 0.01);
  // The JSON carries full precision: it equals the library's value for the file it read.
  const rbaa::TetMesh mesh = rbaa::read_tet_mesh(path("star.mesh")).mesh;
  EXPECT_EQ(j["m0"].get<double>(), rbaa::compute_moments(mesh, 2500.0).m0);
}

TEST_F(Cli, MomentsUseTheMaterialsFile) {
  ASSERT_EQ(run("mesh --shape=cube --target_tets=500 --out=" + path("cube.msh")).exit_code, 0);
  const rbaa::TetMesh mesh = rbaa::read_tet_mesh(path("cube.msh")).mesh;
  std::ofstream csv(path("materials.csv"));
  csv << "Y,nu,rho,alpha\n";
  for (int e = 0; e < mesh.num_tets(); ++e) csv << "1e10,0.3," << (e % 2 ? 1000 : 8000) << ",0.5\n";
  csv.close();
  const Result r = run("moments --mesh=" + path("cube.msh") + " --materials=" + path("materials.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Eigen::VectorXd density(mesh.num_tets());
  for (int e = 0; e < mesh.num_tets(); ++e) density[e] = (e % 2 ? 1000 : 8000) * 0.5;
  EXPECT_DOUBLE_EQ(nlohmann::json::parse(r.out)["m0"].get<double>(), rbaa::compute_moments(mesh, density).m0);
  expect_failure("moments --mesh=" + path("cube.msh") + " --materials=" + path("missing.csv"), "missing.csv");
}

TEST_F(Cli, BadInputGivesOneLineErrors) {
  expect_failure("mesh --shape=torus --out=" + path("t.msh"), "unknown shape 'torus'");
  expect_failure("mesh --surface=" + path("none.off") + " --out=" + path("t.msh"), "none.off");
  expect_failure("mesh --shape=cube", "--out is required");
  expect_failure("moments --mesh=" + path("absent.msh"), "absent.msh");
  std::ofstream(path("broken.msh")) << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2\n";
  expect_failure("moments --mesh=" + path("broken.msh"), "broken.msh");
  std::ofstream(path("open.off")) << "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  expect_failure("mesh --surface=" + path("open.off") + " --out=" + path("t.msh"), "open.off");
  expect_failure("frobnicate", "unknown verb 'frobnicate'");
}

// The mesher reads a size <= 0 as "the default", and each size flag belongs to one input: before
// the check, --shape=sphere --radius=-1 meshed the 0.121 m sphere, --shape=cube --radius=0.5
// --volume=3 the 0.05 m cube, --surface --volume=-1 the surface unscaled, all with exit 0. Each is
// refused with exit 2 and nothing written; a size given to its own input is kept.
TEST_F(Cli, MeshRefusesASizeItsShapeDoesNotReadOrThatIsNotPositive) {
  const std::string surface = write_file(
      "cube.off",
      "OFF\n8 12 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n3 0 2 1\n3 0 3 2\n"
      "3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n3 1 2 6\n3 1 6 5\n3 2 3 7\n3 2 7 6\n3 3 0 4\n3 3 4 7\n");
  std::ofstream(path("flags.txt")) << "--radius=-0.2\n";
  const std::string out = " --target_tets=200 --out=" + path("t.msh");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--shape=sphere --radius=-1", "--radius=-1: must be positive"},
      {"--shape=sphere --radius=0", "--radius=0: must be positive"},
      {"--shape=sphere --flagfile=" + path("flags.txt"), "--radius=-0.2: must be positive"},
      {"--shape=cube --side=0", "--side=0: must be positive"},
      {"--surface=" + surface + " --volume=-1", "--volume=-1: must be positive"},
      {"--shape=cube --radius=0.5 --volume=3", "--radius=0.5: --shape=cube has no radius"},
      {"--shape=sphere --side=0.1", "--side=0.1: --shape=sphere has no side"},
      {"--shape=star --volume=2", "--volume=2: --shape=star has no volume"},
      {"--surface=" + surface + " --radius=0.1", "--radius=0.1: --surface has no radius"},
      {"--shape=sphere --radius=inf", "--radius=inf: expected a finite number"},
      {"--shape=torus --radius=1", "unknown shape 'torus'"},
  };
  for (const auto& [args, fragment] : cases) {
    std::filesystem::remove(path("t.msh"));
    expect_failure("mesh " + args + out, fragment);
    EXPECT_EQ(run("mesh " + args + out).exit_code, 2) << args;
    EXPECT_FALSE(std::filesystem::exists(path("t.msh"))) << args;
  }
  // A size given to its own input is used: the 0.05 m sphere (a polyhedron inside it) and the
  // unit cube scaled to 3 m^3.
  ASSERT_EQ(run("mesh --shape=sphere --radius=0.05" + out).exit_code, 0);
  const double ball = rbaa::tet_volumes(rbaa::read_tet_mesh(path("t.msh")).mesh).sum();
  EXPECT_NEAR(ball / (4.0 / 3.0 * M_PI * 0.05 * 0.05 * 0.05), 1.0, 0.15);
  ASSERT_EQ(run("mesh --surface=" + surface + " --volume=3" + out).exit_code, 0);
  EXPECT_NEAR(rbaa::tet_volumes(rbaa::read_tet_mesh(path("t.msh")).mesh).sum(), 3.0, 1e-9);
}

// gflags' flags are global: another verb's flag would be accepted and ignored (an export given
// --materials, an evaluate given --iterations), and inf or nan would pass as a double. Both are
// one-line errors before the verb runs, also when they come from a --flagfile; the verb's own
// flags and glog's (--v) are fine.
TEST_F(Cli, AFlagTheVerbDoesNotReadOrANonFiniteNumberIsRefused) {
  const std::string ball = "--config=" RBAA_SOURCE_DIR "/configs/ball.yaml --set=mesh.target_tets=300 ";
  const std::string out = " --out=" + path("x");
  std::ofstream(path("flags.txt")) << "--vtu_every=0\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"export --format=polyfem " + ball + "--materials=" + path("m.csv"),
       "--materials is not a flag of rbaa export"},
      {"evaluate " + ball + "--adversarial=reference --iterations=3",
       "--iterations is not a flag of rbaa evaluate"},
      {"attack " + ball + "--progress=false", "--progress is not a flag of rbaa attack"},
      {"export --format=polyfem " + ball + "--flagfile=" + path("flags.txt"),
       "--vtu_every is not a flag of rbaa export"},
      {"evaluate " + ball + "--adversarial=reference --duration=inf",
       "--duration=inf: expected a finite number"},
      {"evaluate " + ball + "--adversarial=reference --rigid_step=nan",
       "--rigid_step=nan: expected a finite number"},
      {"attack " + ball + "--iterations=-5", "--iterations=-5"},
  };
  for (const auto& [args, fragment] : cases) expect_failure(args + out, fragment);
  const Result fine = run("export --format=polyfem " + ball + "--v=0 --out=" + path("fine"));
  EXPECT_EQ(fine.exit_code, 0) << fine.err;
}

TEST_F(Cli, HelpListsVerbsAndFlags) {
  const Result overview = run("--help");
  EXPECT_EQ(overview.exit_code, 0);
  EXPECT_NE(overview.out.find("mesh"), std::string::npos);
  EXPECT_NE(overview.out.find("moments"), std::string::npos);
  const Result mesh = run("mesh --help");
  EXPECT_EQ(mesh.exit_code, 0);
  EXPECT_NE(mesh.out.find("--target_tets"), std::string::npos);
}

}  // namespace
