// rbaa simulate and rbaa evaluate as a user runs them: outputs, and clear errors on bad input.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include <Eigen/Dense>

#include <csignal>

#include "cli/cli_fixture.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/io/materials_io.hpp"
#include "rbaa/io/tet_mesh_file.hpp"
#include "rbaa/scene/scene.hpp"
#include "rbaa/scene/scene_mesh.hpp"
#include "support/floor_obj.hpp"

namespace {

using rbaa_cli_test::Cli;
using rbaa_cli_test::Result;

using rbaa_cli_test::kTinyBall;

class CliSimulate : public Cli {
 protected:
  std::string write_config(const std::string& name, const std::string& text) {
    return write_file(name, text);
  }
  /// report.json without its timing, which differs between runs of the same thing.
  nlohmann::json report_without_timing(const std::string& dir) const {
    auto j = report(dir);
    j.erase("timing");
    return j;
  }
};

TEST_F(CliSimulate, WritesTrajectoryVtuSeriesAndReport) {
  const std::string config = write_config("ball.yaml", kTinyBall);
  const Result r = run("simulate --config=" + config + " --out=" + path("sim"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = Cli::report("sim");
  EXPECT_EQ(report["newton"]["iterations_per_step"].size(), 5u);
  EXPECT_GT(report["kappa"].get<double>(), 0.0);
  std::ifstream csv(path("sim/trajectory.csv"));
  int lines = 0;
  for (std::string line; std::getline(csv, line);) ++lines;
  EXPECT_EQ(lines, 1 + 6);  // header + q_0 .. q_5
  EXPECT_TRUE(std::filesystem::exists(path("sim/trajectory.pvd")));
  // --set overrides a config value from the command line.
  const Result shorter = run("simulate --config=" + config + " --set=time.duration=0.02 --out=" + path("sim2"));
  ASSERT_EQ(shorter.exit_code, 0) << shorter.err;
  EXPECT_EQ(Cli::report("sim2")["newton"]["iterations_per_step"].size(), 2u);
  // Repeated --set flags all apply, in order (gflags alone would keep only the last): 0.02 s at
  // 0.005 s is four steps, and of two values for one key the later wins.
  const Result both = run("simulate --config=" + config +
                          " --set=time.duration=0.03 --set time.step=0.005 -set=time.duration=0.02"
                          " --vtu_every=0 --out=" + path("sim3"));
  ASSERT_EQ(both.exit_code, 0) << both.err;
  EXPECT_EQ(Cli::report("sim3")["newton"]["iterations_per_step"].size(), 4u);
}

// Contact-resolving steps: report.json says what they did, and trajectory.csv keeps one row per
// step of h however many sub-steps were taken.
TEST_F(CliSimulate, ContactResolvingStepsReportTheirStepsAndKeepTheGrid) {
  const std::string config = write_config("ball.yaml", kTinyBall);
  const Result r = run("simulate --config=" + config + " --set=time.contact_substeps=8 --vtu_every=0 --out=" +
                       path("cr"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = Cli::report("cr");
  ASSERT_TRUE(report.contains("contact_resolving")) << report.dump();
  const auto& c = report["contact_resolving"];
  EXPECT_EQ(c["substeps"].get<int>(), 8);
  EXPECT_EQ(c["steps_of_h"].get<int>(), 5);
  EXPECT_EQ(c["steps_taken"].get<int>(), report["steps"].get<int>());
  EXPECT_EQ(c["steps_taken"].get<std::size_t>(), report["newton"]["iterations_per_step"].size());
  // The ball meets the plane 0.015 s in: steps shrink around it.
  EXPECT_GE(c["contacts"].get<int>(), 1);
  EXPECT_GT(c["steps_taken"].get<int>(), 5);
  EXPECT_GT(c["sub_steps"].get<int>(), 0);
  EXPECT_DOUBLE_EQ(report["duration"].get<double>(), 0.05);
  std::ifstream csv(path("cr/trajectory.csv"));
  int lines = 0;
  for (std::string line; std::getline(csv, line);) ++lines;
  EXPECT_EQ(lines, 1 + 6);
}

// The command line sizes OpenMP teams dynamically (CHOLMOD asks for 4 threads on any machine) and
// puts OpenBLAS on one thread, unless the user set OMP_DYNAMIC / OPENBLAS_NUM_THREADS; report.json
// says what it set.
TEST_F(CliSimulate, ThreadSetupRespectsTheUsersEnvironment) {
  const std::string config = write_config("ball.yaml", kTinyBall);
  auto setup = [&](const std::string& env, const std::string& dir) {
    const std::string cmd = "env " + env + " " + std::string(RBAA_EXECUTABLE) + " simulate --config=" + config +
                            " --vtu_every=0 --progress=false --out=" + path(dir) + " 2>/dev/null";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    return report(dir)["timing"]["thread_setup"].get<std::string>();
  };
  EXPECT_EQ(setup("-u OMP_DYNAMIC -u OPENBLAS_NUM_THREADS", "a"), "OpenMP dynamic teams, OpenBLAS on 1 thread");
  EXPECT_EQ(setup("-u OMP_DYNAMIC OPENBLAS_NUM_THREADS=2", "b"), "OpenMP dynamic teams");
  EXPECT_EQ(setup("OMP_DYNAMIC=false OPENBLAS_NUM_THREADS=1", "c"), "");
}

// A cube whose top face is driven down (1 cm/s) while sliding along x (2 m/s) on a two-triangle
// mesh floor with friction 0.4, kappa 1e6 (helper 42's reproducer): the barrier carries the
// drive's growing load and the bottom slides at d ~ 1e-9 m. Additive CCD, capped at 1e5
// iterations, returned small fractions of such steps (0.18 at d0 = 1e-8 m and 5 mm of slide), the
// ballistic and rigid guesses were refused for them, and Newton failed at step 93 on its
// 100-iteration limit. With the separating-plane certificate every step converges (at most 27
// iterations, in 0.6 s).
TEST_F(CliSimulate, ACubePressedAndSlidingOnAMeshFloorEveryStepConverges) {
  write_file("floor.obj", rbaa::test::floor_obj(5));
  const std::string config = write_config(
      "press.yaml",
      "mesh: {shape: cube, target_tets: 300}\n"
      "object:\n"
      "  position: [-0.1, 0.0, 0.0265]\n"
      "  driven: {vertices: {toward: [0, 0, 1], depth: 1.0e-6}, velocity: [2.0, 0, -0.01],\n"
      "           angular_velocity: 0}\n"
      "obstacles: {planes: [], meshes: [{file: " + path("floor.obj") + "}]}\n"
      "gravity: off\n"
      "time: {step: 0.01, duration: 1.0}\n"
      "contact: {d_hat: 1.0e-3, kappa: 1.0e6, friction: 0.4}\n"
      "reference_material: {Y: 1.0e13, nu: 0.28, rho: 2500}\n");
  const Result r = run("simulate --config=" + config + " --vtu_every=0 --progress=false --out=" + path("press"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json report = Cli::report("press");
  EXPECT_EQ(report["steps"].get<int>(), 100);
  EXPECT_LE(report["newton"]["max_iterations_in_a_step"].get<int>(), 40);
  EXPECT_LT(report["min_contact_distance"].get<double>(), 1e-8);  // the regime it is about
  EXPECT_GT(report["min_contact_distance"].get<double>(), 0.0);
}

// Under OpenBLAS's OpenMP build rbaa leaves OpenMP's dynamic teams off: with them, and with
// OPENBLAS_NUM_THREADS set (so that rbaa leaves OpenBLAS's threads alone) on 2 OpenMP threads, the
// tiny ball's first factorisation spun in OpenBLAS's exec_blas for ever (killed after 60 s). Runs
// where Debian's libopenblas0-openmp is installed (scripts/install_deps.sh in CI), by pointing the
// loader at it; `timeout` turns a livelock into a failure.
TEST_F(CliSimulate, OpenblasOpenmpBuildFinishes) {
  std::string dir;
  for (const char* arch : {"x86_64-linux-gnu", "aarch64-linux-gnu"}) {
    const std::string d = std::string("/usr/lib/") + arch + "/openblas-openmp";
    if (std::filesystem::exists(d + "/libopenblas.so.0")) dir = d;
  }
  if (dir.empty()) GTEST_SKIP() << "OpenBLAS's OpenMP build is not installed (libopenblas0-openmp)";
  const std::string config = write_config("ball.yaml", kTinyBall);
  const std::string cmd = "env -u OMP_DYNAMIC OMP_NUM_THREADS=2 OPENBLAS_NUM_THREADS=1 LD_LIBRARY_PATH=" + dir +
                          " timeout 120 " + std::string(RBAA_EXECUTABLE) + " simulate --config=" + config +
                          " --vtu_every=0 --progress=false --out=" + path("omp") + " 2>/dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  EXPECT_EQ(report("omp")["timing"]["thread_setup"].get<std::string>(),
            "OpenMP dynamic teams left off (OpenBLAS's OpenMP build waits for whole teams)");
  // Without OPENBLAS_NUM_THREADS rbaa puts OpenBLAS on 1 thread, which in this build is
  // omp_set_num_threads(1): said, and seen in timing.threads.
  const std::string own = "env -u OMP_DYNAMIC -u OPENBLAS_NUM_THREADS OMP_NUM_THREADS=2 LD_LIBRARY_PATH=" + dir +
                          " timeout 120 " + std::string(RBAA_EXECUTABLE) + " simulate --config=" + config +
                          " --vtu_every=0 --progress=false --out=" + path("omp1") + " 2>/dev/null";
  ASSERT_EQ(std::system(own.c_str()), 0) << own;
  const nlohmann::json timing = report("omp1")["timing"];
  EXPECT_EQ(timing["thread_setup"].get<std::string>(),
            "OpenMP dynamic teams left off (OpenBLAS's OpenMP build waits for whole teams), OpenBLAS on 1 "
            "thread (its OpenMP build: rbaa's OpenMP loops too)");
  EXPECT_EQ(timing["threads"].get<int>(), 1);
  // The user's OMP_DYNAMIC stands, with a warning.
  const std::string dyn = "env OMP_DYNAMIC=true OMP_NUM_THREADS=1 LD_LIBRARY_PATH=" + dir + " timeout 120 " +
                          std::string(RBAA_EXECUTABLE) + " simulate --config=" + config +
                          " --vtu_every=0 --progress=false --out=" + path("omp2") + " 2>/dev/null";
  ASSERT_EQ(std::system(dyn.c_str()), 0) << dyn;
  EXPECT_NE(report("omp2")["timing"]["thread_setup"].get<std::string>().find(
                "warning: OMP_DYNAMIC turns dynamic teams on"),
            std::string::npos);
}

// object.position is the centre of mass (README): a materials file with non-uniform density moves
// the mesh so that the mass-weighted centre, not the volume centroid, starts there.
TEST_F(CliSimulate, MaterialsFileStartsTheCentreOfMassAtThePosition) {
  const std::string config = write_config("ball.yaml", kTinyBall);
  const rbaa::Scene scene = rbaa::parse_scene(kTinyBall, config, "");
  const rbaa::TetMesh mesh = rbaa::make_scene_mesh(scene);
  // Dense on the +x side, light on the -x side: the centroid is millimetres from the centre of
  // mass.
  rbaa::MaterialField f = rbaa::MaterialField::uniform(mesh.num_tets(), 1e10, 0.3, 2500);
  for (int e = 0; e < mesh.num_tets(); ++e) {
    double x = 0;
    for (int k = 0; k < 4; ++k) x += mesh.V(mesh.T(e, k), 0) / 4;
    f.rho[e] = x > scene.position.x() ? 11300 : 800;
  }
  const Eigen::Vector3d centroid_placed =
      rbaa::compute_moments(mesh, f.effective_density()).centre_of_mass();
  ASSERT_GT((centroid_placed - scene.position).norm(), 1e-3);
  rbaa::write_materials_csv(path("heavy_x.csv"), f);
  const Result r = run("simulate --config=" + config + " --materials=" + path("heavy_x.csv") +
                       " --vtu_every=0 --out=" + path("sim"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::istringstream csv(slurp(path("sim/trajectory.csv")));
  std::string header, first;
  std::getline(csv, header);
  std::getline(csv, first);
  std::replace(first.begin(), first.end(), ',', ' ');
  std::istringstream row(first);
  double step, time;
  Eigen::Vector3d com;
  row >> step >> time >> com.x() >> com.y() >> com.z();
  EXPECT_LT((com - scene.position).norm(), 1e-12 * scene.position.norm())
      << "centre of mass at t = 0: " << com.transpose();
}

// A cube thrown into the corner of a floor and a wall, tilted so that it touches both planes
// within one contact episode. Per plane, the centre of mass's normal velocity before and after
// such an episode is no bounce off that plane (it read restitutions of -0.32 on both planes);
// the report names the planes of a corner episode and gives no restitution, and every number it
// does give is -v_n,out / v_n,in of a one-plane contact whose normal velocity reversed.
TEST_F(CliSimulate, CornerContactIsReportedWithItsPlanesAndNoRestitution) {
  const std::string config =
      write_config("corner.yaml",
                   "mesh: {shape: cube, side: 0.05, target_tets: 300}\n"
                   "object: {position: [0, 0.04, 0.04], velocity: [0, -1, -1],\n"
                   "         rotation: {axis: [1, 0, 0], angle_deg: 35}}\n"
                   "obstacles:\n"
                   "  planes:\n"
                   "    - {normal: [0, 0, 1], offset: 0}\n"
                   "    - {normal: [0, 1, 0], offset: 0}\n"
                   "gravity: off\n"
                   "time: {step: 0.01, duration: 0.2}\n");
  const Result r = run("simulate --config=" + config + " --vtu_every=0 --out=" + path("corner"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = Cli::report("corner");
  ASSERT_FALSE(report["bounces"].empty());
  int corners = 0;
  for (const auto& b : report["bounces"]) {
    SCOPED_TRACE(b.dump());
    ASSERT_TRUE(b.contains("kind"));
    const std::string kind = b["kind"].get<std::string>();
    if (kind == "bounce") {
      ASSERT_EQ(b["planes"].size(), 1u);
      const double in_v = b["normal_velocity_in"][0].get<double>();
      const double out_v = b["normal_velocity_out"][0].get<double>();
      EXPECT_LT(in_v, 0.0);
      EXPECT_GT(out_v, 0.0);
      EXPECT_DOUBLE_EQ(b["restitution"].get<double>(), -out_v / in_v);
    } else {
      EXPECT_TRUE(b["restitution"].is_null());
      EXPECT_FALSE(b["note"].get<std::string>().empty());
    }
    if (kind == "corner") {
      ++corners;
      EXPECT_EQ(b["planes"], nlohmann::json::array({0, 1}));
      EXPECT_EQ(b["normal_velocity_in"].size(), 2u);
    }
  }
  EXPECT_GE(corners, 1);
  // The summary on stderr says the same: no restitution for a corner.
  EXPECT_NE(r.err.find("corner contact at t "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("no restitution: planes 0 and 1"), std::string::npos) << r.err;
}

// report.json says how often friction was re-lagged (contact.friction_iterations): never by
// default, and in the steps of the ball's contact with the wall when asked to.
TEST_F(CliSimulate, ReportCountsFrictionReLags) {
  const std::string config = write_config("ball.yaml", kTinyBall);
  for (int k : {1, 3}) {
    const std::string out = "relag" + std::to_string(k);
    const Result r = run("simulate --config=" + config + " --set=contact.friction=0.5" +
                         " --set=contact.friction_iterations=" + std::to_string(k) +
                         " --vtu_every=0 --out=" + path(out));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto newton = report(out)["newton"];
    EXPECT_EQ(newton["friction_iterations"], k);
    if (k == 1) {
      EXPECT_EQ(newton["friction_relags"], 0);
    } else {
      EXPECT_GE(newton["friction_relags"].get<int>(), 1);
      EXPECT_LE(newton["friction_relags"].get<int>(), 2 * 5);  // at most k - 1 per step
    }
  }
}

TEST_F(CliSimulate, BadInputGivesOneLineErrors) {
  const std::string config = write_config("ball.yaml", kTinyBall);
  std::ofstream(path("few.csv")) << "Y,nu,rho,alpha\n1e10,0.3,2500,1\n";
  expect_failure("simulate --config=" + config + " --materials=" + path("few.csv") + " --out=" + path("o"), "few.csv");
  const std::string touching = write_config(
      "touching.yaml", std::string(kTinyBall) + "contact: {d_hat: 0.05}\n");
  expect_failure("simulate --config=" + touching + " --out=" + path("o"), "touching");
  const std::string bad_h = write_config("bad_h.yaml", std::string(kTinyBall).replace(
      std::string(kTinyBall).find("step: 0.01"), 10, "step: -0.01"));
  expect_failure("simulate --config=" + bad_h + " --out=" + path("o"), "time.step");
  expect_failure("simulate --config=" + path("missing.yaml") + " --out=" + path("o"), "missing.yaml");
  expect_failure("simulate --config=" + config + " --set=time.stepp=1 --out=" + path("o"), "time.stepp");
  expect_failure("simulate --config=" + config + " --set=contact.friction_iterations=0 --out=" + path("o"),
                 "contact.friction_iterations");
  // Re-lagged friction is for forward runs: an attack refuses it before it simulates anything.
  expect_failure("attack --config=" + config + " --set=contact.friction_iterations=2 --out=" + path("a"),
                 "ball.yaml: contact.friction_iterations 2");
  expect_failure("attack --config=" + config + " --set=contact.friction_iterations=3 --out=" + path("a"),
                 "takes the lag at q_n (set 1)");
}

TEST_F(CliSimulate, EvaluateRejectsMissingAndMismatchedObjects) {
  const std::string config = write_config("ball.yaml", kTinyBall);
  expect_failure("evaluate --config=" + config + " --adversarial=" + path("none.msh") + " --out=" + path("e"),
                 "none.msh");
  // A mesh that is not the scene's object.
  ASSERT_EQ(run("mesh --shape=cube --target_tets=300 --out=" + path("cube.msh")).exit_code, 0);
  const rbaa::TetMesh cube = rbaa::read_tet_mesh(path("cube.msh")).mesh;
  rbaa::write_tet_mesh(path("cube_adv.msh"), cube,
                       rbaa::material_element_data(rbaa::MaterialField::uniform(cube.num_tets(), 1e10, 0.3, 2500)));
  expect_failure("evaluate --config=" + config + " --adversarial=" + path("cube_adv.msh") + " --out=" + path("e"),
                 "reference object");
  for (const char* step : {"fast", "-0.01", "0"}) {
    expect_failure("evaluate --config=" + config + " --adversarial=" + path("cube_adv.msh") + " --out=" + path("e") +
                       " --time_step=" + step,
                   std::string("--time_step=") + step);
  }
}

}  // namespace

namespace {

// Same seed and inputs give the same report apart from timing, and a run killed with SIGKILL and
// resumed from its checkpoint ends with the same result as an uninterrupted one.
TEST_F(CliSimulate, AttackKilledAndResumedEqualsUninterrupted) {
  const std::string config = write_config(
      "attack.yaml",
      "mesh: {shape: sphere, radius: 0.1, target_tets: 800}\n"
      "object: {position: [0, -0.16, 0.5], velocity: [2.0, 5.0, 0]}\n"
      "obstacles: {planes: [{normal: [0, -1, 0], offset: 0}]}\n"
      "gravity: off\n"
      "time: {step: 0.01, duration: 0.06}\n"
      "attack: {iterations: 12}\n");
  ASSERT_EQ(run("attack --config=" + config + " --out=" + path("straight")).exit_code, 0);
  ASSERT_EQ(run("attack --config=" + config + " --out=" + path("again")).exit_code, 0);
  EXPECT_EQ(report_without_timing("straight"), report_without_timing("again"));

  // Start a run in the background and kill it hard once a few iterations are checkpointed.
  const std::string cmd = std::string(RBAA_EXECUTABLE) + " attack --config=" + config + " --out=" + path("killed") +
                          " > /dev/null 2>&1 & echo $!";
  FILE* p = popen(cmd.c_str(), "r");
  int pid = 0;
  ASSERT_EQ(fscanf(p, "%d", &pid), 1);
  pclose(p);
  bool checkpointed = false;
  for (int i = 0; i < 600 && !checkpointed; ++i) {
    ::usleep(50000);
    std::ifstream cp(path("killed/checkpoint.json"));
    if (cp) {
      try {
        checkpointed = nlohmann::json::parse(cp)["iteration"].get<int>() >= 3;
      } catch (...) {
      }
    }
  }
  ::kill(pid, SIGKILL);
  ASSERT_TRUE(checkpointed) << "no checkpoint with 3 iterations appeared";
  EXPECT_FALSE(std::filesystem::exists(path("killed/report.json")));  // it really was interrupted
  // A resume may raise Newton's iteration limit (it changes no converged step); other
  // overrides make it another run.
  const Result resumed = run("attack --config=" + config + " --out=" + path("killed") +
                             " --resume --set=newton.max_iterations=300");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_EQ(report_without_timing("killed"), report_without_timing("straight"));
  // progress.csv too, but for its last column (wall time per iteration).
  auto without_seconds = [&](const std::string& file) {
    std::istringstream in(slurp(path(file)));
    std::string out;
    for (std::string line; std::getline(in, line);) out += line.substr(0, line.rfind(',')) + "\n";
    return out;
  };
  EXPECT_EQ(without_seconds("killed/progress.csv"), without_seconds("straight/progress.csv"));

  // A finished run may gain a polish stage on resume: the loop's 12 iterations are not repeated.
  const Result polished = run("attack --config=" + config + " --out=" + path("killed") +
                              " --resume --set=attack.polish_iterations=2");
  ASSERT_EQ(polished.exit_code, 0) << polished.err;
  {
    const auto j = report("killed");
    EXPECT_EQ(j["iterations"].get<int>(), 12);
    EXPECT_EQ(j["polish"]["iterations"].get<int>(), 2);
    EXPECT_EQ(j["gap"]["continuous"], report_without_timing("straight")["gap"]["continuous"]);
  }
  EXPECT_EQ(without_seconds("killed/progress.csv"), without_seconds("straight/progress.csv"));

  // The checkpoint belongs to the parsed settings, not to the config's bytes: the same scene with
  // a comment, in another file, resumes (and finds nothing left to do).
  const std::string commented = write_config("commented.yaml", "# the same scene, annotated\n" + slurp(config));
  const Result annotated = run("attack --config=" + commented + " --out=" + path("killed") +
                               " --resume --set=attack.polish_iterations=2");
  ASSERT_EQ(annotated.exit_code, 0) << annotated.err;
  EXPECT_EQ(without_seconds("killed/progress.csv"), without_seconds("straight/progress.csv"));

  // A checkpoint from another scene is refused with a clear error.
  const std::string other = write_config("other.yaml", slurp(config) + "contact: {d_hat: 0.002}\n");
  expect_failure("attack --config=" + other + " --out=" + path("killed") + " --resume", "checkpoint");
  expect_failure("attack --config=" + config + " --out=" + path("killed") + " --resume --set=time.step=0.005",
                 "checkpoint");
  expect_failure("attack --config=" + config + " --out=/proc/rbaa_cannot_write", "not writable");
}

// attack.start: best_uniform resumes exactly too: the checkpoint carries the loop's best design,
// which the result falls back to when the last is worse (learning rate 10 with the plain moment
// penalty overshoots at once on this scene, so the kept design is iteration 0's, measured before
// the interruption; the projected loop, which shortens steps that leave the moments, descends).
TEST_F(CliSimulate, BestUniformAttackResumedEqualsUninterrupted) {
  const std::string config = write_config(
      "best_uniform.yaml",
      "mesh: {shape: sphere, radius: 0.1, target_tets: 800}\n"
      "object: {position: [0, -0.16, 0.5], velocity: [2.0, 5.0, 0]}\n"
      "obstacles: {planes: [{normal: [0, -1, 0], offset: 0}]}\n"
      "gravity: off\n"
      "time: {step: 0.01, duration: 0.06}\n"
      "attack: {iterations: 6, learning_rate: 10, fields: [Y, nu, rho], start: best_uniform,\n"
      "         refinement_factor: 0, project_moments: false}\n");
  ASSERT_EQ(run("attack --config=" + config + " --out=" + path("bu_straight")).exit_code, 0);
  // Stopped after 3 iterations (a finished shorter run leaves the same checkpoint as a killed
  // one), then resumed to 6.
  ASSERT_EQ(run("attack --config=" + config + " --out=" + path("bu_resumed") + " --iterations=3").exit_code, 0);
  const Result resumed = run("attack --config=" + config + " --out=" + path("bu_resumed") + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  const nlohmann::json straight = report_without_timing("bu_straight");
  EXPECT_EQ(report_without_timing("bu_resumed"), straight);
  EXPECT_EQ(straight["start"]["kind"], "best_uniform");
  EXPECT_EQ(straight["start"]["candidates"].size(), 9u);
  EXPECT_EQ(straight["iterations"].get<int>(), 6);
  EXPECT_LT(straight["loop"]["kept_iteration"].get<int>(), 6);
  EXPECT_GE(straight["gap"]["continuous"].get<double>(), straight["gap"]["initial"].get<double>());
  EXPECT_NE(resumed.err.find("starting from the best uniform material"), std::string::npos) << resumed.err;
}

}  // namespace

namespace {

// Two small balls, the object rolling at a resting target on a floor with friction.
const char* const kTwoBalls =
    "mesh: {shape: sphere, radius: 0.05, target_tets: 150}\n"
    "object: {position: [0, 0, 0.0508], velocity: [2.0, 0, 0]}\n"
    "bodies:\n"
    "  - {name: target, mesh: {shape: sphere, radius: 0.06, target_tets: 150},\n"
    "     position: [0.13, 0.03, 0.0608]}\n"
    "obstacles: {planes: [{normal: [0, 0, 1], offset: 0, friction: 0.3}]}\n"
    "time: {step: 0.004, duration: 0.06}\n"
    "reference_material: {Y: 1.0e9, nu: 0.28, rho: 2500}\n";

TEST_F(CliSimulate, SeveralBodiesRunThroughSimulateAndGradcheck) {
  const std::string config = write_config("two_balls.yaml", kTwoBalls);
  const Result r = run("simulate --config=" + config + " --vtu_every=0 --out=" + path("two"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // The object's centre, then the target's, per step: the object hit the target and pushed it.
  std::ifstream csv(path("two/trajectory.csv"));
  std::string header, line, last;
  std::getline(csv, header);
  EXPECT_NE(header.find("target_com_x,target_com_y,target_com_z"), std::string::npos) << header;
  while (std::getline(csv, line)) last = line;
  std::vector<double> row;
  std::stringstream ss(last);
  for (std::string cell; std::getline(ss, cell, ',');) row.push_back(std::stod(cell));
  ASSERT_EQ(row.size(), 20u);
  EXPECT_GT(row[17], 0.13 + 0.01) << last;  // the target moved along +x
  // Gradients of one body's materials (--body: the attacked body, whose elements alone are the
  // design; the other keeps its material), by the exact tangent-linear check: central
  // differences of Y are noise here (see TwoBodyGradient).
  const Result g = run("gradcheck --config=" + config +
                       " --fields=Y --body=target --directions=1 --method=tangent");
  ASSERT_EQ(g.exit_code, 0) << g.err << g.out;
  EXPECT_NE(g.out.find("relative error"), std::string::npos) << g.out;
  EXPECT_NE(g.out.find("design on body 'target'"), std::string::npos) << g.out;
  expect_failure("gradcheck --config=" + config + " --body=ghost", "--body=ghost: the scene has no such body");
  // The directed objective on the struck ball, the design on the object: rho's central
  // differences agree with the adjoint within SPEC's bar through body-body contact. At Newton's
  // tolerance 1e-10 (default 1e-8): at the default the second direction's differences are
  // Newton's noise, which depends on the machine's rounding (relative error 1.4e-5 against 4.4e-6
  // at 4x the step on one AMD EPYC machine, within 1e-5 on another); at 1e-10, 3.4e-8.
  const Result d = run("gradcheck --config=" + config +
                       " --set='objective={body: target, kind: target, component: x, value: 0}'"
                       " --set=newton.tolerance=1e-10 --fields=rho --directions=2 --method=fd");
  ASSERT_EQ(d.exit_code, 0) << d.err << d.out;
  EXPECT_NE(d.out.find("design on body object"), std::string::npos) << d.out;
  EXPECT_NE(d.out.find("objective target on body 'target'"), std::string::npos) << d.out;
  EXPECT_NE(d.out.find("PASS: max relative error"), std::string::npos) << d.out;
  // Bodies that start overlapping are refused naming both.
  std::string text = kTwoBalls;
  text.replace(text.find("[0.13, 0.03, 0.0608]"), 20, "[0.05, 0.0, 0.0608]");
  const std::string overlap = write_config("overlap.yaml", text);
  expect_failure("simulate --config=" + overlap + " --out=" + path("o"), "body object and body 'target' start overlapping");
}

}  // namespace

namespace {

// rbaa attack designs the object among the further bodies, which keep their material, and scores
// the objective on any of them; rbaa study still refuses them (its measures are the object's
// alone), and rbaa evaluate evaluates an attack on another body in that body's place.
TEST_F(CliSimulate, AttackDesignsTheObjectAmongFurtherBodiesAndStudyRefusesThem) {
  const std::string config = write_config("two_balls.yaml", kTwoBalls);
  const Result a = run("attack --config=" + config + " --out=" + path("a") + " --iterations=2" +
                       " --set='objective={body: target, kind: target, component: x, value: 0}'");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const auto report = Cli::report("a");
  EXPECT_EQ(report["attacked_body"], "object");
  EXPECT_EQ(report["objective"]["kind"], "target");
  EXPECT_EQ(report["objective"]["body"], "target");
  EXPECT_EQ(report["score"]["component"], "x");
  // The target was struck: it ended ahead of where it started (x = 0.13).
  EXPECT_GT(report["score"]["centre_of_mass"]["reference"][0].get<double>(), 0.14) << report.dump();
  EXPECT_LT(report["moments"]["max_normalized_residual"].get<double>(), 1e-10);
  EXPECT_EQ(report["iterations"], 2);
  // The design is the object's alone: the written object has the object's elements.
  const Result object_only =
      run("simulate --config=" + config + " --vtu_every=0 --out=" + path("s"));
  ASSERT_EQ(object_only.exit_code, 0) << object_only.err;
  const auto sim = Cli::report("s");
  EXPECT_LT(report["mesh"]["tets"].get<int>(), sim["mesh"]["tets"].get<int>())
      << sim["mesh"].dump();

  expect_failure("study --config=" + config + " --out=" + path("st"),
                 "key 'bodies': rbaa study measures the object in a scene of its own");
  // An attack on the target designs the target; rbaa evaluate puts its object in the target's
  // place (and refuses the object's design there: another surface).
  const std::string on_target =
      write_config("on_target.yaml", std::string(kTwoBalls) + "attack: {body: target}\n");
  const Result t = run("attack --config=" + on_target + " --out=" + path("t") + " --iterations=2");
  ASSERT_EQ(t.exit_code, 0) << t.err;
  expect_failure("evaluate --config=" + on_target + " --adversarial=" + path("a/adversarial.msh") +
                     " --time_step=0.004 --duration=0.06 --out=" + path("e"),
                 "adversarial mesh: the adversarial object's bounding box differs");
  const Result e = run("evaluate --config=" + on_target + " --adversarial=" +
                       path("t/adversarial.msh") +
                       " --time_step=0.004 --duration=0.06 --soft_control=false --out=" + path("e"));
  ASSERT_EQ(e.exit_code, 0) << e.err;
  EXPECT_NE(e.err.find("(the attacked body 'target')"), std::string::npos) << e.err;
  const auto ev = Cli::report("e");
  EXPECT_EQ(ev["compared_body"], "target") << ev.dump();
  // Same surface and moments: the rigid twins agree.
  EXPECT_LT(ev["rigid_vs_rigid"]["max_com_gap_m"].get<double>(), 1e-9) << ev["rigid_vs_rigid"].dump();
  EXPECT_EQ(ev["rigid_identical"], true);
}

}  // namespace
