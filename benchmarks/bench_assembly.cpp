// The pieces of one Newton iteration's assembly on the paper's meshes, at the rest shape moved
// rigidly (the reference object in flight): the energy gradient, the elastic Hessian (projected
// and exact) written into the element buffers, the per-element SNH eigensystem alone, and the
// gather of the buffers into CHOLMOD's matrix. Shows where assembly time goes (section 2: the
// assembly runs in parallel with per-element precomputation).
//
//   ./build/benchmarks/bench_assembly [--scenes=ball,star,bunny,cube] [--configs=configs]

#include <benchmark/benchmark.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "bench_common.hpp"
#include "rbaa/scene/scene_mesh.hpp"
#include "rbaa/scene/scene_world.hpp"
#include "rbaa/sim/barrier_stiffness.hpp"
#include "rbaa/sim/simulator.hpp"
#include "rbaa/sim/stable_neo_hookean.hpp"

namespace {

struct Fixture {
  std::string name;
  std::unique_ptr<rbaa::Simulator> sim;
  Eigen::VectorXd x;
};

std::unique_ptr<Fixture> make_fixture(const rbaa_bench::Options& o, const std::string& name) {
  auto f = std::make_unique<Fixture>();
  f->name = name;
  const rbaa::Scene scene = rbaa_bench::load(o, name);
  const rbaa::TetMesh mesh = rbaa::make_scene_mesh(scene);
  f->sim = std::make_unique<rbaa::Simulator>(
      mesh,
      rbaa::MaterialField::uniform(mesh.num_tets(), scene.reference_Y, scene.reference_nu,
                                   scene.reference_rho),
      rbaa::simulation_settings(scene, rbaa::scene_barrier_stiffness(scene, mesh)));
  // A slightly strained pose, so that the projection has work to do: 1e-3 of random noise.
  f->x = f->sim->rest_positions();
  const Eigen::VectorXd noise = Eigen::VectorXd::Random(f->x.size());
  f->x += 1e-3 * rbaa::bounding_box_diagonal(mesh) * noise;
  f->sim->inertia_form().set_predictor(f->x);
  std::printf("%s: %d tets\n", name.c_str(), mesh.num_tets());
  return f;
}

void BM_Gradient(benchmark::State& state, Fixture* f) {
  for (auto _ : state) benchmark::DoNotOptimize(f->sim->potential().gradient(f->x));
}

void BM_ElasticHessian(benchmark::State& state, Fixture* f, rbaa::HessianKind kind) {
  rbaa::SparseHessian& H = f->sim->hessian_pattern();
  for (auto _ : state) {
    H.set_zero();
    f->sim->elastic_form().add_hessian(f->x, 1.0, kind, H);
    benchmark::DoNotOptimize(H.element_block(0));
  }
}

void BM_Eigensystems(benchmark::State& state, Fixture* f) {
  const rbaa::ElasticForm& elastic = f->sim->elastic_form();
  for (auto _ : state) {
    double sum = 0;
    for (int e = 0; e < elastic.num_elements(); ++e) {
      sum += rbaa::snh::hessian_eigensystem(elastic.deformation_gradient(f->x, e), elastic.mu(e),
                                            elastic.lambda(e))
                 .values[0];
    }
    benchmark::DoNotOptimize(sum);
  }
}

void BM_Gather(benchmark::State& state, Fixture* f) {
  rbaa::SparseHessian& H = f->sim->hessian_pattern();
  for (auto _ : state) benchmark::DoNotOptimize(H.assemble().nonZeros());
}

void BM_WholeHessian(benchmark::State& state, Fixture* f) {
  for (auto _ : state) {
    benchmark::DoNotOptimize(f->sim->potential().hessian(f->x, rbaa::HessianKind::kProjected).nonZeros());
  }
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
    auto reg = [&](const std::string& label, auto fn) {
      benchmark::RegisterBenchmark((label + "/" + name).c_str(), fn, f)
          ->Unit(benchmark::kMillisecond)->UseRealTime();
    };
    reg("Gradient", BM_Gradient);
    reg("ElasticHessianProjected", [](benchmark::State& s, Fixture* g) {
      BM_ElasticHessian(s, g, rbaa::HessianKind::kProjected);
    });
    reg("ElasticHessianExact", [](benchmark::State& s, Fixture* g) {
      BM_ElasticHessian(s, g, rbaa::HessianKind::kExact);
    });
    reg("Eigensystems", BM_Eigensystems);
    reg("Gather", BM_Gather);
    reg("WholeHessian", BM_WholeHessian);
  }
  rbaa_bench::RecordingReporter reporter(options.cpu_time);
  benchmark::RunSpecifiedBenchmarks(&reporter);
  std::printf("\n%-6s %10s %12s %10s %12s %10s %12s   (ms; eigensystems on one thread)\n", "scene",
              "gradient", "H projected", "H exact", "eigensystems", "gather", "whole H");
  for (const auto& f : fixtures) {
    const std::string& n = f->name;
    std::printf("%-6s %10.2f %12.2f %10.2f %12.2f %10.2f %12.2f\n", n.c_str(),
                1e3 * reporter.time("Gradient/" + n), 1e3 * reporter.time("ElasticHessianProjected/" + n),
                1e3 * reporter.time("ElasticHessianExact/" + n), 1e3 * reporter.time("Eigensystems/" + n),
                1e3 * reporter.time("Gather/" + n), 1e3 * reporter.time("WholeHessian/" + n));
  }
  std::printf("\n(%s time)\nBLAS/LAPACK mapped into this process:\n%s", options.cpu_time ? "CPU" : "wall", rbaa_bench::loaded_blas().c_str());
  benchmark::Shutdown();
  return 0;
}
