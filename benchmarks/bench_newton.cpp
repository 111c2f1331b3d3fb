// Newton iteration, CHOLMOD numeric factorisation and a whole forward time step on the paper's
// meshes (configs/{ball,star,bunny,cube}.yaml, the reference material Y = 1e13), inside each
// scene's contact step: the first step in which Newton iterates inside contact (an iterate within
// d_hat of an obstacle, where the barrier is non-zero, from which Newton takes a line-searched
// step). The Newton iteration is NewtonSolver::minimize's own, at the first such iterate of that
// step. Prints, per scene and measured in one run, the ratio Newton iteration / factorisation
// (SPEC section 10 asks for it; the README's target is <= 1.3) beside the absolute times and the
// timed iterate's active pairs, and the BLAS library actually mapped into the process.
//
//   ./build/benchmarks/bench_newton [--scenes=ball,star,bunny,cube] [--configs=configs]
//                                   [--benchmark_repetitions=3]

#include <benchmark/benchmark.h>

#include <Eigen/CholmodSupport>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench_common.hpp"
#include "rbaa/scene/scene_mesh.hpp"
#include "rbaa/scene/scene_world.hpp"
#include "rbaa/sim/barrier_stiffness.hpp"
#include "rbaa/sim/simulator.hpp"

namespace {

// Sees every iterate the Newton solver moves to (IncrementalPotential::solution_changed passes it
// to each form): the public API's only window on a step's iterates. No energy; added with weight
// 0, it costs the potential an empty call per form loop (tens of ns) when not recording.
class IterateRecorder : public rbaa::Form {
 public:
  const char* name() const override { return "iterate recorder"; }
  double value(const Eigen::VectorXd&) const override { return 0; }
  void add_gradient(const Eigen::VectorXd&, double, Eigen::VectorXd&) const override {}
  void add_hessian(const Eigen::VectorXd&, double, rbaa::HessianKind,
                   rbaa::SparseHessian&) const override {}
  void solution_changed(const Eigen::VectorXd& q) override {
    if (recording) latest = q;
  }
  bool recording = false;
  Eigen::VectorXd latest;
};

// One line-searched Newton iteration of a step: the iterate at which its Hessian was assembled
// (after the rigid sub-step, if one was taken) and what the iteration did from there.
struct Iterate {
  Eigen::VectorXd x;
  int active_pairs = 0;
  rbaa::NewtonIteration info;
};

struct Fixture {
  std::string name;
  std::unique_ptr<rbaa::Simulator> sim;
  Eigen::VectorXd q0, v0;
  rbaa::BdfIntegrator saved{rbaa::Integrator::kBdf2, 0.01};            // before the contact step
  rbaa::BdfIntegrator before_previous{rbaa::Integrator::kBdf2, 0.01};  // one step earlier
  IterateRecorder recorder;
  int contact_step = 0;
  int run_iterations = 0;         // Newton iterations of the contact step in the run from q0
  int step_iterations = 0;        // the same, in the contact step the benchmarks replay
  std::vector<Iterate> iterates;  // the replayed contact step's line-searched iterations
  int timed = 0;                  // index in iterates of the timed one: the first inside contact
  Eigen::VectorXd x;              // iterates[timed].x
  rbaa::HessianKind kind = rbaa::HessianKind::kProjected;  // the Hessian the step used there
  bool timed_ran = false;
  rbaa::NewtonIteration timed_info;  // what the last timed iteration did (compared with the step's)
};

int active_pairs(rbaa::Simulator& sim, const Eigen::VectorXd& x) {
  int n = sim.contact_form().num_active_pairs(x);
  if (sim.mesh_obstacle_form()) n += sim.mesh_obstacle_form()->num_active_pairs(x);
  if (sim.body_contact_form()) n += sim.body_contact_form()->num_active_pairs(x);
  return n;
}

// One step, recording its line-searched Newton iterations.
rbaa::StepStats advance_recording(Fixture& f, std::vector<Iterate>& iterates) {
  rbaa::Simulator& sim = *f.sim;
  iterates.clear();
  f.recorder.recording = true;
  sim.newton().set_iteration_callback([&](const std::string&, const rbaa::NewtonIteration& it) {
    iterates.push_back({f.recorder.latest, active_pairs(sim, f.recorder.latest), it});
  });
  const rbaa::StepStats s = sim.advance();
  sim.newton().set_iteration_callback({});
  f.recorder.recording = false;
  return s;
}

// The first of `iterates` inside contact, or -1.
int first_in_contact(const std::vector<Iterate>& iterates) {
  for (std::size_t k = 0; k < iterates.size(); ++k) {
    if (iterates[k].active_pairs > 0) return int(k);
  }
  return -1;
}

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
  rbaa::Simulator& sim = *f->sim;
  sim.potential().add(f->recorder, 0.0);
  f->q0 = sim.rest_positions();
  f->v0 = rbaa::rigid_velocities(f->q0, scene.position, scene.velocity, scene.angular_velocity);
  sim.reset(f->q0, f->v0);
  // The contact step: the first in which Newton iterates inside contact. The first step that
  // merely ends within d_hat can be no contact for Newton: the cube's (step 24) ends 173 pairs
  // deep after one factorisation at the ballistic guess, its barrier too weak there to move
  // anything beyond the tolerance; its impact is the next step.
  f->saved = sim.integrator();
  std::vector<Iterate> iterates;
  for (int k = 0; k < 400 && f->contact_step == 0; ++k) {
    f->before_previous = f->saved;
    f->saved = sim.integrator();
    const rbaa::StepStats s = advance_recording(*f, iterates);
    if (first_in_contact(iterates) >= 0) {
      f->contact_step = k + 1;
      f->run_iterations = s.newton_iterations;
    }
  }
  if (f->contact_step == 0)
    throw std::runtime_error(name + ": no Newton iterate in contact in 400 steps");
  // The contact step as the benchmarks replay it (start_contact_step), recorded. Afterwards the
  // forms stay set up for it (step weight, predictor, history lag), as the per-iteration
  // benchmarks need.
  start_contact_step(*f);
  f->step_iterations = advance_recording(*f, f->iterates).newton_iterations;
  f->timed = first_in_contact(f->iterates);
  if (f->timed < 0)
    throw std::runtime_error(name + ": the replayed contact step has no iterate in contact");
  const Iterate& t = f->iterates[f->timed];
  f->x = t.x;
  f->kind = t.info.exact_hessian ? rbaa::HessianKind::kExact : rbaa::HessianKind::kProjected;
  std::printf(
      "%s: %d vertices, %d tets, %d dofs; contact step %d (%d Newton iterations in the run, "
      "%d replayed); timed: its iteration %d, %d active pairs, %s Hessian, step velocity "
      "%.3g m/s, CCD bound %.3g, step %.3g\n",
      name.c_str(), sim.rest_mesh().num_vertices(), sim.rest_mesh().num_tets(), sim.num_dofs(),
      f->contact_step, f->run_iterations, f->step_iterations, t.info.iteration + 1, t.active_pairs,
      t.info.exact_hessian ? "exact" : "projected", t.info.step_velocity, t.info.max_step_fraction,
      t.info.step_fraction);
  return f;
}

// The same Hessian with CHOLMOD's simplicial LL^T (no dense supernodal blocks, no BLAS): issue 15
// asks which of the two is faster at these sizes. Its symbolic analysis runs once, outside.
void BM_FactorizationSimplicial(benchmark::State& state, Fixture* f) {
  rbaa::IncrementalPotential& E = f->sim->potential();
  E.solution_changed(f->x);
  const Eigen::SparseMatrix<double> H = E.hessian(f->x, f->kind);
  Eigen::CholmodSimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower> llt;
  llt.analyzePattern(H);
  // CHOLMOD's own rule (supernodal_switch, default 40) picks supernodal when flops / nnz(L) >= 40.
  state.counters["flops_per_lnz"] = llt.cholmod().fl / llt.cholmod().lnz;
  for (auto _ : state) {
    llt.factorize(H);
    benchmark::DoNotOptimize(llt.info());
  }
}

struct StopNewton {};

// One Newton iteration as NewtonSolver::minimize does it, at the contact step's first iterate in
// contact: the iterate's solution_changed (contact pairs), the gradient, the rigid sub-step (from
// the second iteration on), the Hessian assembly, the factorisation, the solve, the finite-rotation
// transform, and the line search (max_step_size's CCD, is_step_valid, value differences; the line
// minimisation after a halving, the extrapolation after a full step). minimize itself runs, from
// the iterate before (untimed, its iteration callback resumes the clock as that iteration ends)
// so that the timed iteration has the step's history (Hessian kind, last Hessian for the rigid
// sub-step), and the next callback stops it by throwing. The Newton factor is forgotten first: no
// chord step (it precedes the first iteration; the contact step's first iteration comes after it).
void BM_NewtonIteration(benchmark::State& state, Fixture* f) {
  rbaa::IncrementalPotential& E = f->sim->potential();
  rbaa::NewtonSolver& newton = f->sim->newton();
  const bool replay = f->timed > 0;
  const Eigen::VectorXd& start = replay ? f->iterates[f->timed - 1].x : f->x;
  bool timing = true;
  newton.set_iteration_callback([&](const std::string&, const rbaa::NewtonIteration& it) {
    if (!timing) {
      state.ResumeTiming();
      timing = true;
      return;
    }
    state.PauseTiming();
    timing = false;
    f->timed_info = it;
    f->timed_ran = true;
    throw StopNewton{};
  });
  for (auto _ : state) {
    state.PauseTiming();
    timing = false;
    Eigen::VectorXd x = start;
    newton.forget_factor();
    if (!replay) {
      state.ResumeTiming();
      timing = true;
    }
    try {
      newton.minimize(E, x, "bench_newton");
    } catch (const StopNewton&) {
    }
    if (!timing) state.ResumeTiming();
  }
  newton.set_iteration_callback({});
  state.counters["active_pairs"] = f->iterates[f->timed].active_pairs;
  state.counters["step"] = f->timed_info.step_fraction;
}

// Gradient and Hessian assembly at the same iterate (everything of an iteration but CHOLMOD and
// the line search), with the Hessian the contact step used there.
void BM_Assembly(benchmark::State& state, Fixture* f) {
  rbaa::IncrementalPotential& E = f->sim->potential();
  E.solution_changed(f->x);
  for (auto _ : state) {
    benchmark::DoNotOptimize(E.gradient(f->x));
    benchmark::DoNotOptimize(E.hessian(f->x, f->kind).nonZeros());
  }
}

void BM_Factorization(benchmark::State& state, Fixture* f) {
  rbaa::IncrementalPotential& E = f->sim->potential();
  rbaa::LinearSolver& solver = f->sim->newton().linear_solver();
  E.solution_changed(f->x);
  const Eigen::SparseMatrix<double> H = E.hessian(f->x, f->kind);
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

  // "rest": the iteration less assembly and factorisation, i.e. the solve, the line search (CCD,
  // validity, energy differences), the step's transform and the new iterate's contact pairs.
  std::printf("\n%-6s %8s %6s %14s %10s %10s %10s %14s %12s %12s\n", "scene", "dofs", "pairs",
              "Newton it (ms)", "assembly", "factor", "rest", "it / factor", "contact step",
              "simplicial");
  std::printf("%-6s %8s %6s %14s %10s %10s %10s %14s %12s %12s\n", "", "", "", "", "(ms)", "(ms)",
              "(ms)", "(<= 1.3)", "(ms)", "/ factor");
  for (const auto& f : fixtures) {
    const std::string& n = f->name;
    const double it = reporter.time("NewtonIteration/" + n), as = reporter.time("Assembly/" + n),
                 fa = reporter.time("Factorization/" + n), st = reporter.time("ForwardStep/" + n),
                 si = reporter.time("FactorizationSimplicial/" + n);
    std::printf("%-6s %8d %6d %14.2f %10.2f %10.2f %10.2f %14.2f %12.1f %12.2f\n", n.c_str(),
                f->sim->num_dofs(), f->iterates[f->timed].active_pairs, it * 1e3, as * 1e3,
                fa * 1e3, (it - as - fa) * 1e3, fa > 0 ? it / fa : 0.0, st * 1e3,
                fa > 0 ? si / fa : 0.0);
  }
  // The timed iteration must be the step's: the same step velocity, CCD bound and step taken.
  for (const auto& f : fixtures) {
    if (!f->timed_ran) continue;
    const rbaa::NewtonIteration& a = f->iterates[f->timed].info;
    const rbaa::NewtonIteration& b = f->timed_info;
    const bool same = a.step_velocity == b.step_velocity &&
                      a.max_step_fraction == b.max_step_fraction &&
                      a.step_fraction == b.step_fraction && a.exact_hessian == b.exact_hessian;
    std::printf(
        "%s: timed iteration %s the contact step's (step velocity %.6g / %.6g m/s, CCD bound "
        "%.4g / %.4g, step %.4g / %.4g, %s / %s Hessian)\n",
        f->name.c_str(), same ? "is" : "DIFFERS FROM", b.step_velocity, a.step_velocity,
        b.max_step_fraction, a.max_step_fraction, b.step_fraction, a.step_fraction,
        b.exact_hessian ? "exact" : "projected", a.exact_hessian ? "exact" : "projected");
  }
  std::printf("\n(%s time)\nBLAS/LAPACK mapped into this process:\n%s", options.cpu_time ? "CPU" : "wall", rbaa_bench::loaded_blas().c_str());
  benchmark::Shutdown();
  return 0;
}
