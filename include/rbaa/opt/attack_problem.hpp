#pragma once
// One attack problem built from a scene (issue 19, "Layout"): the sequence that rbaa attack,
// rbaa gradcheck, rbaa study and the gradient benchmarks all need, written once.
//
//   scene -> placed meshes (the object and the further bodies, stacked: SceneWorld)
//         -> kappa (the reference scene's, frozen) -> simulation settings
//         -> reference run (the attacked body uniform at the reference material, every other
//            body its own material)
//         -> objective (the config's `objective`; default: the attacked body's undirected term)
//         -> design space (the world's, masked to the attacked body: attack body A, score body B)
//         -> trajectory gradient function theta -> C, dC/dtheta.
//
// A scene without further bodies is the single-body problem of SPEC section 4, bit for bit.

#include <Eigen/Core>
#include <cstddef>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "rbaa/diff/adjoint.hpp"
#include "rbaa/diff/trajectory_gradient.hpp"
#include "rbaa/diff/trajectory_objective.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/material/design_space.hpp"
#include "rbaa/mesh/tet_mesh.hpp"
#include "rbaa/scene/scene.hpp"
#include "rbaa/scene/scene_world.hpp"
#include "rbaa/sim/simulator.hpp"

namespace rbaa {

/// A reference run: the world at the reference materials from q0, v0
/// (AttackProblem::run_reference).
struct ReferenceRun {
  std::unique_ptr<Simulator> simulator;  ///< as left by the run
  Trajectory trajectory;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();         ///< c_A(T) (m)
  Eigen::Vector3d scored_com = Eigen::Vector3d::Zero();  ///< c_B(T) (m)
};

/// How a reference run is made from its simulator; empty: reference.run(q0, v0) once.
using ReferenceRunner = std::function<Trajectory(Simulator& reference, const Eigen::VectorXd& q0,
                                                 const Eigen::VectorXd& v0)>;

struct AttackProblemOptions {
  /// The attacked body: "object" or a name from scene.bodies; empty: the scene's attack.body.
  std::string attacked_body;
  /// The design's fields; empty: the scene's attack.fields.
  std::vector<DesignField> fields;
  /// The object's placed mesh when the caller has one (the study's mesh sweep; it must outlive
  /// the call); null: make_scene_mesh(scene).
  const TetMesh* object_mesh = nullptr;
  /// Barrier stiffness; <= 0: scene_barrier_stiffness(scene, object mesh).
  double kappa = 0;
  FactorStorage storage = FactorStorage::kStore;
  /// Stored factors that would take more than this (the reference run's factor times its steps)
  /// are rebuilt in the backward pass instead (SPEC section 10's memory budget).
  std::size_t stored_factor_budget = std::numeric_limits<std::size_t>::max();
  /// Build the gradient function (false: everything up to the design space).
  bool with_gradient = true;
  /// How the reference run is made; default reference.run(q0, v0) once (the study times it).
  ReferenceRunner run_reference;
  /// Stage messages: "meshing the reference object", "simulating the reference object".
  std::function<void(const std::string&)> on_stage;
};

/// The attacked body's part of a world run that the reports need.
struct BodyFinalState {
  double gap = 0;      ///< sqrt(||q_A(T) - q_A,ref(T)||^2_Mref / m0_A) (m)
  double com_gap = 0;  ///< |c_A(T) - c_A,ref(T)| (m)
  Eigen::Vector3d scored_com = Eigen::Vector3d::Zero();  ///< c_B(T) (m)
};

/// A world run with A's materials replaced: the objective's trajectory term and A's figures.
struct BodyRun {
  double objective = 0;  ///< the objective's trajectory term (no moment term)
  BodyFinalState state;
};

/// A world with the attacked body's mesh replaced (AttackProblem::with_body): what simulating and
/// differentiating it needs.
struct ReplacedWorld {
  TetMesh mesh;              ///< stacked, the replacement in the attacked body's place
  std::vector<Body> bodies;  ///< the ranges in `mesh`
  MaterialField materials;   ///< the replacement's, then the others' fixed ones, stacked
  SimulationSettings settings;
  Eigen::VectorXd q0, v0;  ///< 3 #V
  /// The reference run's final positions at the replacement's vertices (through vertex_origin)
  /// and the other bodies'.
  Eigen::VectorXd reference_final;
  std::shared_ptr<const TrajectoryObjective> objective;
  std::shared_ptr<const UndirectedTrajectoryObjective> gap;
};

struct AttackProblem {
  Scene scene;
  SceneWorld world;  ///< every body placed and stacked, the object first
  int attacked = 0;  ///< the attacked body A (index into world.bodies)
  int scored = 0;    ///< the objective's body B
  /// A's placed mesh alone (its own vertex and element indices): the domain of its moments, its
  /// occupancy smoothing and its post-processing. The world's mesh for a single body.
  TetMesh body_mesh;
  double kappa = 0;
  SimulationSettings settings;  ///< with world.bodies when there are several
  Eigen::VectorXd q0, v0;       ///< the world's initial positions and velocities (3 #V)
  /// The world's reference material: A uniform at the scene's reference material, every other
  /// body its own (the reference material or its materials file).
  MaterialField reference_materials;
  std::unique_ptr<Simulator> reference_simulator;  ///< as left by the reference run
  Trajectory reference;
  Moments reference_moments;  ///< A's, at the reference material, about the origin
  Eigen::Vector3d reference_com = Eigen::Vector3d::Zero();         ///< c_A(T) of the reference run
  Eigen::Vector3d scored_reference_com = Eigen::Vector3d::Zero();  ///< c_B(T) of the reference run
  double scored_length = 0;  ///< L_B, B's radius of gyration at the reference material (m)
  std::shared_ptr<const TrajectoryObjective> objective;
  /// A's undirected term, whatever the objective: its gap in metres for progress and reports.
  std::shared_ptr<const UndirectedTrajectoryObjective> gap;
  /// The world's design space, masked to A; every other element holds reference_materials.
  std::unique_ptr<DesignSpace> design;
  /// The same layout on body_mesh (moments, smoothing, post-processing work on A alone).
  std::unique_ptr<DesignSpace> body_design;
  FactorStorage storage = FactorStorage::kStore;  ///< after the memory budget
  std::string storage_note;  ///< why stored factors were switched to rebuilt (empty: they were not)
  std::unique_ptr<TrajectoryGradientFunction> gradient;  ///< null without with_gradient

  const Body& body() const { return world.bodies[attacked]; }
  bool several_bodies() const { return world.bodies.size() > 1; }
  /// The world's field with A's elements from `body_field` (#T_A) and the others' from
  /// reference_materials. Throws rbaa::InputError naming `source` if it does not fit A.
  MaterialField world_materials(const MaterialField& body_field,
                                const std::string& source = "materials") const;
  /// A's elements of a world field (#T_A).
  MaterialField body_materials(const MaterialField& world_field) const;
  /// The reference run under `settings` (the problem's own, or at a finer step for the
  /// refinement check): world.mesh at reference_materials from q0, v0, made by `runner`, with A's
  /// and B's centres of mass at T. Throws rbaa::SolverError if the run fails.
  ReferenceRun run_reference(const SimulationSettings& settings,
                             const ReferenceRunner& runner = {}) const;
  /// A's report figures of a world run with the given (world) materials.
  BodyFinalState final_state(const Eigen::VectorXd& q_final, const MaterialField& materials) const;
  /// Simulates the world with A's elements at `body_field` (#T_A) and the others at
  /// reference_materials, from q0, v0. Throws rbaa::SolverError if the run fails.
  BodyRun simulate(const MaterialField& body_field) const;
  /// Sets scene.Y0, scene.nu0 and rebuilds design, body_design and (if there was one) gradient
  /// on them: the same layout and maps, the new initial material (attack.start: best_uniform).
  void start_from(double Y0, double nu0);
  /// A new gradient function on the current *design (e.g. after hold_fixed_fields).
  std::unique_ptr<TrajectoryGradientFunction> make_gradient(FactorStorage storage) const;
  /// The world with A's mesh replaced by `mesh` (placed; vertex i was A's vertex vertex_origin[i],
  /// e.g. the final object without its voids) and its materials by `materials` (#T of mesh), with
  /// the objective and gap rebuilt on it. A single body gives mesh alone. `reference_final`
  /// (3 #V of the world), if given, replaces the reference run's final positions (a reference
  /// run at another step).
  ReplacedWorld with_body(const TetMesh& mesh, const MaterialField& materials,
                          const std::vector<int>& vertex_origin,
                          const Eigen::VectorXd* reference_final = nullptr) const;
};

/// Builds the problem. Throws rbaa::InputError on bad input (an unknown body, an objective that
/// does not fit the world) and rbaa::SolverError naming the step if the reference run fails.
AttackProblem build_attack_problem(const Scene& scene, const AttackProblemOptions& options = {});

/// The objective of `spec` on a world: B = bodies[scored], `reference_final` the reference run's
/// final positions (3 #V), c_B,ref and L_B as in AttackProblem.
std::shared_ptr<const TrajectoryObjective> make_objective(
    const ObjectiveSpec& spec, const TetMesh& mesh, const std::vector<Body>& bodies, int scored,
    double reference_rho, const Eigen::VectorXd& reference_final,
    const Eigen::Vector3d& scored_reference_com, double scored_length);

/// The centre of mass of one body of a stacked mesh with per-element density (#T, rho alpha).
Eigen::Vector3d body_centre_of_mass(const Eigen::VectorXd& q, const TetMesh& mesh,
                                    const Eigen::VectorXd& density, const Body& body);

/// The index of the body named `name` ("object" is the first) in a scene's world; throws
/// rbaa::InputError naming `what` and the value otherwise.
int body_index(const Scene& scene, const std::string& name, const std::string& what);

}  // namespace rbaa
