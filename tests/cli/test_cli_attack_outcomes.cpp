// `rbaa attack` when something goes wrong in the middle of a run, seen as a user sees it: the loop
// stopped early by a simulation that does not converge (report.json says so, the failing design is
// written and reproduces the failure, a resume with a higher limit finishes the run), a polish
// whose last design fails (not kept, the post-processed object is the result), and a
// post-process that fails after the loop (the optimised design is kept on disk and the error
// says where).

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "cli/cli_fixture.hpp"
#include "rbaa/io/tet_mesh_file.hpp"
#include "rbaa/mesh/tet_mesh.hpp"

namespace {

using rbaa_cli_test::Cli;
using rbaa_cli_test::Result;

// The tiny ball (r = 0.1 m, 300 tets) thrown at a plane at `speed` m/s, its attack at Adam's
// `learning_rate` (0.05 is the default). The stop-early test needs an early Adam design that
// needs more Newton iterations than the reference and the designs before it, and Newton's counts
// are flat: since Newton minimises along its backtracked steps
// (newton_solver.cpp) most designs need 12. Which scene gives such a design depends on the
// machine's rounding, so the test tries kStopScenes in turn and uses the first that does.
// Measured 2026-11-28, each scene alone giving the test its case (reference: designs 0 .. 6):
// 15 m/s at 0.05, 12: 12 13 ... (design 1); 17.5 m/s at 0.05; 12.5 m/s at 0.2, 12: 12 12 12 12 12
// 13 (design 5); 15 m/s at 0.01, 12: 12 12 12 12 13 (design 4). None at 10, 12.5, 20, 22.5, 25 or
// 30 m/s at 0.05 (within 10 designs), at 10 m/s at 0.01 or 0.2, or at 20 m/s at 0.2 (13: 12 13 13
// ...: never more than the reference).
std::string tiny_ball(double speed, double learning_rate) {
  return "mesh: {shape: sphere, radius: 0.1, target_tets: 300}\n"
         "object: {position: [0, -0.13, 0.5], velocity: [0, " + std::to_string(speed) + ", 0]}\n"
         "obstacles: {planes: [{normal: [0, -1, 0], offset: 0}]}\n"
         "gravity: off\n"
         "time: {step: 0.01, duration: 0.05}\n"
         "attack: {learning_rate: " + std::to_string(learning_rate) + "}\n";
}
struct StopScene {
  double speed, learning_rate;
};
const StopScene kStopScenes[] = {{15.0, 0.05}, {17.5, 0.05}, {12.5, 0.2}, {15.0, 0.01}};

class CliAttackOutcomes : public Cli {
 protected:
  /// The most Newton iterations any step of `rbaa simulate` needs (materials: "" = reference).
  int max_newton_iterations(const std::string& config, const std::string& materials, const std::string& dir) {
    const Result r = run("simulate --config=" + config + (materials.empty() ? "" : " --materials=" + materials) +
                         " --vtu_every=0 --progress=false --out=" + path(dir));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    if (r.exit_code != 0) return -1;
    const auto its = report(dir)["newton"]["iterations_per_step"].get<std::vector<int>>();
    return *std::max_element(its.begin(), its.end());
  }
};

TEST_F(CliAttackOutcomes, StoppedEarlyWritesTheFailedDesignAndResumes) {
  // The Newton iterations of the reference and of the designs after k Adam iterations (the
  // continuous.msh of an attack run with --iterations=k is design k). The limit is chosen from
  // these counts, not hard-coded, and the scene from kStopScenes, so that another machine's
  // rounding cannot make the test vacuous.
  std::string config, tag, tried;
  int limit = 0, failing = -1;
  for (size_t i = 0; i < std::size(kStopScenes) && failing < 0; ++i) {
    const StopScene& scene = kStopScenes[i];
    tag = "scene" + std::to_string(i);
    config = write_file(tag + ".yaml", tiny_ball(scene.speed, scene.learning_rate));
    const int reference = max_newton_iterations(config, "", tag + "_ref");
    ASSERT_GT(reference, 1);
    limit = reference;
    for (int k = 0; k <= 6 && failing < 0; ++k) {
      const std::string dir = tag + "_k" + std::to_string(k);
      const Result a = run("attack --config=" + config + " --iterations=" + std::to_string(k) + " --out=" + path(dir));
      ASSERT_EQ(a.exit_code, 0) << a.err;
      const int n = max_newton_iterations(config, path(dir + "/continuous.msh"), dir + "_sim");
      if (n > limit && k > 0) failing = k;
      else limit = std::max(limit, n);
    }
    tried += " " + std::to_string(scene.speed) + " m/s at " + std::to_string(scene.learning_rate) + " (limit " +
             std::to_string(limit) + ");";
  }
  ASSERT_GT(failing, 0) << "in no scene did a design within 6 Adam iterations need more Newton iterations than "
                           "the reference and the designs before it:" << tried;

  // With newton.max_iterations = limit, the reference and designs 0 .. failing-1 simulate and
  // design `failing` does not: the loop stops there and keeps design failing-1.
  const std::string set = " --set=newton.max_iterations=" + std::to_string(limit);
  const Result stopped = run("attack --config=" + config + " --iterations=10 --out=" + path("s") + set);
  ASSERT_EQ(stopped.exit_code, 0) << stopped.err;
  EXPECT_NE(stopped.err.find("stopped early"), std::string::npos) << stopped.err;
  const auto j = report("s");
  ASSERT_TRUE(j["stopped_early"].is_string()) << j.dump(2);
  const std::string why = j["stopped_early"].get<std::string>();
  EXPECT_NE(why.find("did not converge in " + std::to_string(limit) + " iterations"), std::string::npos) << why;
  EXPECT_EQ(j["iterations"].get<int>(), failing);
  // The tolerance in the message is the one `rbaa simulate` reports in m/s (newton.tolerance is
  // relative to the bounding-box diagonal), to the message's 6 digits.
  const auto ref_newton = report(tag + "_ref")["newton"];
  const size_t at = why.find("tolerance ");
  ASSERT_NE(at, std::string::npos) << why;
  const double tolerance = std::stod(why.substr(at + 10));
  EXPECT_NEAR(tolerance, ref_newton["tolerance_m_per_s"].get<double>(), 1e-5 * tolerance);
  EXPECT_LT(ref_newton["tolerance_m_per_s"].get<double>(), ref_newton["tolerance"].get<double>());
  // The kept design is the last that simulated, design failing-1, bit for bit.
  const rbaa::TetMeshFile kept = rbaa::read_tet_mesh(path("s/continuous.msh"));
  const rbaa::TetMeshFile before = rbaa::read_tet_mesh(path(tag + "_k" + std::to_string(failing - 1) + "/continuous.msh"));
  ASSERT_EQ(kept.element_data.count("Y"), 1u);
  for (const char* field : {"Y", "nu", "rho", "alpha"}) {
    EXPECT_EQ(kept.element_data.at(field), before.element_data.at(field)) << field;
  }
  // The failing design is written, is design `failing`, and reproduces the failure in
  // `rbaa simulate`; with the default limit it simulates.
  ASSERT_TRUE(std::filesystem::exists(path("s/failed_design.msh")));
  const rbaa::TetMeshFile failed = rbaa::read_tet_mesh(path("s/failed_design.msh"));
  const rbaa::TetMeshFile design = rbaa::read_tet_mesh(path(tag + "_k" + std::to_string(failing) + "/continuous.msh"));
  for (const char* field : {"Y", "nu", "rho", "alpha"}) {
    EXPECT_EQ(failed.element_data.at(field), design.element_data.at(field)) << field;
  }
  expect_failure("simulate --config=" + config + " --materials=" + path("s/failed_design.msh") + set +
                     " --vtu_every=0 --progress=false --out=" + path("f"),
                 "did not converge");
  EXPECT_GT(max_newton_iterations(config, path("s/failed_design.msh"), "f2"), limit);

  // A resume with a higher limit goes on past the failing design and finishes the run.
  const Result resumed = run("attack --config=" + config + " --iterations=" + std::to_string(failing + 2) +
                             " --resume --set=newton.max_iterations=100 --out=" + path("s"));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  const auto done = report("s");
  EXPECT_TRUE(done["stopped_early"].is_null()) << done.dump(2);
  EXPECT_EQ(done["iterations"].get<int>(), failing + 2);
}

// A polish whose last design cannot be measured (its density re-fit or its simulation fails; both
// happen only after the polish loop) is not kept: the attack ends normally with the
// post-processed object, and report.json says why. A learning rate of 50 with the plain moment
// penalty throws the densities to their bounds in two polish steps, and the re-fit cannot bring
// the moments back (measured: max normalised residual 11.8 at Ceres' convergence). Before, the
// whole attack failed at its end. (The projected loop, since 2026-11-28, shortens the steps that
// would leave the moments, and its polish at this rate is kept.)
TEST_F(CliAttackOutcomes, PolishThatFailsIsNotKept) {
  const std::string config = write_file("fast.yaml", tiny_ball(10.0, 0.05));
  const std::string base = "attack --config=" + config +
                           " --iterations=0 --set=attack.learning_rate=50 --set=attack.project_moments=false";
  ASSERT_EQ(run(base + " --out=" + path("p0")).exit_code, 0);
  const Result r = run(base + " --set=attack.polish_iterations=2 --out=" + path("nk"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("the polished object failed, keeping the post-processed object"), std::string::npos) << r.err;
  const auto j = report("nk");
  EXPECT_EQ(j["polish"]["iterations"].get<int>(), 2) << j.dump(2);
  EXPECT_TRUE(j["polish"]["stopped_early"].is_null()) << j.dump(2);
  EXPECT_FALSE(j["polish"]["kept"].get<bool>());
  EXPECT_TRUE(j["polish"]["gap"].is_null());
  ASSERT_TRUE(j["polish"]["failed"].is_string()) << j.dump(2);
  EXPECT_NE(j["polish"]["failed"].get<std::string>().find("density re-fit"), std::string::npos);
  EXPECT_EQ(j["gap"]["final"], j["gap"]["post_processed"]);
  EXPECT_EQ(j["gap"]["post_processed"], report("p0")["gap"]["post_processed"]);
  EXPECT_LE(j["moments"]["max_normalized_residual"].get<double>(), 1e-10);
  // The result is the unpolished object, byte for byte.
  EXPECT_EQ(slurp(path("nk/adversarial.msh")), slurp(path("p0/adversarial.msh")));
}

// A post-process that cannot succeed: all interior elements start at alpha0 = 0.3 and round to
// void at threshold 0.9, and the shell alone cannot carry the reference's mass within the density
// bounds. The error says why and where the optimised design is, and that design is on disk.
TEST_F(CliAttackOutcomes, FailedPostProcessKeepsTheOptimisedDesign) {
  const std::string config = write_file(
      "void.yaml", std::string(rbaa_cli_test::kTinyBall) +
                       "reference_material: {Y: 1.0e11, nu: 0.3, rho: 2500}\n"
                       "material_bounds: {rho: [2490, 8400]}\n"
                       "attack: {iterations: 1, alpha0: 0.3, round_threshold: 0.9}\n");
  const Result r = run("attack --config=" + config + " --out=" + path("a"));
  EXPECT_NE(r.exit_code, 0);
  std::string last;
  std::istringstream lines(r.err);
  for (std::string line; std::getline(lines, line);) last = line;
  EXPECT_NE(last.find("density re-fit"), std::string::npos) << r.err;
  EXPECT_NE(last.find("kept in " + path("a") + "/continuous.msh"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(path("a/report.json")));
  const rbaa::TetMeshFile design = rbaa::read_tet_mesh(path("a/continuous.msh"));
  ASSERT_EQ(design.element_data.count("alpha"), 1u);
  EXPECT_GT(design.mesh.num_tets(), 0);
  // It is a design `rbaa simulate` runs.
  const Result sim = run("simulate --config=" + config + " --materials=" + path("a/continuous.msh") +
                         " --vtu_every=0 --progress=false --out=" + path("sim"));
  EXPECT_EQ(sim.exit_code, 0) << sim.err;
}

}  // namespace
