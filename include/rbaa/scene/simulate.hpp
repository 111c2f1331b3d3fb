#pragma once
// The `rbaa simulate` pipeline as a library call: a scene, its placed mesh and a material field go
// in, a Trajectory with everything needed to report it comes out; write_simulation_outputs turns
// it into the per-step CSV, the ParaView series and report.json.

#include <Eigen/Core>

#include <functional>
#include <string>
#include <vector>

#include "rbaa/material/material_field.hpp"
#include "rbaa/mesh/tet_mesh.hpp"
#include "rbaa/scene/scene.hpp"
#include "rbaa/scene/scene_world.hpp"
#include "rbaa/sim/observables.hpp"
#include "rbaa/sim/simulator.hpp"
#include "rbaa/sim/trajectory.hpp"

namespace rbaa {

struct SimulationOptions {
  /// Barrier stiffness; <= 0: scene_barrier_stiffness(scene, mesh) (the reference scene's rule).
  double kappa = 0;
  /// Called after every step (e.g. progress on stderr).
  Simulator::StepCallback on_step;
  /// Called after every accepted Newton iteration (diagnosing a step that does not converge).
  NewtonSolver::IterationCallback on_newton_iteration;
};

/// Per-position observables (index k = position q_k, k = 0 .. N, on the grid of h: sub-steps of
/// contact-resolving steps are left out): the object's motion (the first
/// body's), the whole system's momenta and contact distances.
struct StepObservables {
  double time = 0;
  Eigen::Vector3d centre_of_mass = Eigen::Vector3d::Zero();
  Eigen::Vector3d com_velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d linear_momentum = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_momentum = Eigen::Vector3d::Zero();  ///< about the origin
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< best fit from q_0
  double min_distance = 0;           ///< to any plane (m)
  std::vector<double> plane_distance;  ///< per plane (m)
  std::vector<Eigen::Vector3d> body_centres;  ///< centres of mass of the further bodies
};

struct SimulationRun {
  TetMesh mesh;  ///< rest shape: the placed reference mesh (then the further bodies', stacked)
  MaterialField materials;
  std::vector<Body> bodies;  ///< the object, then the scene's further bodies
  SimulationSettings settings;
  bool kappa_from_rule = false;
  Trajectory trajectory;
  Eigen::VectorXd vertex_masses;
  std::vector<StepObservables> observables;  ///< N + 1 entries
  std::vector<Bounce> bounces;
  double setup_seconds = 0;
  double simulate_seconds = 0;
  /// The run's wall time: set-up and simulation (what `rbaa evaluate` reports per run).
  double seconds() const { return setup_seconds + simulate_seconds; }
};

/// The centre-of-mass velocity of run.bodies[b] (of the whole mesh when the run has no bodies)
/// at trajectory frame j, weighted by the run's vertex masses.
Eigen::Vector3d body_velocity(const SimulationRun& run, int b, int frame);

/// Simulates the scene (its time step, duration, obstacles, gravity, initial velocity and spin
/// about scene.position) for the placed mesh with the given materials. Throws rbaa::InputError on
/// bad input and rbaa::SolverError naming the step when a step fails.
SimulationRun run_simulation(const Scene& scene, const TetMesh& placed_mesh,
                             const MaterialField& materials, const SimulationOptions& options = {});

/// Observables of every position of a trajectory on the grid of h (Trajectory::grid_frames).
std::vector<StepObservables> compute_observables(Simulator& simulator,
                                                 const Trajectory& trajectory);

struct OutputOptions {
  int vtu_every = 1;  ///< write every k-th position as .vtu (0: none)
};

/// Writes DIR/trajectory.csv (one row per position: time, centre of mass, linear and angular
/// momentum, orientation quaternion, minimum contact distance, Newton iterations of the step that
/// produced it), DIR/frames/frame_NNNNN.vtu + DIR/trajectory.pvd, and DIR/report.json. Creates DIR.
void write_simulation_outputs(const SimulationRun& run, const Scene& scene, const std::string& dir,
                              const OutputOptions& options = {});

}  // namespace rbaa
