// The speed/accuracy study's pieces: material transfer between meshes, gradient comparison,
// the Pareto front, the CSV round trip, and a tiny study run on a coarse star.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "rbaa/io/msh.hpp"
#include "rbaa/io/materials_io.hpp"
#include "rbaa/opt/post_process.hpp"
#include "rbaa/scene/scene.hpp"
#include "rbaa/scene/scene_mesh.hpp"
#include "rbaa/sim/threads.hpp"
#include "rbaa/study/gradient_comparison.hpp"
#include "rbaa/study/material_transfer.hpp"
#include "rbaa/study/object_voids.hpp"
#include "rbaa/study/pareto.hpp"
#include "rbaa/study/trade_off_study.hpp"
#include "sim/mesh_fixtures.hpp"

namespace rbaa {
namespace {

Eigen::Vector3d centroid(const TetMesh& m, int e) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int a = 0; a < 4; ++a) c += m.V.row(m.T(e, a)).transpose();
  return c / 4.0;
}

// Piecewise constant on the coarse cells: 1 below x = 0.5, 2 above; 3 where also z > 0.75.
double piecewise(const Eigen::Vector3d& c) { return c.z() > 0.75 ? 3.0 : (c.x() < 0.5 ? 1.0 : 2.0); }

TEST(MaterialTransfer, PreservesAPiecewiseConstantFieldWhereTheMeshesOverlap) {
  const TetMesh coarse = test::box_mesh(4, 4, 4, 0.25);
  const TetMesh fine = test::box_mesh(8, 8, 8, 0.125);
  MaterialField field = MaterialField::uniform(coarse.num_tets(), 1e10, 0.3, 2500);
  for (int e = 0; e < coarse.num_tets(); ++e) field.Y[e] = 1e10 * piecewise(centroid(coarse, e));
  const MaterialField moved = transfer_materials(coarse, field, fine);
  ASSERT_EQ(moved.size(), fine.num_tets());
  for (int e = 0; e < fine.num_tets(); ++e) {
    EXPECT_EQ(moved.Y[e], 1e10 * piecewise(centroid(fine, e))) << "element " << e;
    EXPECT_EQ(moved.nu[e], 0.3);
    EXPECT_EQ(moved.rho[e], 2500);
    EXPECT_EQ(moved.alpha[e], 1.0);
  }
}

TEST(MaterialTransfer, LocatesPointsAndFallsBackToTheNearestElementOutside) {
  const TetMesh mesh = test::box_mesh(3, 3, 3, 1.0);
  const ElementLocator locator(mesh);
  for (int e = 0; e < mesh.num_tets(); e += 7) EXPECT_EQ(locator.containing(centroid(mesh, e)), e);
  EXPECT_EQ(locator.containing(Eigen::Vector3d(5, 5, 5)), -1);
  const int near = locator.containing_or_nearest(Eigen::Vector3d(3.2, 3.2, 3.2));
  ASSERT_GE(near, 0);
  EXPECT_GT(centroid(mesh, near).minCoeff(), 2.0);  // a corner element
  // A mesh onto itself is the identity.
  const std::vector<int> self = centroid_lookup(mesh, mesh);
  for (int e = 0; e < mesh.num_tets(); ++e) EXPECT_EQ(self[e], e);
}

TEST(GradientComparison, CosineOfIdenticalGradientsIsOneAndOfOppositeMinusOne) {
  const TetMesh mesh = test::box_mesh(3, 2, 2, 0.5);
  const int nt = mesh.num_tets();
  MaterialGradient g;
  g.Y = Eigen::VectorXd::Random(nt) * 1e-12;
  g.nu = Eigen::VectorXd::Random(nt);
  g.rho = Eigen::VectorXd::Random(nt) * 1e-4;
  g.alpha = Eigen::VectorXd::Random(nt);
  const Eigen::Vector4d half(3e11, 0.1, 5000, 0.5);
  const std::vector<std::string> fields{"Y", "nu", "rho", "alpha"};
  const Eigen::MatrixXd d = gradient_density(mesh, g, half, fields);
  EXPECT_NEAR(gradient_cosine(d, d, tet_volumes(mesh)), 1.0, 1e-15);
  EXPECT_NEAR(gradient_cosine(d, -d, tet_volumes(mesh)), -1.0, 1e-15);
  EXPECT_NEAR(gradient_cosine_across(mesh, d, mesh, d), 1.0, 1e-15);
  // A field left out of `fields` is zero in the density.
  const Eigen::MatrixXd no_alpha = gradient_density(mesh, g, half, {"Y", "nu", "rho"});
  EXPECT_EQ(no_alpha.col(3).norm(), 0.0);
}

TEST(GradientComparison, AConstantDensityAgreesAcrossResolutions) {
  const TetMesh coarse = test::box_mesh(2, 2, 2, 0.5), fine = test::box_mesh(4, 4, 4, 0.25);
  // Extensive gradients of one constant density: dC/dx_e = V_e * const.
  MaterialGradient gc, gf;
  gc.Y = tet_volumes(coarse) * 2.0;
  gf.Y = tet_volumes(fine) * 2.0;
  const Eigen::Vector4d half(1, 1, 1, 1);
  const Eigen::MatrixXd dc = gradient_density(coarse, gc, half, {"Y"});
  const Eigen::MatrixXd df = gradient_density(fine, gf, half, {"Y"});
  EXPECT_NEAR(gradient_cosine_across(coarse, dc, fine, df), 1.0, 1e-14);
}

TEST(Pareto, KeepsExactlyTheNonDominatedPoints) {
  const std::vector<CostError> pts = {{1, 10}, {2, 5}, {3, 7}, {4, 1}, {2, 5}, {0.5, 20},
                                      {5, 1}, {std::nan(""), 0}, {6, 0.5}};
  const std::vector<int> front = pareto_front(pts);
  EXPECT_EQ(front, (std::vector<int>{5, 0, 1, 3, 8}));
  EXPECT_TRUE(pareto_front({}).empty());
}

TEST(StudyCsv, RoundTripsEveryField) {
  StudyPoint p;
  p.sweep = "time_step";
  p.label = "h=0.005";
  p.is_config = true;
  p.time_step = 1.0 / 30;
  p.steps = 9;
  p.tets = 1506;
  p.integrator = "bdf2";
  p.mass = "consistent";
  p.storage = "store";
  p.newton_tolerance = 1e-8;
  p.newton_iterations = 53;
  p.forward_seconds = 0.123456789012345;
  p.gradient_seconds = 0.2;
  p.forward_cpu_seconds = 0.25;
  p.gradient_cpu_seconds = 1.0 / 3;
  p.com_error = 1.2345678901234567e-5;
  p.orientation_error_deg = 0.01;
  p.gradient_cosine = 0.999999;
  p.pareto = true;
  p.note = "a, note";
  StudyPoint q = p;
  q.is_config = false;
  q.is_reference = true;
  q.pareto = false;
  q.note = "";
  const std::string path = (std::filesystem::temp_directory_path() / "rbaa_study_roundtrip.csv").string();
  write_study_csv(path, {p, q});
  const std::vector<StudyPoint> back = read_study_csv(path);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].sweep, p.sweep);
  EXPECT_EQ(back[0].label, p.label);
  EXPECT_EQ(back[0].is_config, true);
  EXPECT_EQ(back[0].time_step, p.time_step);
  EXPECT_EQ(back[0].steps, 9);
  EXPECT_EQ(back[0].tets, 1506);
  EXPECT_EQ(back[0].integrator, "bdf2");
  EXPECT_EQ(back[0].mass, "consistent");
  EXPECT_EQ(back[0].storage, "store");
  EXPECT_EQ(back[0].newton_tolerance, 1e-8);
  EXPECT_EQ(back[0].newton_iterations, 53);
  EXPECT_EQ(back[0].forward_seconds, p.forward_seconds);
  EXPECT_EQ(back[0].gradient_seconds, p.gradient_seconds);
  EXPECT_EQ(back[0].forward_cpu_seconds, p.forward_cpu_seconds);
  EXPECT_EQ(back[0].gradient_cpu_seconds, p.gradient_cpu_seconds);
  EXPECT_EQ(back[0].orientation_error_deg, p.orientation_error_deg);
  EXPECT_EQ(back[0].com_error, p.com_error);
  EXPECT_EQ(back[0].gradient_cosine, p.gradient_cosine);
  EXPECT_TRUE(back[0].pareto);
  EXPECT_EQ(back[0].note, "a; note");  // commas cannot live inside a field
  EXPECT_TRUE(back[1].is_reference);
  EXPECT_FALSE(back[1].pareto);
  EXPECT_EQ(back[1].note, "");
  std::filesystem::remove(path);
}

TEST(Study, ATinyStudyOfACoarseStarRunsEverySweepAndTheSurvivalCheck) {
  set_simulation_threads(2);
  const Scene scene = load_scene(std::string(RBAA_SOURCE_DIR) + "/configs/star.yaml",
                                 {"mesh.target_tets=700", "time.duration=0.2"});
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "rbaa_study_tiny";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  // An adversarial star: the config mesh with a softer, denser half.
  const TetMesh mesh = make_scene_mesh(scene);
  MaterialField adv = MaterialField::uniform(mesh.num_tets(), 6e11, 0.3, 2500);
  for (int e = 0; e < mesh.num_tets(); ++e) {
    if (centroid(mesh, e).z() > scene.position.z()) adv.Y[e] = 5e9;
  }
  const std::string adv_file = (dir / "adversarial.msh").string();
  write_msh(adv_file, mesh, material_element_data(adv));

  StudyOptions options;
  options.reference_time_divisor = 2;
  options.timing_repeats = 1;
  options.time_steps = {0.02};
  options.mesh_factors = {0.9, 1.4};
  options.newton_tolerances = {1e-6};
  options.adversarial_file = adv_file;
  const StudyResult r = run_study(scene, options);

  int per_sweep[6] = {0, 0, 0, 0, 0, 0};
  const char* sweeps[6] = {"time_step", "mesh", "integrator", "mass", "newton_tolerance", "factor_storage"};
  bool any_pareto = false;
  for (const StudyPoint& p : r.points) {
    for (int s = 0; s < 6; ++s) per_sweep[s] += p.sweep == sweeps[s];
    EXPECT_TRUE(std::isfinite(p.com_error)) << p.label;
    EXPECT_GE(p.gradient_cosine, -1.0 - 1e-12) << p.label;
    EXPECT_LE(p.gradient_cosine, 1.0 + 1e-12) << p.label;
    EXPECT_GT(p.forward_seconds, 0) << p.label;
    if (p.is_reference) {
      EXPECT_EQ(p.com_error, 0.0) << p.label;
      EXPECT_NEAR(p.gradient_cosine, 1.0, 1e-12) << p.label;
    }
    any_pareto = any_pareto || p.pareto;
  }
  EXPECT_EQ(per_sweep[0], 3);  // 0.02, the config (1/30), the reference (h/2)
  EXPECT_EQ(per_sweep[1], 3);
  EXPECT_EQ(per_sweep[2], 2);
  EXPECT_EQ(per_sweep[3], 2);
  EXPECT_EQ(per_sweep[4], 2);
  EXPECT_EQ(per_sweep[5], 2);
  EXPECT_TRUE(any_pareto);
  // Stored and rebuilt factors give the same gradient.
  std::vector<double> storage_cosines;
  for (const StudyPoint& p : r.points) {
    if (p.sweep == "factor_storage") storage_cosines.push_back(p.gradient_cosine);
  }
  ASSERT_EQ(storage_cosines.size(), 2u);
  EXPECT_NEAR(storage_cosines[0], storage_cosines[1], 1e-9);
  // The survival check: h, h/4, h/16 and the finer mesh (the star has no voids).
  ASSERT_EQ(r.survival.size(), 4u) << r.survival_note;
  for (const SurvivalPoint& s : r.survival) {
    EXPECT_TRUE(std::isfinite(s.gap));
    EXPECT_GT(s.gap, 0.0);  // a soft half moves differently
  }
  EXPECT_LT(r.survival[0].moment_residual, 1e-12);  // same density everywhere: same moments
  EXPECT_GT(r.survival[3].tets, mesh.num_tets());
  EXPECT_TRUE(r.survival_note.empty()) << r.survival_note;  // the config's own mesh, no voids

  write_study_outputs(r, dir.string());
  for (const char* f : {"study.csv", "study.md", "pareto.gp", "survival.csv"}) {
    EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
  }
  EXPECT_EQ(read_study_csv((dir / "study.csv").string()).size(), r.points.size());
  std::filesystem::remove_all(dir);
}

// An attack's object is its mesh without the emptied elements; an interior one gone leaves an
// inner surface. Whether that mesh is the config's is told apart from whether it has voids.
TEST(ObjectVoids, AreToldFromAlphaRemovedElementsAndInnerSurfacesNotFromTheTetCount) {
  const TetMesh config = test::box_mesh(4, 4, 4, 0.25);
  const MaterialField solid = MaterialField::uniform(config.num_tets(), 1e10, 0.3, 2500);
  EXPECT_EQ(boundary_surface_pieces(config), 1);
  ObjectVoids v = find_object_voids(config, solid, config);
  EXPECT_TRUE(v.part_of_config);
  EXPECT_FALSE(v.any()) << v.describe();

  // The same mesh, one element half full.
  MaterialField partial = solid;
  partial.alpha[7] = 0.5;
  v = find_object_voids(config, partial, config);
  EXPECT_EQ(v.partial_elements, 1);
  EXPECT_EQ(v.describe(), "1 element with alpha < 1");

  // The config mesh with the 6 tets of an interior cube (cell 1, 1, 1) cut out, as
  // remove_void_elements does: a cavity.
  MaterialField emptied = solid;
  int cut = 0;
  for (int e = 0; e < config.num_tets(); ++e) {
    if ((centroid(config, e) / 0.25).cast<int>() == Eigen::Vector3i(1, 1, 1)) {
      emptied.alpha[e] = 0;
      ++cut;
    }
  }
  ASSERT_EQ(cut, 6);
  const SolidObject object = remove_void_elements(config, emptied);
  EXPECT_EQ(boundary_surface_pieces(object.mesh), 2);
  v = find_object_voids(object.mesh, object.materials, config);
  EXPECT_TRUE(v.part_of_config);
  EXPECT_EQ(v.removed_elements, 6);
  EXPECT_EQ(v.inner_surfaces, 1);
  EXPECT_EQ(v.describe(), "6 elements of the config's mesh removed, 1 inner surface");

  // Another mesh of the same box (an attack at another mesh.target_tets): no voids, but not the
  // config's; with its own interior cube cut out, the inner surface tells the void.
  const TetMesh other = test::box_mesh(5, 5, 5, 0.2);
  const MaterialField other_solid = MaterialField::uniform(other.num_tets(), 1e10, 0.3, 2500);
  v = find_object_voids(other, other_solid, config);
  EXPECT_FALSE(v.part_of_config);
  EXPECT_FALSE(v.any()) << v.describe();
  MaterialField other_emptied = other_solid;
  for (int e = 0; e < other.num_tets(); ++e) {
    if ((centroid(other, e) / 0.2).cast<int>() == Eigen::Vector3i(2, 2, 2)) {
      other_emptied.alpha[e] = 0;
    }
  }
  const SolidObject other_object = remove_void_elements(other, other_emptied);
  v = find_object_voids(other_object.mesh, other_object.materials, config);
  EXPECT_FALSE(v.part_of_config);
  EXPECT_EQ(v.removed_elements, 0);  // not countable on another mesh
  EXPECT_EQ(v.inner_surfaces, 1);
  EXPECT_TRUE(v.any());
}

// An attack run at another mesh.target_tets than the study's config has another tet count but no
// voids: the study took that count for voids ("has voids (elements removed or alpha < 1)") and
// skipped the refined-mesh check. Now the check runs and a note says the meshes differ.
TEST(Study, AnAdversarialObjectOnAnotherMeshIsCheckedOnTheFinerMeshAndSaidToDiffer) {
  set_simulation_threads(2);
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "rbaa_study_other_mesh";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string config = (dir / "ball.yaml").string();
  // The tiny ball of the CLI tests: 300 tets, five steps of 0.01 s against a wall.
  std::ofstream(config) << "mesh: {shape: sphere, radius: 0.1, target_tets: 300}\n"
                           "object: {position: [0, -0.13, 0.5], velocity: [0, 2.0, 0]}\n"
                           "obstacles: {planes: [{normal: [0, -1, 0], offset: 0}]}\n"
                           "gravity: off\n"
                           "time: {step: 0.01, duration: 0.05}\n";
  const Scene scene = load_scene(config, {});
  const TetMesh mesh = make_scene_mesh(load_scene(config, {"mesh.target_tets=200"}));
  ASSERT_NE(mesh.num_tets(), make_scene_mesh(scene).num_tets());
  MaterialField adv = MaterialField::uniform(mesh.num_tets(), 1e10, 0.3, 2500);
  for (int e = 0; e < mesh.num_tets(); ++e) {
    if (centroid(mesh, e).z() > scene.position.z()) adv.Y[e] = 1e8;
  }
  const std::string adv_file = (dir / "adversarial.msh").string();
  write_msh(adv_file, mesh, material_element_data(adv));

  StudyOptions options;
  options.reference_time_divisor = 2;
  options.timing_repeats = 1;
  options.time_steps = {0.01};
  options.mesh_factors = {1.5};
  options.newton_tolerances = {1e-8};
  options.adversarial_file = adv_file;
  const StudyResult r = run_study(scene, options);
  ASSERT_EQ(r.survival.size(), 4u) << r.survival_note;
  EXPECT_NE(r.survival[3].label.find("materials transferred"), std::string::npos);
  EXPECT_EQ(r.survival_note.find("voids"), std::string::npos) << r.survival_note;
  EXPECT_NE(r.survival_note.find("adversarial object's mesh (" + std::to_string(mesh.num_tets()) +
                                 " tets) is not the config's"),
            std::string::npos)
      << r.survival_note;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace rbaa
