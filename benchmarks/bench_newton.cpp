// Newton iteration, CHOLMOD numeric factorisation and a whole time step on the paper's ball
// (configs/ball.yaml, the reference material Y = 1e13), at the start of its contact step.
// Prints the ratio Newton iteration / factorisation (target <= 1.3, SPEC section 10) with the
// absolute times and the BLAS library actually mapped into the process.
//
//   ./build/benchmarks/bench_newton [--config=configs/ball.yaml]

#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <set>
#include <string>

#include "rbaa/scene/scene.hpp"
#include "rbaa/scene/scene_mesh.hpp"
#include "rbaa/sim/barrier_stiffness.hpp"
#include "rbaa/sim/simulator.hpp"

namespace {

std::string g_config = "configs/ball.yaml";

struct Fixture {
  std::unique_ptr<rbaa::Simulator> sim;
  rbaa::BdfIntegrator saved{rbaa::Integrator::kBdf2, 0.01};
  Eigen::VectorXd x;  // the first Newton iterate of the contact step
  int contact_step = 0;
};

Fixture& fixture() {
  static Fixture f = [] {
    Fixture f;
    const rbaa::Scene scene = rbaa::load_scene(g_config);
    const rbaa::TetMesh mesh = rbaa::make_scene_mesh(scene);
    const double kappa = rbaa::scene_barrier_stiffness(scene, mesh);
    f.sim = std::make_unique<rbaa::Simulator>(
        mesh,
        rbaa::MaterialField::uniform(mesh.num_tets(), scene.reference_Y, scene.reference_nu,
                                     scene.reference_rho),
        rbaa::simulation_settings(scene, kappa));
    const Eigen::VectorXd q0 = f.sim->rest_positions();
    f.sim->reset(q0, rbaa::rigid_velocities(q0, scene.position, scene.velocity,
                                            scene.angular_velocity));
    // Advance until the next step brings a vertex within d_hat: that step is the contact step.
    for (int k = 0; k < 200; ++k) {
      f.saved = f.sim->integrator();
      const rbaa::StepStats s = f.sim->advance();
      if (s.active_pairs > 0) {
        f.contact_step = k + 1;
        break;
      }
    }
    f.sim->integrator() = f.saved;
    f.x = f.sim->integrator().current();
    f.sim->inertia_form().set_predictor(f.sim->integrator().predictor());
    std::printf("ball: %d vertices, %d tets, %d dofs; contact step %d\n",
                f.sim->rest_mesh().num_vertices(), f.sim->rest_mesh().num_tets(),
                f.sim->num_dofs(), f.contact_step);
    return f;
  }();
  return f;
}

double g_iteration_s = 0, g_factorization_s = 0, g_assembly_s = 0, g_step_s = 0;

// One Newton iteration: gradient, projected Hessian assembly, factorisation, solve.
void BM_NewtonIteration(benchmark::State& state) {
  Fixture& f = fixture();
  rbaa::IncrementalPotential& E = f.sim->potential();
  rbaa::LinearSolver& solver = f.sim->newton().linear_solver();
  const auto pattern = f.sim->hessian_pattern().pattern_version();
  for (auto _ : state) {
    const Eigen::VectorXd g = E.gradient(f.x);
    solver.factorize(E.hessian(f.x, rbaa::HessianKind::kProjected), pattern);
    benchmark::DoNotOptimize(solver.solve(g));
  }
}

void BM_Assembly(benchmark::State& state) {
  Fixture& f = fixture();
  rbaa::IncrementalPotential& E = f.sim->potential();
  for (auto _ : state) {
    benchmark::DoNotOptimize(E.gradient(f.x));
    benchmark::DoNotOptimize(E.hessian(f.x, rbaa::HessianKind::kProjected).nonZeros());
  }
}

void BM_Factorization(benchmark::State& state) {
  Fixture& f = fixture();
  rbaa::IncrementalPotential& E = f.sim->potential();
  rbaa::LinearSolver& solver = f.sim->newton().linear_solver();
  const auto pattern = f.sim->hessian_pattern().pattern_version();
  const Eigen::SparseMatrix<double> H = E.hessian(f.x, rbaa::HessianKind::kProjected);
  for (auto _ : state) benchmark::DoNotOptimize(solver.factorize(H, pattern));
}

void BM_ContactStep(benchmark::State& state) {
  Fixture& f = fixture();
  int iterations = 0;
  for (auto _ : state) {
    f.sim->integrator() = f.saved;
    iterations = f.sim->advance().newton_iterations;
  }
  state.counters["newton_iterations"] = iterations;
}

std::string loaded_blas() {
  std::ifstream maps("/proc/self/maps");
  std::set<std::string> libs;
  for (std::string line; std::getline(maps, line);) {
    const auto slash = line.find('/');
    if (slash == std::string::npos) continue;
    const std::string path = line.substr(slash);
    for (const char* key : {"blas", "atlas", "lapack", "mkl"}) {
      if (path.find(key) != std::string::npos) libs.insert(path);
    }
  }
  std::string out;
  for (const auto& l : libs) out += "  " + l + "\n";
  return out.empty() ? "  (none mapped)\n" : out;
}

class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      const double s = r.GetAdjustedRealTime() * 1e-9 *
                       (r.time_unit == benchmark::kMillisecond ? 1e6 : 1.0);
      const std::string name = r.benchmark_name();
      if (name.find("NewtonIteration") != std::string::npos) g_iteration_s = s;
      if (name.find("Factorization") != std::string::npos) g_factorization_s = s;
      if (name.find("Assembly") != std::string::npos) g_assembly_s = s;
      if (name.find("ContactStep") != std::string::npos) g_step_s = s;
    }
    ConsoleReporter::ReportRuns(runs);
  }
};

}  // namespace

BENCHMARK(BM_NewtonIteration)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Assembly)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Factorization)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ContactStep)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (!std::strncmp(argv[i], "--config=", 9)) g_config = argv[i] + 9;
  }
  benchmark::Initialize(&argc, argv);
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  std::printf("\nNewton iteration %.1f ms = assembly+projection %.1f ms + factorisation %.1f ms + solve/rest\n",
              g_iteration_s * 1e3, g_assembly_s * 1e3, g_factorization_s * 1e3);
  if (g_factorization_s > 0) {
    std::printf("ratio Newton iteration / factorisation = %.2f (target <= 1.3)\n",
                g_iteration_s / g_factorization_s);
  }
  std::printf("contact step %.1f ms\nBLAS/LAPACK mapped into this process:\n%s", g_step_s * 1e3,
              loaded_blas().c_str());
  benchmark::Shutdown();
  return 0;
}
