#include "rbaa/study/trade_off_study.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <memory>
#include <sstream>

#include "rbaa/diff/trajectory_gradient.hpp"
#include "rbaa/error.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/io/atomic_file.hpp"
#include "rbaa/io/materials_io.hpp"
#include "rbaa/io/tet_mesh_file.hpp"
#include "rbaa/opt/attack_problem.hpp"
#include "rbaa/scene/scene_mesh.hpp"
#include "rbaa/scene/scene_world.hpp"
#include "rbaa/sim/barrier_stiffness.hpp"
#include "rbaa/sim/observables.hpp"
#include "rbaa/sim/simulator.hpp"
#include "rbaa/study/gradient_comparison.hpp"
#include "rbaa/study/material_transfer.hpp"
#include "rbaa/study/object_voids.hpp"
#include "rbaa/study/pareto.hpp"

namespace rbaa {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// CPU time of the whole process (every thread), s.
double process_cpu_seconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

std::string number(double x, int digits = 4) {
  std::ostringstream s;
  s << std::setprecision(digits) << x;
  return s.str();
}

// The state at T that the accuracy measures compare.
struct FinalState {
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  Eigen::Vector3d com_velocity = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

FinalState final_state(const Trajectory& t, const Eigen::VectorXd& vertex_masses) {
  FinalState f;
  f.com = centre_of_mass(t.q.back(), vertex_masses);
  f.com_velocity = centre_of_mass(t.velocity(t.num_steps()), vertex_masses);  // linear in q
  f.orientation = best_fit_rotation(t.q.front(), t.q.back(), vertex_masses);
  return f;
}

double rotation_angle_deg(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  const double c = std::min(1.0, std::abs(a.dot(b)));
  return 2.0 * std::acos(c) * 180.0 / M_PI;
}

double angle_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double n = a.norm() * b.norm();
  if (!(n > 0)) return 0.0;
  return std::acos(std::clamp(a.dot(b) / n, -1.0, 1.0)) * 180.0 / M_PI;
}

// T / round(T / h): every point of the time sweep ends at the same time T.
double snap_time_step(double h, double T) {
  return T / std::max(1.0, std::round(T / h));
}

// The time sweep's range (the default sweep's largest step down to --full's smallest) and the
// mesh sweep's smallest mesh (below it the shape is lost: the 0.121 m sphere meshed at 17 tets
// holds 42 % of its volume, at 55 tets 80 %). A given value outside them is refused: moved to
// the bound, it measured another setting than the one asked for, without a word.
constexpr double kLargestTimeStep = 1.0 / 30, kSmallestTimeStep = 1e-4;
constexpr int kSmallestMeshTets = 50;

// A step typed as 1/30 to 16 digits, or T / n of one, may round just past a bound.
bool in_time_step_range(double h) {
  return h >= kSmallestTimeStep * (1 - 1e-12) && h <= kLargestTimeStep * (1 + 1e-12);
}

// snap_time_step, but to the nearest T / n within the range: the default sweep's 1/30 s on
// T = 0.04 s would round to T / 1 = 0.04 s.
double snap_time_step_in_range(double h, double T) {
  double n = std::max(1.0, std::round(T / h));
  if (T / n > kLargestTimeStep * (1 + 1e-12)) {
    n = std::ceil(T / kLargestTimeStep * (1 - 1e-12));
  } else if (T / n < kSmallestTimeStep * (1 - 1e-12)) {
    n = std::max(1.0, std::floor(T / kSmallestTimeStep * (1 + 1e-12)));
  }
  return T / n;
}

// The mesh sweep's base count: the config's mesh.target_tets, or its mesh's count without one.
int mesh_sweep_base(const Scene& scene, const TetMesh& config_mesh) {
  return scene.mesh.target_tets > 0 ? scene.mesh.target_tets : config_mesh.num_tets();
}

std::vector<double> unique_sorted(std::vector<double> v, bool descending) {
  std::sort(v.begin(), v.end());
  std::vector<double> out;
  for (double x : v) {
    if (out.empty() || std::abs(x - out.back()) > 1e-9 * std::abs(x)) out.push_back(x);
  }
  if (descending) std::reverse(out.begin(), out.end());
  return out;
}

struct Measurement {
  std::shared_ptr<const TetMesh> mesh;
  int steps = 0, iterations = 0;
  double forward_seconds = 0, gradient_seconds = 0;
  double forward_cpu_seconds = 0, gradient_cpu_seconds = 0;
  FinalState final;
  Eigen::MatrixXd density;  // gradient density (#T by 4)
  std::string storage;
  std::string note;
};

class StudyRunner {
 public:
  StudyRunner(const Scene& scene, const StudyOptions& options) : scene_(scene), options_(options) {
    progress("meshing the config's object");
    config_mesh_ = std::make_shared<const TetMesh>(make_scene_mesh(scene));
    kappa_ = scene.kappa > 0 ? scene.kappa : scene_barrier_stiffness(scene, *config_mesh_);
    half_ranges_ << 0.5 * (scene.Y_range.hi - scene.Y_range.lo),
        0.5 * (scene.nu_range.hi - scene.nu_range.lo),
        0.5 * (scene.rho_range.hi - scene.rho_range.lo), 0.5 * (1.0 - scene.alpha_min);
  }

  const TetMesh& config_mesh() const { return *config_mesh_; }

  void progress(const std::string& message) const {
    if (options_.on_progress) options_.on_progress(message);
  }

  // Forward run of the reference object (timed), then the gradient at the design's start
  // (timed), storing or rebuilding factors (rebuilding past the memory budget).
  Measurement measure(const Scene& s, const std::shared_ptr<const TetMesh>& mesh,
                      FactorStorage storage, bool with_gradient = true) {
    Measurement m;
    m.mesh = mesh;
    // The attack problem on this mesh at this scene's settings, kappa frozen from the config's
    // mesh; its reference run timed here.
    AttackProblemOptions o;
    o.object_mesh = mesh.get();
    o.kappa = kappa_;
    o.storage = storage;
    o.stored_factor_budget = options_.memory_budget_bytes;
    o.with_gradient = with_gradient;
    // Wall times are the fastest of up to 3 runs for runs under a second (the machine is shared;
    // the least disturbed run is the truest), one run otherwise. Runs are deterministic.
    o.run_reference = [&](Simulator& reference, const Eigen::VectorXd& q0,
                          const Eigen::VectorXd& v0) {
      Trajectory traj;
      m.forward_seconds = std::numeric_limits<double>::infinity();
      m.forward_cpu_seconds = std::numeric_limits<double>::infinity();
      for (int r = 0; r < std::max(1, options_.timing_repeats); ++r) {
        const auto t0 = Clock::now();
        const double c0 = process_cpu_seconds();
        traj = reference.run(q0, v0);
        m.forward_seconds = std::min(m.forward_seconds, seconds_since(t0));
        m.forward_cpu_seconds = std::min(m.forward_cpu_seconds, process_cpu_seconds() - c0);
        if (m.forward_seconds > 1.0) break;
      }
      return traj;
    };
    const AttackProblem problem = build_attack_problem(s, o);
    const Trajectory& traj = problem.reference;
    m.steps = traj.num_steps();
    for (const StepStats& st : traj.steps) m.iterations += st.newton_iterations;
    m.final = final_state(traj, problem.reference_simulator->vertex_masses());
    if (!with_gradient) return m;

    m.storage = factor_storage_name(problem.storage);
    m.note = problem.storage_note;
    TrajectoryGradientFunction& f = *problem.gradient;
    MaterialGradient g;
    m.gradient_seconds = std::numeric_limits<double>::infinity();
    m.gradient_cpu_seconds = std::numeric_limits<double>::infinity();
    for (int r = 0; r < std::max(1, options_.timing_repeats); ++r) {
      const auto t1 = Clock::now();
      const double c1 = process_cpu_seconds();
      f.evaluate_materials(problem.design->initial_material(), &g);
      m.gradient_seconds = std::min(m.gradient_seconds, seconds_since(t1));
      m.gradient_cpu_seconds = std::min(m.gradient_cpu_seconds, process_cpu_seconds() - c1);
      if (m.gradient_seconds > 1.0) break;
    }
    m.density = gradient_density(*mesh, g, half_ranges_, s.fields);
    return m;
  }

  StudyPoint point(const std::string& sweep, const std::string& label, const Scene& s,
                   const Measurement& m, const Measurement& reference) const {
    StudyPoint p;
    p.sweep = sweep;
    p.label = label;
    p.time_step = s.time_step;
    p.steps = m.steps;
    p.tets = m.mesh->num_tets();
    p.integrator = s.integrator == Integrator::kBdf2 ? "bdf2" : "bdf1";
    p.mass = s.mass == MassModel::kConsistent ? "consistent" : "lumped";
    p.storage = m.storage;
    p.newton_tolerance = s.newton_tolerance;
    p.newton_iterations = m.iterations;
    p.forward_seconds = m.forward_seconds;
    p.gradient_seconds = m.gradient_seconds;
    p.forward_cpu_seconds = m.forward_cpu_seconds;
    p.gradient_cpu_seconds = m.gradient_cpu_seconds;
    p.com_error = (m.final.com - reference.final.com).norm();
    p.orientation_error_deg = rotation_angle_deg(m.final.orientation, reference.final.orientation);
    p.gradient_cosine = gradient_cosine_across(*m.mesh, m.density, *reference.mesh, reference.density);
    p.note = m.note;
    return p;
  }

  StudyResult run() {
    const auto t_start = Clock::now();
    StudyResult result;
    result.scene = scene_.name;
    result.reference_time_divisor = options_.reference_time_divisor;
    const double h0 = scene_.time_step, T = scene_.duration;

    progress("config point (h = " + number(h0) + " s, " + std::to_string(config_mesh_->num_tets()) + " tets)");
    const Measurement config = measure(scene_, config_mesh_, FactorStorage::kStore);

    // --- Time step (reference: the config mesh at h / divisor) ---
    Scene ref_scene = scene_;
    ref_scene.time_step = snap_time_step(h0 / options_.reference_time_divisor, T);
    progress("reference in time (h = " + number(ref_scene.time_step) + " s)");
    const Measurement time_ref = measure(ref_scene, config_mesh_, FactorStorage::kStore);
    references_[ref_scene.time_step] = time_ref.final;
    references_[h0] = config.final;

    std::vector<double> hs = options_.time_steps;
    if (hs.empty()) {
      hs = {1.0 / 30, 2 * h0, h0, h0 / 2, h0 / 4};
      if (options_.full) {
        for (double h : {1.0 / 60, h0 / 8, 1e-4}) hs.push_back(h);
      }
      // The default sweep's steps stay within the range once rounded to T / n (the star's
      // 2 h0 = 1/15 s becomes 1/30 s, its own step; 1/30 s on T = 0.04 s becomes T / 2, not
      // T / 1); given steps outside it, as given or rounded, were refused in run_study.
      for (double& h : hs) h = snap_time_step_in_range(h, T);
    }
    for (double& h : hs) {
      const double snapped = snap_time_step(h, T);
      if (!options_.time_steps.empty() && std::abs(snapped - h) > 1e-9 * h) {
        progress("time step " + number(h, 12) + " s rounded to " + number(snapped) + " s (T / " +
                 std::to_string(std::lround(T / snapped)) +
                 ") so that the run ends at T = " + number(T) + " s");
      }
      h = snapped;
    }
    hs.push_back(h0);
    for (double h : unique_sorted(hs, true)) {
      Scene s = scene_;
      s.time_step = h;
      const bool is_config = std::abs(h - h0) <= 1e-12 * h0;
      if (is_config) {
        add(result, point("time_step", "h=" + number(h) + " (config)", s, config, time_ref), true, false);
        continue;
      }
      progress("time step h = " + number(h) + " s");
      const Measurement m = measure(s, config_mesh_, FactorStorage::kStore);
      references_[h] = m.final;
      add(result, point("time_step", "h=" + number(h), s, m, time_ref), false, false);
    }
    add(result, point("time_step", "h=" + number(ref_scene.time_step) + " (reference)", ref_scene,
                      time_ref, time_ref),
        false, true);

    // --- Mesh resolution (reference: the finest mesh at the config's h) ---
    std::shared_ptr<const TetMesh> finest;
    Measurement space_ref;
    if (scene_.mesh.mesh_file.empty()) {
      const int base = mesh_sweep_base(scene_, *config_mesh_);
      std::vector<double> factors = options_.mesh_factors;
      if (factors.empty()) {
        // The default sweep's coarse meshes stay at the smallest mesh or above, as its time steps
        // stay in their range (0.25 x a 120-tet config is 50 tets, not 30; on an 80-tet config
        // 0.25 and 0.5 are one point), and are left out when that is no coarser than the config's
        // mesh. Given factors below it were refused in run_study.
        const double smallest = static_cast<double>(kSmallestMeshTets) / base;
        for (double f : {0.25, 0.5}) {
          if (smallest < 1) factors.push_back(std::max(f, smallest));
        }
        factors.push_back(2.0);
        if (options_.full) factors.push_back(4.0);
      }
      factors.push_back(1.0);
      factors = unique_sorted(factors, false);
      std::vector<std::pair<Scene, Measurement>> runs;
      for (double factor : factors) {
        Scene s = scene_;
        if (std::abs(factor - 1.0) < 1e-12) {
          runs.emplace_back(s, config);
          continue;
        }
        s.mesh.target_tets = static_cast<int>(std::lround(factor * base));
        progress("mesh x" + number(factor) + " (target " + std::to_string(s.mesh.target_tets) + " tets)");
        std::shared_ptr<const TetMesh> mesh;
        try {
          mesh = std::make_shared<const TetMesh>(make_scene_mesh(s));
        } catch (const InputError& e) {
          // Coarse meshes of thin shapes can come out with slivers the validation rejects.
          result.notes.push_back("mesh x" + number(factor) + " skipped: " + e.what());
          progress(result.notes.back());
          continue;
        }
        runs.emplace_back(s, measure(s, mesh, FactorStorage::kStore));
      }
      space_ref = runs.back().second;
      finest = space_ref.mesh;
      for (std::size_t i = 0; i < runs.size(); ++i) {
        const bool is_config = runs[i].second.mesh == config_mesh_;
        const bool is_ref = i + 1 == runs.size();
        std::string label = "tets=" + std::to_string(runs[i].second.mesh->num_tets());
        if (is_config) label += " (config)";
        if (is_ref) label += " (reference)";
        add(result, point("mesh", label, runs[i].first, runs[i].second, space_ref), is_config, is_ref);
      }
    } else {
      progress("mesh sweep skipped: the config reads a mesh file");
    }

    // --- Integrator, mass, Newton tolerance, factor storage (reference: time_ref) ---
    {
      Scene s = scene_;
      s.integrator = scene_.integrator == Integrator::kBdf2 ? Integrator::kBdf1 : Integrator::kBdf2;
      progress(std::string("integrator ") + (s.integrator == Integrator::kBdf2 ? "bdf2" : "bdf1"));
      const Measurement m = measure(s, config_mesh_, FactorStorage::kStore);
      for (Integrator in : {Integrator::kBdf1, Integrator::kBdf2}) {
        const bool is_config = in == scene_.integrator;
        Scene si = scene_;
        si.integrator = in;
        add(result, point("integrator", std::string(in == Integrator::kBdf2 ? "bdf2" : "bdf1") +
                                            (is_config ? " (config)" : ""),
                          si, is_config ? config : m, time_ref),
            is_config, false);
      }
    }
    {
      Scene s = scene_;
      s.mass = scene_.mass == MassModel::kConsistent ? MassModel::kLumped : MassModel::kConsistent;
      progress(std::string("mass ") + (s.mass == MassModel::kConsistent ? "consistent" : "lumped"));
      const Measurement m = measure(s, config_mesh_, FactorStorage::kStore);
      for (MassModel mm : {MassModel::kLumped, MassModel::kConsistent}) {
        const bool is_config = mm == scene_.mass;
        Scene si = scene_;
        si.mass = mm;
        add(result, point("mass", std::string(mm == MassModel::kConsistent ? "consistent" : "lumped") +
                                      (is_config ? " (config)" : ""),
                          si, is_config ? config : m, time_ref),
            is_config, false);
      }
    }
    {
      const double tol0 = scene_.newton_tolerance;
      std::vector<double> tols = options_.newton_tolerances;
      if (tols.empty()) {
        tols = {1e3 * tol0, 1e2 * tol0, 10 * tol0};
        if (options_.full) tols.push_back(0.1 * tol0);
      }
      tols.push_back(tol0);
      for (double tol : unique_sorted(tols, true)) {
        Scene s = scene_;
        s.newton_tolerance = tol;
        const bool is_config = std::abs(tol - tol0) <= 1e-12 * tol0;
        if (is_config) {
          add(result, point("newton_tolerance", "tol=" + number(tol) + " (config)", s, config, time_ref),
              true, false);
          continue;
        }
        progress("Newton tolerance " + number(tol));
        add(result, point("newton_tolerance", "tol=" + number(tol), s,
                          measure(s, config_mesh_, FactorStorage::kStore), time_ref),
            false, false);
      }
    }
    {
      progress("factor storage: rebuild");
      // Same forward run and the same numbers; only the gradient's time changes.
      Measurement rebuilt = measure(scene_, config_mesh_, FactorStorage::kRebuild);
      rebuilt.forward_seconds = config.forward_seconds;
      rebuilt.forward_cpu_seconds = config.forward_cpu_seconds;
      add(result, point("factor_storage", config.storage + " (config)", scene_, config, time_ref), true, false);
      add(result, point("factor_storage", "rebuild", scene_, rebuilt, time_ref), false, false);
    }

    // --- Pareto fronts: forward time against centre-of-mass error, one per reference (errors
    // against the reference in time and against the reference in space are not comparable) ---
    for (const bool space : {false, true}) {
      std::vector<CostError> ce;
      for (const StudyPoint& p : result.points) {
        const bool usable = !p.is_reference && (p.sweep == "mesh") == space;
        ce.push_back({p.forward_seconds, usable ? p.com_error : std::nan("")});
      }
      for (int i : pareto_front(ce)) result.points[i].pareto = true;
    }

    if (!options_.adversarial_file.empty()) survival(result, finest, space_ref);
    result.total_seconds = seconds_since(t_start);
    return result;
  }

 private:
  void add(StudyResult& result, StudyPoint p, bool is_config, bool is_reference) {
    p.is_config = is_config;
    p.is_reference = is_reference;
    result.points.push_back(std::move(p));
  }

  const FinalState& reference_final(double h) {
    for (const auto& [key, f] : references_) {
      if (std::abs(key - h) <= 1e-12 * h) return f;
    }
    Scene s = scene_;
    s.time_step = h;
    progress("reference object at h = " + number(h));
    references_[h] = measure(s, config_mesh_, FactorStorage::kRebuild, false).final;
    return references_[h];
  }

  double moment_residual(const TetMesh& mesh, const MaterialField& m, const TetMesh& ref_mesh) const {
    const Moments ref = compute_moments(ref_mesh, scene_.reference_rho);
    const Moments adv = compute_moments(mesh, m.effective_density());
    return (adv.as_vector() - ref.as_vector()).cwiseQuotient(moment_normalisation(ref)).cwiseAbs().maxCoeff();
  }

  SurvivalPoint simulate_adversarial(const std::string& label, double h, const TetMesh& mesh,
                                     const MaterialField& materials, const FinalState& ref,
                                     const TetMesh& ref_mesh) {
    Scene s = scene_;
    s.time_step = h;
    progress("adversarial object: " + label);
    // Its own centre of mass starts at object.position, as in rbaa evaluate.
    const TetMesh placed = place_centre_of_mass(scene_, mesh, materials.effective_density(),
                                                options_.adversarial_file);
    Simulator sim(placed, materials, simulation_settings(s, kappa_), options_.adversarial_file);
    const Eigen::VectorXd q0 =
        Eigen::Map<const Eigen::VectorXd>(placed.V.data(), 3 * placed.num_vertices());
    const Trajectory t = sim.run(q0, rigid_velocities(q0, s.position, s.velocity, s.angular_velocity));
    const FinalState f = final_state(t, sim.vertex_masses());
    SurvivalPoint p;
    p.label = label;
    p.time_step = h;
    p.tets = mesh.num_tets();
    p.gap = (f.com - ref.com).norm();
    p.angle_deg = angle_deg(f.com_velocity, ref.com_velocity);
    p.orientation_deg = rotation_angle_deg(f.orientation, ref.orientation);
    p.moment_residual = moment_residual(mesh, materials, ref_mesh);
    return p;
  }

  void survival(StudyResult& result, const std::shared_ptr<const TetMesh>& finest,
                const Measurement& space_ref) {
    const TetMeshFile adv = read_tet_mesh(options_.adversarial_file);
    const MaterialField materials = read_materials(options_.adversarial_file, adv.mesh.num_tets());
    const double h0 = scene_.time_step, T = scene_.duration;
    const double hs[3] = {h0, snap_time_step(h0 / 4, T),
                          snap_time_step(h0 / options_.reference_time_divisor, T)};
    for (int i = 0; i < 3; ++i) {
      const std::string label = "h=" + number(hs[i]) + (i == 0 ? " (config)" : "");
      result.survival.push_back(simulate_adversarial(label, hs[i], adv.mesh, materials,
                                                     reference_final(hs[i]), *config_mesh_));
    }
    // Voids are told from the object's materials and mesh (object_voids.hpp), not from its tet
    // count: an attack run at another mesh.target_tets has another count and may have no void.
    // That the meshes differ is said apart, as the gaps then include their difference.
    const ObjectVoids voids = find_object_voids(adv.mesh, materials, *config_mesh_);
    std::vector<std::string> notes;
    if (!voids.part_of_config) {
      notes.push_back("the adversarial object's mesh (" + std::to_string(adv.mesh.num_tets()) +
                      " tets) is not the config's (" + std::to_string(config_mesh_->num_tets()) +
                      " tets) nor a part of it, as from an attack at another mesh.target_tets: its "
                      "gaps are against the reference object on the config's mesh, so they include "
                      "the difference between the two meshes");
    }
    if (!finest || finest == config_mesh_) {
      notes.push_back("no finer mesh in the mesh sweep: the refined-mesh check was skipped");
    } else if (voids.any()) {
      notes.push_back("the adversarial object has voids (" + voids.describe() +
                      "): carrying it to a finer mesh would blur its holes, so the refined-mesh "
                      "check was skipped");
    } else {
      const MaterialField moved = transfer_materials(adv.mesh, materials, *finest);
      result.survival.push_back(simulate_adversarial(
          "tets=" + std::to_string(finest->num_tets()) + ", materials transferred", h0, *finest, moved,
          space_ref.final, *finest));
    }
    for (const std::string& n : notes) {
      result.survival_note += (result.survival_note.empty() ? "" : "\n\n") + n;
    }
  }

  const Scene& scene_;
  const StudyOptions& options_;
  std::shared_ptr<const TetMesh> config_mesh_;
  double kappa_ = 0;
  Eigen::Vector4d half_ranges_;
  std::map<double, FinalState> references_;  // reference object's state at T per h (config mesh)
};

// CSV of study points: strings and numbers, no commas inside fields.
const std::vector<std::string> kColumns = {
    "sweep", "label", "is_config", "is_reference", "time_step", "steps", "tets", "integrator",
    "mass", "storage", "newton_tolerance", "newton_iterations", "forward_seconds",
    "gradient_seconds", "forward_cpu_seconds", "gradient_cpu_seconds", "com_error", "orientation_error_deg", "gradient_cosine", "pareto", "note"};

std::string clean(std::string s) {
  std::replace(s.begin(), s.end(), ',', ';');
  std::replace(s.begin(), s.end(), '\n', ' ');
  return s;
}

std::string exact(double x) {
  std::ostringstream s;
  s << std::setprecision(17) << x;
  return s.str();
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream in(line);
  for (std::string f; std::getline(in, f, ',');) out.push_back(f);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

std::string markdown_table(const std::vector<StudyPoint>& points, const std::string& sweep) {
  std::ostringstream md;
  md << "| setting | forward (s) | gradient (s) | forward CPU (s) | gradient CPU (s) | Newton iterations | "
        "COM error (mm) | orientation error (deg) | gradient cosine | Pareto | note |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const StudyPoint& p : points) {
    if (p.sweep != sweep) continue;
    md << "| " << p.label << " | " << number(p.forward_seconds, 3) << " | "
       << number(p.gradient_seconds, 3) << " | " << number(p.forward_cpu_seconds, 3) << " | "
       << number(p.gradient_cpu_seconds, 3) << " | "
       << p.newton_iterations << " | " << number(p.com_error * 1e3, 3) << " | "
       << number(p.orientation_error_deg, 3) << " | " << number(p.gradient_cosine, 5) << " | "
       << (p.pareto ? "yes" : "") << " | " << p.note << " |\n";
  }
  return md.str();
}

// Plain-language reading of the sweeps: the cheapest setting within tolerances of the object's
// accuracy needs. `tolerance`: centre-of-mass error (m) taken as "as good as the reference".
std::string recommendations(const StudyResult& r) {
  std::ostringstream md;
  const StudyPoint* config = nullptr;
  for (const StudyPoint& p : r.points) {
    if (p.is_config && p.sweep == "time_step") config = &p;
  }
  if (config == nullptr) return "";
  md << "* The config's own settings: forward " << number(config->forward_seconds, 3) << " s, gradient "
     << number(config->gradient_seconds, 3) << " s, centre-of-mass error "
     << number(config->com_error * 1e3, 3) << " mm and gradient cosine "
     << number(config->gradient_cosine, 4) << " against the reference in time.\n";
  for (const std::string sweep : {"time_step", "mesh", "integrator", "mass", "newton_tolerance"}) {
    // The cheapest non-reference point whose error is at most the config's and cosine at least.
    const StudyPoint* best = nullptr;
    for (const StudyPoint& p : r.points) {
      if (p.sweep != sweep || p.is_reference || p.is_config) continue;
      const StudyPoint* cfg = nullptr;
      for (const StudyPoint& q : r.points) {
        if (q.sweep == sweep && q.is_config) cfg = &q;
      }
      if (cfg == nullptr) continue;
      if (p.forward_seconds < cfg->forward_seconds && p.com_error <= cfg->com_error * 1.05 &&
          p.gradient_cosine >= cfg->gradient_cosine - 1e-3 && (!best || p.forward_seconds < best->forward_seconds)) {
        best = &p;
      }
    }
    if (best != nullptr) {
      md << "* " << sweep << ": `" << best->label << "` is cheaper than the config (forward "
         << number(best->forward_seconds, 3) << " s) and as accurate (COM error "
         << number(best->com_error * 1e3, 3) << " mm, gradient cosine " << number(best->gradient_cosine, 4)
         << ").\n";
    } else {
      md << "* " << sweep << ": no setting in the sweep is both cheaper than the config and as accurate.\n";
    }
  }
  return md.str();
}

void write_pareto_plot(const StudyResult& r, const std::string& dir) {
  std::map<std::string, std::vector<const StudyPoint*>> by_sweep;
  std::vector<const StudyPoint*> front[2];  // against the reference in time, in space
  for (const StudyPoint& p : r.points) {
    if (p.is_reference || !(p.com_error > 0)) continue;
    by_sweep[p.sweep].push_back(&p);
    if (p.pareto) front[p.sweep == "mesh"].push_back(&p);
  }
  for (auto& f : front) {
    std::sort(f.begin(), f.end(), [](const StudyPoint* a, const StudyPoint* b) {
      return a->forward_seconds < b->forward_seconds;
    });
  }
  const std::filesystem::path d(dir);
  std::ostringstream gp;
  gp << "set terminal pngcairo size 1100,700 noenhanced\nset output 'pareto.png'\n"
     << "set title 'rbaa study: " << r.scene << " (forward time against centre-of-mass error at T)'\n"
     << "set logscale xy\nset grid\nset xlabel 'forward run (s)'\nset ylabel 'centre-of-mass error at T (m)'\n"
     << "set format y '%g'\nset key outside below horizontal\nplot ";
  int i = 0;
  for (const auto& [sweep, pts] : by_sweep) {
    std::ofstream dat(d / ("pareto_" + sweep + ".dat"));
    dat << std::setprecision(10);
    for (const StudyPoint* p : pts) dat << p->forward_seconds << " " << p->com_error << " \"" << p->label << "\"\n";
    gp << (i ? ", " : "") << "'pareto_" << sweep << ".dat' using 1:2 with points pt " << (6 + i)
       << " ps 1.5 title '" << sweep << "'";
    ++i;
  }
  const char* names[2] = {"pareto_front_time.dat", "pareto_front_space.dat"};
  const std::string titles[2] = {"front (vs h/" + std::to_string(r.reference_time_divisor) + ")",
                                 "front (mesh, vs finest)"};
  for (int k = 0; k < 2; ++k) {
    std::ofstream dat(d / names[k]);
    dat << std::setprecision(10);
    for (const StudyPoint* p : front[k]) dat << p->forward_seconds << " " << p->com_error << "\n";
    if (front[k].empty()) continue;
    gp << (i++ ? ", " : "") << "'" << names[k] << "' using 1:2 with lines lw 2 dt " << (k + 1)
       << " lc rgb 'black' title '" << titles[k] << "'";
  }
  gp << "\n";
  write_file_atomically((d / "pareto.gp").string(), [&](std::ostream& out) { out << gp.str(); });
  const std::string command = "cd '" + dir + "' && gnuplot pareto.gp >/dev/null 2>&1";
  if (std::system("command -v gnuplot >/dev/null 2>&1") == 0) {
    if (std::system(command.c_str()) != 0) {
      // The CSV and the Markdown table hold the numbers; a missing PNG is not fatal.
    }
  }
}

}  // namespace

StudyResult run_study(const Scene& scene, const StudyOptions& options) {
  // The study's measures are the object's alone (its final state, the gradient's density over
  // its mesh, its mesh sweep); silently dropping the further bodies would study another scene
  // than the one given. The attack problem it builds would take them.
  if (!scene.bodies.empty()) {
    throw InputError(scene.source +
                     ": key 'bodies': rbaa study measures the object in a scene of its own; "
                     "scenes with further bodies are not supported by it yet");
  }
  if (!(options.reference_time_divisor >= 2)) throw InputError("study: the reference time divisor must be >= 2");
  const std::string range =
      "outside the study's range of steps, " + number(kSmallestTimeStep) + " to 1/30 s";
  for (double h : options.time_steps) {
    if (!in_time_step_range(h)) throw InputError("--time_steps=" + number(h, 12) + ": " + range);
    // The step that would run: 0.03 s on T = 0.04 s is T / 1.
    const double snapped = snap_time_step(h, scene.duration);
    if (!in_time_step_range(snapped)) {
      throw InputError("--time_steps=" + number(h, 12) + ": rounded to " + number(snapped) +
                       " s (T / " + std::to_string(std::lround(scene.duration / snapped)) +
                       ") so that the run ends at T = " + number(scene.duration) + " s, " + range);
    }
  }
  StudyRunner runner(scene, options);
  if (scene.mesh.mesh_file.empty()) {
    // Checked on the config's mesh, before any run: a factor's count is relative to it.
    const int base = mesh_sweep_base(scene, runner.config_mesh());
    for (double factor : options.mesh_factors) {
      const long tets = std::lround(factor * base);
      if (tets < kSmallestMeshTets) {
        throw InputError("--mesh_factors=" + number(factor, 12) + ": " + number(factor, 12) +
                         " x the config's " + std::to_string(base) + " tets is " +
                         std::to_string(tets) + ", below the study's smallest mesh of " +
                         std::to_string(kSmallestMeshTets) + " tets");
      }
    }
  }
  return runner.run();
}

void write_study_csv(const std::string& path, const std::vector<StudyPoint>& points) {
  write_file_atomically(path, [&](std::ostream& out) {
    for (std::size_t c = 0; c < kColumns.size(); ++c) out << (c ? "," : "") << kColumns[c];
    out << "\n";
    for (const StudyPoint& p : points) {
      out << clean(p.sweep) << "," << clean(p.label) << "," << p.is_config << "," << p.is_reference
          << "," << exact(p.time_step) << "," << p.steps << "," << p.tets << "," << clean(p.integrator)
          << "," << clean(p.mass) << "," << clean(p.storage) << "," << exact(p.newton_tolerance) << ","
          << p.newton_iterations << "," << exact(p.forward_seconds) << "," << exact(p.gradient_seconds)
          << "," << exact(p.forward_cpu_seconds) << "," << exact(p.gradient_cpu_seconds)
          << "," << exact(p.com_error) << "," << exact(p.orientation_error_deg) << ","
          << exact(p.gradient_cosine) << "," << p.pareto << "," << clean(p.note) << "\n";
    }
  });
}

std::vector<StudyPoint> read_study_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the study CSV");
  std::string line;
  std::getline(in, line);
  if (split(line) != kColumns) throw InputError(path + ":1: not an rbaa study CSV header");
  std::vector<StudyPoint> points;
  int line_number = 1;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty()) continue;
    const std::vector<std::string> f = split(line);
    if (f.size() != kColumns.size()) {
      throw InputError(path + ":" + std::to_string(line_number) + ": expected " +
                       std::to_string(kColumns.size()) + " fields");
    }
    try {
      StudyPoint p;
      p.sweep = f[0];
      p.label = f[1];
      p.is_config = std::stoi(f[2]) != 0;
      p.is_reference = std::stoi(f[3]) != 0;
      p.time_step = std::stod(f[4]);
      p.steps = std::stoi(f[5]);
      p.tets = std::stoi(f[6]);
      p.integrator = f[7];
      p.mass = f[8];
      p.storage = f[9];
      p.newton_tolerance = std::stod(f[10]);
      p.newton_iterations = std::stoi(f[11]);
      p.forward_seconds = std::stod(f[12]);
      p.gradient_seconds = std::stod(f[13]);
      p.forward_cpu_seconds = std::stod(f[14]);
      p.gradient_cpu_seconds = std::stod(f[15]);
      p.com_error = std::stod(f[16]);
      p.orientation_error_deg = std::stod(f[17]);
      p.gradient_cosine = std::stod(f[18]);
      p.pareto = std::stoi(f[19]) != 0;
      p.note = f[20];
      points.push_back(std::move(p));
    } catch (const std::logic_error&) {
      throw InputError(path + ":" + std::to_string(line_number) + ": a numeric field is not a number");
    }
  }
  return points;
}

void write_study_outputs(const StudyResult& result, const std::string& dir) {
  std::filesystem::create_directories(dir);
  const std::filesystem::path d(dir);
  write_study_csv((d / "study.csv").string(), result.points);
  if (!result.survival.empty()) {
    write_file_atomically((d / "survival.csv").string(), [&](std::ostream& out) {
      out << "label,time_step,tets,gap_m,angle_deg,orientation_deg,moment_residual\n";
      for (const SurvivalPoint& s : result.survival) {
        out << clean(s.label) << "," << exact(s.time_step) << "," << s.tets << "," << exact(s.gap) << ","
            << exact(s.angle_deg) << "," << exact(s.orientation_deg) << "," << exact(s.moment_residual) << "\n";
      }
    });
  }
  write_pareto_plot(result, dir);
  write_file_atomically((d / "study.md").string(), [&](std::ostream& md) {
    md << "# Speed against accuracy: " << result.scene << "\n\n"
       << "One factor at a time around the config. Forward: a run of the reference object; gradient: "
          "forward + adjoint of the undirected trajectory term at the attack's unperturbed start. "
          "Errors at T against the config mesh at h / "
       << result.reference_time_divisor
       << " (all sweeps but the mesh sweep) or against "
          "the finest mesh at the config's h (mesh sweep); gradient cosine of volume-normalised "
          "gradient densities (the mesh sweep's carried to the finest mesh by centroid lookup). "
          "Pareto: not beaten in both forward time and centre-of-mass error by another row measured against the same reference (two fronts: the mesh sweep against the reference in space, every other sweep against the reference in time). "
          "Study time "
       << number(result.total_seconds, 4) << " s.\n\n![Pareto front](pareto.png)\n\n";
    const char* titles[][2] = {{"time_step", "Time step"},           {"mesh", "Mesh resolution"},
                               {"integrator", "Integrator"},         {"mass", "Mass matrix"},
                               {"newton_tolerance", "Newton tolerance"}, {"factor_storage", "Factor storage"}};
    for (const auto& t : titles) {
      bool any = false;
      for (const StudyPoint& p : result.points) any = any || p.sweep == t[0];
      if (any) md << "## " << t[1] << "\n\n" << markdown_table(result.points, t[0]) << "\n";
    }
    if (!result.survival.empty() || !result.survival_note.empty()) {
      md << "## Does the attack survive refinement?\n\n"
         << "| setting | tets | COM gap at T (m) | velocity angle at T (deg) | orientation gap at T (deg) | "
            "moment residual |\n|---|---|---|---|---|---|\n";
      for (const SurvivalPoint& s : result.survival) {
        md << "| " << s.label << " | " << s.tets << " | " << number(s.gap, 4) << " | "
           << number(s.angle_deg, 4) << " | " << number(s.orientation_deg, 4) << " | "
           << number(s.moment_residual, 3) << " |\n";
      }
      if (!result.survival_note.empty()) md << "\n" << result.survival_note << "\n";
      md << "\n";
    }
    if (!result.notes.empty()) {
      md << "## Notes\n\n";
      for (const std::string& n : result.notes) md << "* " << n << "\n";
      md << "\n";
    }
    md << "## Reading\n\n" << recommendations(result);
  });
}

}  // namespace rbaa
