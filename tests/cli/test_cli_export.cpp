// rbaa export --format=polyfem: the files it writes agree with each other and with the scene.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli/cli_fixture.hpp"
#include "io/io_test_support.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/io/msh.hpp"
#include "rbaa/io/tet_mesh_file.hpp"
#include "rbaa/io/triangle_soup.hpp"
#include "rbaa/scene/scene.hpp"
#include "rbaa/scene/scene_mesh.hpp"

namespace {

using rbaa_cli_test::Cli;

std::vector<double> read_values(const std::string& file) {
  std::vector<double> values;
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);) values.push_back(std::stod(line));
  return values;
}

nlohmann::json read_json(const std::string& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

const std::string kBall =
    "--config=" RBAA_SOURCE_DIR "/configs/ball.yaml --set=mesh.target_tets=300 ";

TEST_F(Cli, ExportPolyfemBallFilesAgree) {
  const std::string out = path("ball");
  const auto r = run("export --format=polyfem " + kBall + "--out=" + out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json scene = read_json(out + "/scene.json");

  // The body: one Gmsh 2.2 tet mesh, one value per element in each material file.
  ASSERT_EQ(scene["geometry"].size(), 2u);
  const nlohmann::json& body = scene["geometry"][0];
  const std::string msh = out + "/" + body["mesh"].get<std::string>();
  EXPECT_EQ(Cli::slurp(msh).rfind("$MeshFormat\n2.2 0 8\n", 0), 0u);
  const rbaa::TetMeshFile file = rbaa::read_msh(msh);
  EXPECT_GT(file.mesh.num_tets(), 200);
  EXPECT_EQ(body["volume_selection"], 1);
  EXPECT_FALSE(body.contains("is_obstacle"));
  const nlohmann::json& material = scene["materials"];
  EXPECT_EQ(material["type"], "NeoHookean");
  for (const char* key : {"E", "nu", "rho"}) {
    const std::string values_file = out + "/" + material[key].get<std::string>();
    ASSERT_TRUE(std::filesystem::is_regular_file(values_file)) << key;
    const std::vector<double> values = read_values(values_file);
    ASSERT_EQ(static_cast<int>(values.size()), file.mesh.num_tets()) << key;
    const double expected = std::string(key) == "E" ? 1e13 : std::string(key) == "nu" ? 0.28 : 2500;
    for (double v : values) ASSERT_EQ(v, expected) << key;  // the uniform reference material
  }

  // The backboard: a square of two triangles in y = 0 with normal -y, an obstacle.
  const nlohmann::json& plane = scene["geometry"][1];
  EXPECT_EQ(plane["is_obstacle"], true);
  const rbaa::SurfaceMesh square =
      rbaa::read_triangle_soup(out + "/" + plane["mesh"].get<std::string>());
  ASSERT_EQ(square.F.rows(), 2);
  for (int v = 0; v < square.V.rows(); ++v) EXPECT_EQ(square.V(v, 1), 0.0);
  for (int f = 0; f < 2; ++f) {
    const Eigen::Vector3d a = square.V.row(square.F(f, 0)), b = square.V.row(square.F(f, 1)),
                          c = square.V.row(square.F(f, 2));
    const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    EXPECT_NEAR(n.y(), -1.0, 1e-15);
  }
  // It covers the ball's whole flight (centre, 0.25 s at ~5.4 m/s, radius): a few metres.
  const double side = (square.V.colwise().maxCoeff() - square.V.colwise().minCoeff()).maxCoeff();
  EXPECT_GT(side, 4.0);

  // Gravity as rhs = -g, BDF2, h, T, d_hat, friction 0, Newton's gradient tolerance.
  EXPECT_EQ(scene["boundary_conditions"]["rhs"], nlohmann::json({0.0, 0.0, 9.8}));
  EXPECT_FALSE(scene["boundary_conditions"].contains("dirichlet_boundary"));
  EXPECT_EQ(scene["time"]["integrator"]["type"], "BDF");
  EXPECT_EQ(scene["time"]["integrator"]["steps"], 2);
  EXPECT_EQ(scene["time"]["dt"], 0.01);
  EXPECT_EQ(scene["time"]["time_steps"], 25);
  EXPECT_FALSE(scene["time"].contains("tend"));  // PolyFEM takes exactly two of the three
  EXPECT_EQ(scene["contact"]["enabled"], true);
  EXPECT_EQ(scene["contact"]["dhat"], 1e-3);
  EXPECT_EQ(scene["contact"]["friction_coefficient"], 0.0);
  EXPECT_EQ(scene["solver"]["nonlinear"]["grad_norm_tol"], 1e-5);
  // Friction lagged as rbaa lags it: once per step unless the scene says otherwise.
  EXPECT_EQ(scene["solver"]["contact"]["friction_iterations"], 1);
  const nlohmann::json& velocity = scene["initial_conditions"]["velocity"];
  ASSERT_EQ(velocity.size(), 1u);
  EXPECT_EQ(velocity[0]["id"], 1);
  EXPECT_EQ(velocity[0]["value"].size(), 3u);

  const std::string relagged = path("ball_relagged");
  const auto r3 = run("export --format=polyfem " + kBall +
                      "--set=contact.friction_iterations=3 --out=" + relagged);
  ASSERT_EQ(r3.exit_code, 0) << r3.err;
  EXPECT_EQ(read_json(relagged + "/scene.json")["solver"]["contact"]["friction_iterations"], 3);

  // PolyFEM runs as many steps as rbaa, round(T / h), where tend and dt would give ceil(T / h):
  // 0.07 / 0.005 = 14.000000000000002, 14 steps in rbaa, 15 from ceil.
  const std::string uneven = path("ball_uneven");
  const auto r4 = run("export --format=polyfem " + kBall +
                      "--set=time.step=0.005 --set=time.duration=0.07 --out=" + uneven);
  ASSERT_EQ(r4.exit_code, 0) << r4.err;
  ASSERT_GT(0.07 / 0.005, 14.0);
  const nlohmann::json time = read_json(uneven + "/scene.json")["time"];
  EXPECT_EQ(time["time_steps"], 14);
  EXPECT_EQ(time["dt"], 0.005);
}

TEST_F(Cli, ExportPolyfemMeshRoundTrip) {
  const std::string out = path("ball");
  ASSERT_EQ(run("export --format=polyfem " + kBall + "--out=" + out).exit_code, 0);
  const rbaa::TetMesh exported = rbaa::read_msh(out + "/object.msh").mesh;
  const rbaa::Scene scene =
      rbaa::load_scene(RBAA_SOURCE_DIR "/configs/ball.yaml", {"mesh.target_tets=300"});
  const rbaa::TetMesh placed = rbaa::make_scene_mesh(scene);
  ASSERT_EQ(exported.num_vertices(), placed.num_vertices());
  ASSERT_EQ(exported.T, placed.T);
  const double scale = placed.V.cwiseAbs().maxCoeff();
  EXPECT_LE((exported.V - placed.V).cwiseAbs().maxCoeff(), 1e-12 * scale);
}

// A jittered cube (48 tets) as an adversarial object: seven void elements (alpha 0, and 0.3 < 0.5;
// all six of the first cell, so its corner vertex goes too), one partly occupied (0.75), the rest
// solid with varied materials.
TEST_F(Cli, ExportPolyfemAdversarialDropsVoid) {
  rbaa::TetMesh cube = rbaa::test::make_jittered_cube(2);
  const int nt = cube.num_tets();
  rbaa::ElementData data;
  data["Y"] = Eigen::VectorXd::LinSpaced(nt, 3e9, 6e11);
  data["nu"] = Eigen::VectorXd::LinSpaced(nt, 0.21, 0.39);
  data["rho"] = Eigen::VectorXd::LinSpaced(nt, 900, 11000);
  data["alpha"] = Eigen::VectorXd::Ones(nt);
  const std::vector<int> void_elements{0, 1, 2, 3, 4, 5, 17};
  for (int e : void_elements) data["alpha"][e] = 0.0;
  data["alpha"][17] = 0.3;
  data["alpha"][30] = 0.75;
  // The scene's object is the same cube; its position is where the centre of mass goes. The
  // adversarial object is the cube where the scene places it, as an attack writes it.
  rbaa::write_tet_mesh(path("cube.msh"), cube, {});
  const std::string config =
      write_file("cube.yaml",
                 "mesh: {file: cube.msh}\nobject: {position: [0.3, 0.2, 0.5], velocity: [1, 0, 0],"
                 " angular_velocity: [0, 0, 2]}\ngravity: off\ncontact: {kappa: 1}\n"
                 "time: {step: 0.001, duration: 0.01}\n");
  const std::string mesh_file = path("cube_adversarial.msh");
  rbaa::write_tet_mesh(path("cube_elsewhere.msh"), cube, data);
  cube = rbaa::make_scene_mesh(rbaa::load_scene(config));
  rbaa::write_tet_mesh(mesh_file, cube, data);
  const std::string out = path("adv");
  const auto r = run("export --format=polyfem --config=" + config + " --adversarial=" + mesh_file +
                     " --out=" + out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // The same object where its file put it, not the scene's pose, is another scene's (as rbaa
  // evaluate says): the export used to place it anyway.
  const auto elsewhere = run("export --format=polyfem --config=" + config + " --adversarial=" +
                             path("cube_elsewhere.msh") + " --out=" + path("adv_elsewhere"));
  EXPECT_EQ(elsewhere.exit_code, 2);
  EXPECT_NE(elsewhere.err.find("cube_elsewhere.msh: the adversarial object's bounding box differs"),
            std::string::npos)
      << elsewhere.err;
  EXPECT_EQ(std::count(elsewhere.err.begin(), elsewhere.err.end(), '\n'), 1) << elsewhere.err;
  EXPECT_NE(r.err.find("7 void elements"), std::string::npos) << r.err;

  const rbaa::TetMesh exported = rbaa::read_msh(out + "/object.msh").mesh;
  ASSERT_EQ(exported.num_tets(), nt - 7);
  std::vector<int> kept;
  for (int e = 0; e < nt; ++e) {
    if (std::find(void_elements.begin(), void_elements.end(), e) == void_elements.end())
      kept.push_back(e);
  }
  // Vertices only the void elements used are gone; the rest keep their order, moved rigidly.
  std::vector<int> used(cube.num_vertices(), 0);
  for (int e : kept) {
    for (int c = 0; c < 4; ++c) used[cube.T(e, c)] = 1;
  }
  std::vector<int> old_of_new;
  for (int v = 0; v < cube.num_vertices(); ++v) {
    if (used[v]) old_of_new.push_back(v);
  }
  ASSERT_LT(static_cast<int>(old_of_new.size()), cube.num_vertices());
  ASSERT_EQ(exported.num_vertices(), static_cast<int>(old_of_new.size()));
  const Eigen::RowVector3d shift = exported.V.row(0) - cube.V.row(old_of_new[0]);
  for (int i = 0; i < exported.num_vertices(); ++i) {
    EXPECT_LE((exported.V.row(i) - cube.V.row(old_of_new[i]) - shift).cwiseAbs().maxCoeff(), 1e-15);
  }
  for (int i = 0; i < exported.num_tets(); ++i) {
    for (int c = 0; c < 4; ++c) EXPECT_EQ(old_of_new[exported.T(i, c)], cube.T(kept[i], c));
  }

  const std::vector<double> E = read_values(out + "/E.txt"), nu = read_values(out + "/nu.txt"),
                            rho = read_values(out + "/rho.txt");
  ASSERT_EQ(E.size(), kept.size());
  ASSERT_EQ(nu.size(), kept.size());
  ASSERT_EQ(rho.size(), kept.size());
  for (std::size_t i = 0; i < kept.size(); ++i) {
    const double a = data["alpha"][kept[i]];
    EXPECT_EQ(E[i], data["Y"][kept[i]] * (a * a * a)) << i;
    EXPECT_EQ(nu[i], data["nu"][kept[i]]) << i;
    EXPECT_EQ(rho[i], data["rho"][kept[i]] * a) << i;
    EXPECT_GE(E[i], 0.4 * 3e9);
    EXPECT_LE(E[i], 6e11);
  }
  // No planes, no obstacles, no gravity; the spin about z in the velocity field.
  const nlohmann::json scene = read_json(out + "/scene.json");
  EXPECT_EQ(scene["geometry"].size(), 1u);
  EXPECT_EQ(scene["boundary_conditions"]["rhs"], nlohmann::json({0.0, 0.0, 0.0}));
  // The exported object's centre of mass (its own rho per element) is object.position.
  const Eigen::Vector3d position(0.3, 0.2, 0.5);
  const Eigen::Vector3d centre =
      rbaa::compute_moments(exported, Eigen::Map<const Eigen::VectorXd>(rho.data(), rho.size()))
          .centre_of_mass();
  EXPECT_LE((centre - position).norm(), 1e-12) << centre.transpose();

  // So is a uniform object's, whose kept elements have one density: without its void elements
  // its centre of mass is not the whole cube's, which the scene placed.
  rbaa::ElementData uniform = data;
  uniform["Y"].setConstant(1e10);
  uniform["nu"].setConstant(0.3);
  uniform["rho"].setConstant(2500);
  uniform["alpha"].setOnes();
  for (int e : void_elements) uniform["alpha"][e] = 0.0;
  const std::string uniform_file = path("cube_uniform.msh");
  rbaa::write_tet_mesh(uniform_file, cube, uniform);
  const std::string uniform_out = path("adv_uniform");
  const auto u = run("export --format=polyfem --config=" + config + " --adversarial=" +
                     uniform_file + " --out=" + uniform_out);
  ASSERT_EQ(u.exit_code, 0) << u.err;
  const rbaa::TetMesh uniform_exported = rbaa::read_msh(uniform_out + "/object.msh").mesh;
  ASSERT_EQ(uniform_exported.num_tets(), nt - 7);
  const Eigen::Vector3d uniform_centre =
      rbaa::compute_moments(uniform_exported, 2500.0).centre_of_mass();
  EXPECT_LE((uniform_centre - position).norm(), 1e-12) << uniform_centre.transpose();
}

TEST_F(Cli, ExportPolyfemBadInput) {
  expect_failure("export --format=abaqus " + kBall + "--out=" + path("x"),
                 "unknown format 'abaqus'");
  expect_failure("export --format=polyfem " + kBall, "--out is required");
  expect_failure("export --format=polyfem " + kBall + "--adversarial=" + path("missing.msh") +
                     " --out=" + path("x"),
                 "no such file");
  // An adversarial mesh without materials.
  rbaa::write_tet_mesh(path("bare.msh"), rbaa::test::make_jittered_cube(1));
  expect_failure("export --format=polyfem " + kBall + "--adversarial=" + path("bare.msh") +
                     " --out=" + path("x"),
                 "no element data 'Y'");
  // PolyFEM has one friction coefficient: a floor with 0.3 and bodies with 0 is refused.
  expect_failure("export --format=polyfem --config=" RBAA_SOURCE_DIR
                 "/configs/two_balls.yaml --set=mesh.target_tets=300 --out=" +
                     path("x"),
                 "one friction coefficient");
  EXPECT_FALSE(std::filesystem::exists(path("x") + "/scene.json"));
}

TEST_F(Cli, ExportPolyfemHelpNamesTheFormat) {
  const auto r = run("export --help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("--format=polyfem"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("PolyFEM_bin -j"), std::string::npos) << r.out;
}

}  // namespace
