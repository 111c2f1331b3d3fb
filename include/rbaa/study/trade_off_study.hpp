#pragma once
// `rbaa study` as a library call: the speed/accuracy trade-off of the simulator and its gradient
// around a scene's config (SPEC section 10). One factor is swept at a time, the others staying at
// the config's values:
//
//   time step   h from 1/30 down (to 1e-4 with --full), each rounded so that T / h is an integer
//   mesh        about 0.25x .. 2x (4x with --full) the config's tet count, none below 50 tets
//   integrator  BDF-1, BDF-2          mass  lumped, consistent
//   Newton tolerance                  factor storage  store, rebuild (same numbers, other time)
//
// Every point measures the wall time of a forward run of the reference object (uniform
// reference material) and of a gradient (forward + adjoint of the undirected attack's trajectory
// term at the attack's unperturbed starting design), and its accuracy against a fine reference:
// the config mesh at h / 16 (StudyOptions::reference_time_divisor) for every sweep but the mesh
// sweep, the finest mesh at the config's h
// for the mesh sweep. Accuracy: centre-of-mass and orientation error at T, and the cosine of the
// gradient with the reference's gradient, compared as volume-normalised densities on the
// reference's mesh (gradient_comparison.hpp: the identity for sweeps on the config mesh, centroid
// lookup for the mesh sweep).
//
// Stored factorisations switch to rebuilt ones when steps x one factor would exceed the memory
// budget. With an adversarial object the study also asks whether the attack survives
// refinement: its deformable gap and angle against the reference at h, h/4 and
// h / reference_time_divisor, and on the finest mesh of the mesh sweep with the materials
// carried over element-wise (objects without voids only).

#include <Eigen/Core>

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "rbaa/scene/scene.hpp"

namespace rbaa {

struct StudyOptions {
  bool full = false;
  std::size_t memory_budget_bytes = std::size_t(8) << 30;  ///< stored factors above: rebuild
  int reference_time_divisor = 16;        ///< the reference in time runs at h / this
  /// Overrides of the swept values (empty: the defaults above). run_study refuses (InputError) a
  /// time step outside [1e-4, 1/30] s, as given or as rounded to T / n, and a mesh factor that
  /// asks for fewer than 50 tets.
  std::vector<double> time_steps;         ///< s
  std::vector<double> mesh_factors;       ///< x the config's tet count (mesh.target_tets)
  std::vector<double> newton_tolerances;  ///< relative, like newton.tolerance
  std::string adversarial_file;           ///< rbaa .msh with Y, nu, rho, alpha (empty: none)
  /// Runs shorter than a second are timed up to this many times (the fastest counts).
  int timing_repeats = 3;
  std::function<void(const std::string&)> on_progress;
};

/// One measured configuration.
struct StudyPoint {
  std::string sweep;      ///< time_step | mesh | integrator | mass | newton_tolerance | factor_storage
  std::string label;      ///< e.g. "h=0.005", "tets=2400", "bdf1"
  bool is_config = false;     ///< the scene's own settings (repeated in every sweep)
  bool is_reference = false;  ///< the sweep's reference
  double time_step = 0;
  int steps = 0;
  int tets = 0;
  std::string integrator, mass, storage;
  double newton_tolerance = 0;
  int newton_iterations = 0;  ///< of the forward run
  double forward_seconds = 0;       ///< wall time
  double gradient_seconds = 0;      ///< wall time
  /// Process CPU time (all threads) of the same runs: on a shared machine the wall times of two
  /// rows are comparable only when the load did not change between them, CPU times always.
  double forward_cpu_seconds = 0, gradient_cpu_seconds = 0;
  double com_error = 0;            ///< m, at T, against the sweep's reference
  double orientation_error_deg = 0;
  double gradient_cosine = 0;
  std::string note;
  bool pareto = false;             ///< on the front of forward time against centre-of-mass error
};

/// The adversarial object against the reference at one setting.
struct SurvivalPoint {
  std::string label;      ///< "h=0.01 (config)", "h=0.0025", "tets=3012, materials transferred"
  double time_step = 0;
  int tets = 0;
  double gap = 0;         ///< centre-of-mass distance at T (m)
  double angle_deg = 0;   ///< between the centre-of-mass velocities at T
  double orientation_deg = 0;
  double moment_residual = 0;  ///< max normalised moment residual of the object simulated
};

struct StudyResult {
  std::string scene;
  int reference_time_divisor = 16;  ///< the reference in time ran at h / this (study.md says so)
  std::vector<StudyPoint> points;
  std::vector<SurvivalPoint> survival;
  /// Why the refined-mesh check was skipped, and whether the object's mesh is not the config's
  /// (one paragraph each).
  std::string survival_note;
  std::vector<std::string> notes;  ///< points that could not be measured, and why
  double total_seconds = 0;
};

/// Runs the study. Throws rbaa::InputError on bad input, rbaa::SolverError when a run fails.
StudyResult run_study(const Scene& scene, const StudyOptions& options);

/// The CSV of the points (one row per StudyPoint, header = the field names) and back.
void write_study_csv(const std::string& path, const std::vector<StudyPoint>& points);
std::vector<StudyPoint> read_study_csv(const std::string& path);

/// DIR/study.csv, DIR/survival.csv (with an adversarial object), DIR/study.md (tables and the
/// recommendations they support), DIR/pareto.gp + pareto.png (gnuplot; skipped silently without
/// it). Creates DIR.
void write_study_outputs(const StudyResult& result, const std::string& dir);

}  // namespace rbaa
