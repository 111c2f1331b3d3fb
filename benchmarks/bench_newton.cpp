// Newton iteration, CHOLMOD numeric factorisation and a whole forward time step on the paper's
// meshes (configs/{ball,star,bunny,cube}.yaml, the reference material Y = 1e13), at the start of
// each scene's first contact step. Prints, per scene and measured in one run, the ratio Newton
// iteration / factorisation (target <= 1.3, SPEC section 10) beside the absolute times, and the
// BLAS library actually mapped into the process.
//
//   ./build/benchmarks/bench_newton [--scenes=ball,star,bunny,cube] [--configs=configs]
//                                   [--benchmark_repetitions=3]

#include <benchmark/benchmark.h>

#include <Eigen/CholmodSupport>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "bench_common.hpp"
#include "rbaa/scene/scene_mesh.hpp"
#include "rbaa/scene/scene_world.hpp"
#include "rbaa/sim/barrier_stiffness.hpp"
#include "rbaa/sim/simulator.hpp"

namespace {

struct Fixture {
  std::string name;
  std::unique_ptr<rbaa::Simulator> sim;
  Eigen::VectorXd q0, v0;
  rbaa::BdfIntegrator saved{rbaa::Integrator::kBdf2, 0.01};            // before the contact step
  rbaa::BdfIntegrator before_previous{rbaa::Integrator::kBdf2, 0.01};  // one step earlier
  Eigen::VectorXd x;  // the first Newton iterate of the contact step
  int contact_step = 0;
  int run_iterations = 0;  // Newton iterations of the contact step in the run from q0
};

// Brings the simulator to the start of the contact step in the same state every time: the
// integrator of two steps back, the Newton solver's factor forgotten, then the step before
// contact taken (untimed by the callers), which leaves its factor and chord flag for the contact
// step's chord start as a run does. Restoring the integrator alone left the previous contact
// step's own converged factor in the solver, so each repetition's chord start differed from the
// run's and from the repetition before. The step before contact starts without a chord step (the
// run's had one): its solution agrees with the run's within Newton's tolerance, and is the same
// in every repetition. The simulator's step count and time carry over (no public setter): in
// these scenes, without driven vertices, they only name the step in error messages.
void start_contact_step(Fixture& f) {
  if (f.contact_step == 1) {
    f.sim->reset(f.q0, f.v0);  // forgets the factor too
    return;
  }
  f.sim->integrator() = f.before_previous;
  f.sim->newton().forget_factor();
  f.sim->advance();
}

std::unique_ptr<Fixture> make_fixture(const rbaa_bench::Options& o, const std::string& name) {
  auto f = std::make_unique<Fixture>();
  f->name = name;
  const rbaa::Scene scene = rbaa_bench::load(o, name);
  const rbaa::TetMesh mesh = rbaa::make_scene_mesh(scene);
  const double kappa = rbaa::scene_barrier_stiffness(scene, mesh);
  f->sim = std::make_unique<rbaa::Simulator>(
      mesh,
      rbaa::MaterialField::uniform(mesh.num_tets(), scene.reference_Y, scene.reference_nu,
                                   scene.reference_rho),
      rbaa::simulation_settings(scene, kappa));
  f->q0 = f->sim->rest_positions();
  f->v0 = rbaa::rigid_velocities(f->q0, scene.position, scene.velocity, scene.angular_velocity);
  f->sim->reset(f->q0, f->v0);
  // Advance until a step ends within d_hat of an obstacle: that step is the contact step.
  f->saved = f->sim->integrator();
  for (int k = 0; k < 400; ++k) {
    f->before_previous = f->saved;
    f->saved = f->sim->integrator();
    const rbaa::StepStats s = f->sim->advance();
    if (s.active_pairs > 0) {
      f->contact_step = k + 1;
      f->run_iterations = s.newton_iterations;
      break;
    }
  }
  f->sim->integrator() = f->saved;
  f->x = f->sim->integrator().current();
  f->sim->inertia_form().set_predictor(f->sim->integrator().predictor());
  f->sim->potential().solution_changed(f->x);
  std::printf(
      "%s: %d vertices, %d tets, %d dofs; contact step %d (%d Newton iterations in the run)\n",
      name.c_str(), f->sim->rest_mesh().num_vertices(), f->sim->rest_mesh().num_tets(),
      f->sim->num_dofs(), f->contact_step, f->run_iterations);
  return f;
}

// The same Hessian with CHOLMOD's simplicial LL^T (no dense supernodal blocks, no BLAS): issue 15
// asks which of the two is faster at these sizes. Its symbolic analysis runs once, outside.
void BM_FactorizationSimplicial(benchmark::State& state, Fixture* f) {
  rbaa::IncrementalPotential& E = f->sim->potential();
  const Eigen::SparseMatrix<double> H = E.hessian(f->x, rbaa::HessianKind::kProjected);
  Eigen::CholmodSimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower> llt;
  llt.analyzePattern(H);
  // CHOLMOD's own rule (supernodal_switch, default 40) picks supernodal when flops / nnz(L) >= 40.
  state.counters["flops_per_lnz"] = llt.cholmod().fl / llt.cholmod().lnz;
  for (auto _ : state) {
    llt.factorize(H);
    benchmark::DoNotOptimize(llt.info());
  }
}

// One Newton iteration: gradient, projected Hessian assembly, factorisation, solve.
void BM_NewtonIteration(benchmark::State& state, Fixture* f) {
  rbaa::IncrementalPotential& E = f->sim->potential();
  rbaa::LinearSolver& solver = f->sim->newton().linear_solver();
  for (auto _ : state) {
    const Eigen::VectorXd g = E.gradient(f->x);
    const Eigen::SparseMatrix<double>& H = E.hessian(f->x, rbaa::HessianKind::kProjected);
    solver.factorize(H, f->sim->hessian_pattern().pattern_version());
    benchmark::DoNotOptimize(solver.solve(g));
  }
}

// Gradient and projected Hessian assembly (everything of an iteration but CHOLMOD).
void BM_Assembly(benchmark::State& state, Fixture* f) {
  rbaa::IncrementalPotential& E = f->sim->potential();
  for (auto _ : state) {
    benchmark::DoNotOptimize(E.gradient(f->x));
    benchmark::DoNotOptimize(E.hessian(f->x, rbaa::HessianKind::kProjected).nonZeros());
  }
}

void BM_Factorization(benchmark::State& state, Fixture* f) {
  rbaa::IncrementalPotential& E = f->sim->potential();
  rbaa::LinearSolver& solver = f->sim->newton().linear_solver();
  const Eigen::SparseMatrix<double> H = E.hessian(f->x, rbaa::HessianKind::kProjected);
  const auto pattern = f->sim->hessian_pattern().pattern_version();  // after assembling
  for (auto _ : state) benchmark::DoNotOptimize(solver.factorize(H, pattern));
}

// The whole contact step (all its Newton iterations), each time from the same state.
void BM_ForwardStep(benchmark::State& state, Fixture* f) {
  int iterations = 0;
  for (auto _ : state) {
    state.PauseTiming();
    start_contact_step(*f);
    state.ResumeTiming();
    iterations = f->sim->advance().newton_iterations;
  }
  state.counters["newton_iterations"] = iterations;
}

}  // namespace

int main(int argc, char** argv) {
  const rbaa_bench::Options options =
      rbaa_bench::parse_options(argc, argv, {"ball", "star", "bunny", "cube"});
  benchmark::Initialize(&argc, argv);
  std::vector<std::unique_ptr<Fixture>> fixtures;
  for (const std::string& name : options.scenes) {
    fixtures.push_back(make_fixture(options, name));
    Fixture* f = fixtures.back().get();
    benchmark::RegisterBenchmark(("NewtonIteration/" + name).c_str(), BM_NewtonIteration, f)
        ->Unit(benchmark::kMillisecond)->UseRealTime();
    benchmark::RegisterBenchmark(("Assembly/" + name).c_str(), BM_Assembly, f)
        ->Unit(benchmark::kMillisecond)->UseRealTime();
    benchmark::RegisterBenchmark(("Factorization/" + name).c_str(), BM_Factorization, f)
        ->Unit(benchmark::kMillisecond)->UseRealTime();
    benchmark::RegisterBenchmark(("FactorizationSimplicial/" + name).c_str(), BM_FactorizationSimplicial, f)
        ->Unit(benchmark::kMillisecond)->UseRealTime();
    benchmark::RegisterBenchmark(("ForwardStep/" + name).c_str(), BM_ForwardStep, f)
        ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
  }
  rbaa_bench::RecordingReporter reporter(options.cpu_time);
  benchmark::RunSpecifiedBenchmarks(&reporter);

  std::printf("\n%-6s %8s %14s %10s %10s %14s %12s %12s\n", "scene", "dofs", "Newton it (ms)",
              "assembly", "factor", "it / factor", "contact step", "simplicial");
  std::printf("%-6s %8s %14s %10s %10s %14s %12s %12s\n", "", "", "", "(ms)", "(ms)", "(<= 1.3)", "(ms)",
              "/ factor");
  for (const auto& f : fixtures) {
    const std::string& n = f->name;
    const double it = reporter.time("NewtonIteration/" + n), as = reporter.time("Assembly/" + n),
                 fa = reporter.time("Factorization/" + n), st = reporter.time("ForwardStep/" + n),
                 si = reporter.time("FactorizationSimplicial/" + n);
    std::printf("%-6s %8d %14.2f %10.2f %10.2f %14.2f %12.1f %12.2f\n", n.c_str(), f->sim->num_dofs(),
                it * 1e3, as * 1e3, fa * 1e3, fa > 0 ? it / fa : 0.0, st * 1e3, fa > 0 ? si / fa : 0.0);
  }
  std::printf("\n(%s time)\nBLAS/LAPACK mapped into this process:\n%s", options.cpu_time ? "CPU" : "wall", rbaa_bench::loaded_blas().c_str());
  benchmark::Shutdown();
  return 0;
}
