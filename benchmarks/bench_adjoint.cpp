// The whole gradient on a scene (default: the paper's ball, configs/ball.yaml): forward run,
// adjoint with stored Newton factors and with rebuilt ones, at the attack's perturbed starting
// design. Prints absolute times, the ratios SPEC section 3 targets (gradient / forward <= 1.10;
// backward time per step <= 0.25 x one numeric factorisation when factors are stored) and the
// memory the stored factors take.
//
//   ./build/benchmarks/bench_adjoint [--config=configs/ball.yaml] [--set=key=value;...] [--repeat=3]

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "rbaa/diff/trajectory_gradient.hpp"
#include "rbaa/material/design_space.hpp"
#include "rbaa/scene/scene.hpp"
#include "rbaa/scene/scene_mesh.hpp"
#include "rbaa/sim/barrier_stiffness.hpp"
#include "rbaa/sim/simulator.hpp"

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// BLAS/LAPACK libraries mapped into this process (which one CHOLMOD really calls).
std::string loaded_blas() {
  std::ifstream maps("/proc/self/maps");
  std::set<std::string> libs;
  for (std::string line; std::getline(maps, line);) {
    const auto slash = line.find('/');
    if (slash == std::string::npos) continue;
    const std::string path = line.substr(slash);
    if (path.find("blas") != std::string::npos || path.find("lapack") != std::string::npos ||
        path.find("atlas") != std::string::npos) {
      libs.insert(path);
    }
  }
  std::string s;
  for (const auto& l : libs) s += (s.empty() ? "" : ", ") + l;
  return s.empty() ? "(none found)" : s;
}

}  // namespace

int main(int argc, char** argv) {
  std::string config = "configs/ball.yaml";
  std::vector<std::string> overrides;
  int repeat = 3;
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--config=", 9) == 0) config = argv[i] + 9;
    else if (std::strncmp(argv[i], "--set=", 6) == 0) {
      std::string s = argv[i] + 6;
      for (std::size_t p = 0; p != std::string::npos;) {
        const std::size_t q = s.find(';', p);
        overrides.push_back(s.substr(p, q == std::string::npos ? q : q - p));
        p = q == std::string::npos ? q : q + 1;
      }
    } else if (std::strncmp(argv[i], "--repeat=", 9) == 0) repeat = std::max(1, std::atoi(argv[i] + 9));
  }
  const rbaa::Scene scene = rbaa::load_scene(config, overrides);
  const rbaa::TetMesh mesh = rbaa::make_scene_mesh(scene);
  const double kappa = rbaa::scene_barrier_stiffness(scene, mesh);
  const rbaa::SimulationSettings settings = rbaa::simulation_settings(scene, kappa);
  const Eigen::VectorXd q0 = Eigen::Map<const Eigen::VectorXd>(mesh.V.data(), 3 * mesh.num_vertices());
  const Eigen::VectorXd v0 = rbaa::rigid_velocities(q0, scene.position, scene.velocity, scene.angular_velocity);
  rbaa::Simulator reference(mesh, rbaa::MaterialField::uniform(mesh.num_tets(), scene.reference_Y,
                                                               scene.reference_nu, scene.reference_rho),
                            settings);
  const rbaa::Trajectory ref = reference.run(q0, v0);
  auto objective = rbaa::UndirectedTrajectoryObjective::from_reference(mesh, scene.reference_rho, ref.q.back());
  const rbaa::DesignSpace design(mesh, rbaa::DesignSpaceOptions::from_scene(scene));
  const Eigen::VectorXd theta = design.initial_theta(true);
  std::printf("%s: %d vertices, %d tets, %d dofs, %d steps; BLAS: %s\n", scene.name.c_str(),
              mesh.num_vertices(), mesh.num_tets(), 3 * mesh.num_vertices(), settings.num_steps,
              loaded_blas().c_str());

  rbaa::TrajectoryGradientFunction stored(mesh, settings, q0, v0, design, objective, rbaa::FactorStorage::kStore);
  rbaa::TrajectoryGradientFunction rebuilt(mesh, settings, q0, v0, design, objective, rbaa::FactorStorage::kRebuild);

  // Best of `repeat` for every measurement (the machine is shared).
  double forward = 1e300, grad_store = 1e300, fwd_store = 1e300, bwd_store = 1e300,
         grad_rebuild = 1e300, bwd_rebuild = 1e300, factor_per = 1e300, solve_store = 1e300;
  std::size_t bytes = 0;
  int stored_solves = 0, rebuilt_count = 0, steps = 0, newton = 0;
  for (int r = 0; r < repeat; ++r) {
    auto t0 = std::chrono::steady_clock::now();
    rebuilt.evaluate(theta, nullptr);  // forward only (no factor copies)
    forward = std::min(forward, seconds_since(t0));

    Eigen::VectorXd g;
    t0 = std::chrono::steady_clock::now();
    stored.evaluate(theta, &g);
    grad_store = std::min(grad_store, seconds_since(t0));
    const rbaa::TrajectoryEvaluation& s = stored.last();
    fwd_store = std::min(fwd_store, s.forward_seconds);
    bwd_store = std::min(bwd_store, s.adjoint_seconds);
    solve_store = std::min(solve_store, s.adjoint.solve_seconds);
    bytes = s.stored_factor_bytes;
    stored_solves = s.adjoint.stored_factor_solves;
    steps = s.adjoint.steps;
    newton = 0;
    for (const rbaa::StepStats& st : s.trajectory.steps) newton += st.newton_iterations;

    t0 = std::chrono::steady_clock::now();
    rebuilt.evaluate(theta, &g);
    grad_rebuild = std::min(grad_rebuild, seconds_since(t0));
    const rbaa::TrajectoryEvaluation& b = rebuilt.last();
    bwd_rebuild = std::min(bwd_rebuild, b.adjoint_seconds);
    rebuilt_count = b.adjoint.rebuilt_factorizations;
    if (rebuilt_count > 0) factor_per = std::min(factor_per, b.adjoint.factorization_seconds / rebuilt_count);
  }
  std::printf("forward only            %8.3f s  (%d Newton factorisations over %d steps)\n", forward, newton, steps);
  std::printf("gradient, stored        %8.3f s  = forward %.3f s (with factor copies) + backward %.3f s "
              "(%d solves with stored factors, of which solves %.3f s)\n",
              grad_store, fwd_store, bwd_store, stored_solves, solve_store);
  std::printf("gradient, rebuilt       %8.3f s  = backward %.3f s (%d factorisations, %.4f s each)\n",
              grad_rebuild, bwd_rebuild, rebuilt_count, factor_per);
  std::printf("stored factors          %8.1f MB  (%.2f MB per step)\n", bytes / 1e6,
              bytes / 1e6 / std::max(1, stored_solves));
  std::printf("ratio gradient/forward: stored %.3f (target <= 1.10), rebuilt %.3f\n",
              grad_store / forward, grad_rebuild / forward);
  std::printf("ratio (forward + backward) / forward within the stored evaluation: %.3f\n",
              (fwd_store + bwd_store) / fwd_store);
  std::printf("ratio backward per step / one numeric factorisation: stored %.3f (target <= 0.25), "
              "rebuilt %.3f\n",
              bwd_store / steps / factor_per, bwd_rebuild / steps / factor_per);
  return 0;
}
