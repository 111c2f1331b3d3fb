#pragma once
// A scene: the reference object, the obstacles, the initial state, time stepping, contact and
// solver settings, and the attack's material bounds and optimiser settings. Loaded from YAML
// (configs/<scene>.yaml) by load_scene, which validates every key; SI units throughout.

#include <Eigen/Core>

#include <array>
#include <limits>
#include <string>
#include <vector>

#include "rbaa/sim/world.hpp"

namespace rbaa {

/// Where the reference object's tet mesh comes from: a primitive (meshed with CGAL at load time,
/// deterministically), a closed surface file (meshed likewise) or a tet mesh file.
struct MeshSource {
  std::string shape;         ///< sphere | cube | star | bat | bunny, or empty
  std::string surface_file;  ///< closed surface (.off/.obj/.stl), or empty
  std::string mesh_file;     ///< tet mesh (.msh/.mesh/.node), or empty
  int target_tets = 0;       ///< for shape and surface; 0 = the shape's default
  // Primitive parameters (m); <= 0 means the SPEC's default for the shape.
  double radius = 0;         ///< sphere
  double side = 0;           ///< cube
  // Surfaces: scale so that the tet mesh has this volume (m^3) and centre it (0 = leave as is).
  double volume = 0;
};

/// A body's kinematic (Dirichlet) vertices and their prescribed motion: the `driven` key of
/// `object` or of bodies[i].
///
///   driven:
///     vertices: [3, 17, 40]                       # body-local vertex ids, or a selector:
///     vertices: {toward: [0, 0, -1], count: 14}   # the 14 vertices farthest along toward
///     vertices: {toward: [0, 0, -1], depth: 1e-6} # every vertex within depth (m) of that end
///     vertices: {toward: [0, 0, -1], depth: 0.012, count: 14}
///                                  # of those, the 14 nearest the body's axis along toward
///                                  # (the line through its centre of mass)
///     axis: [0, 0, 1]              # rotation axis (world; normalised; default z)
///     centre: [0, 0, 0]            # a point of the axis at t = 0 (world, m; default origin)
///     angular_velocity: 3.927      # rad/s about axis, right-handed; or a piecewise-linear table
///                                  # [[t, omega], ...] (s, rad/s; times increasing)
///     velocity: [0, 0, 0]          # the axis' translation (m/s)
///
/// A selector's `toward` is in the body's own frame (its mesh's axes, before `rotation`), so that
/// "the knob end" stays the same wherever the scene turns the body. A driven body starts with its
/// drive's rigid motion: its `velocity` and `angular_velocity` keys are refused.
struct DriveSpec {
  bool enabled = false;
  std::string key;            ///< "object.driven" or "bodies[i].driven", for messages
  std::vector<int> vertices;  ///< listed body-local ids (ascending, unique), or empty
  Eigen::Vector3d toward = Eigen::Vector3d::Zero();  ///< selector direction (unit), or zero
  double depth = -1;                                 ///< selector slab depth (m); < 0: not given
  int count = 0;                                     ///< selector count; 0: not given
  PrescribedMotion motion;
};

/// A further body besides the object (bodies[i]): its mesh, initial state and fixed material. The
/// object is the body an attack designs; these keep their material.
struct BodySpec {
  std::string name;  ///< bodies[i].name, unique; default "bodies[i]"
  MeshSource mesh;
  // As the object's: centre of mass at `position` after the rotation about the centre.
  Eigen::Vector3d position = Eigen::Vector3d::Zero();          ///< m
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();          ///< m/s
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  ///< rad/s
  Eigen::Vector3d rotation_axis = Eigen::Vector3d::UnitX();
  double rotation_angle_deg = 0.0;
  /// A materials file (.msh with fields, or materials CSV) for its elements; empty: the scene's
  /// reference material.
  std::string materials_file;
  DriveSpec driven;  ///< its driven vertices (bodies[i].driven), if any
  /// A copy of the run's object (demonstration.object_copies, set by with_object_copies in
  /// scene_world.hpp): make_world gives it the object's placed mesh, turned and moved to this
  /// body's pose, and the object's materials; `mesh` is then unused.
  bool object_copy = false;
};

/// What the attack minimises besides the moment term (the config's `objective` key; SPEC section
/// 4, issue 16). Body B is the scored body, A the attacked one; L_B is B's radius of gyration at
/// the uniform reference density, so that every kind is dimensionless and beta means the same.
struct ObjectiveSpec {
  enum class Kind {
    /// -||q_B(T) - q_B,ref(T)||^2_Mref / (m0_B L_B^2): SPEC section 4's undirected term (the
    /// default, on the attacked body).
    kUndirected,
    /// (c_B(T)[component] - value)^2 / L_B^2: B's final centre of mass towards a value (m).
    kTarget,
    /// -|c_B(T) - c_B,ref(T)|^2 / L_B^2: B's final centre of mass away from where the reference
    /// run put it (the undirected term of B's centre of mass alone).
    kAway,
  };
  Kind kind = Kind::kUndirected;
  std::string body;   ///< "object" or a name from `bodies`; empty: the attacked body
  int component = 0;  ///< 0, 1, 2 for x, y, z (kTarget)
  double value = 0;   ///< m (kTarget)
};

/// "undirected", "target", "away".
const char* objective_kind_name(ObjectiveSpec::Kind kind);

/// What a demonstration checks (the config's `demonstration.predicate`): a yes/no outcome of a
/// run, evaluated on every run of `rbaa evaluate` (eval/demonstration.hpp).
struct PredicateSpec {
  enum class Kind {
    kNone,
    /// The body's centre of mass crosses the disc {x : axis.(x - centre) = 0, |x - centre| <=
    /// radius} against `axis` (downwards for axis +z), within radius minus the body's bounding
    /// radius of the centre: the body's bounding sphere fits through the opening.
    kThroughHoop,
    /// The body's centre of mass ends inside the axis-aligned box [min, max]; with
    /// stays_below_top, it also stays below max.z from the first sample inside the box on.
    kInsideBox,
    /// Each of `bodies` ends with its initial pose's +z within max_tilt_deg of world +z and its
    /// centre of mass above min_height (one height for all, or one per body).
    kStands,
  };
  Kind kind = Kind::kNone;
  std::string body;  ///< through_hoop, inside_box: "object" or a bodies[i].name
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  ///< through_hoop (m)
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();   ///< through_hoop (unit)
  double radius = 0;                                 ///< through_hoop, the opening's radius (m)
  Eigen::Vector3d min = Eigen::Vector3d::Zero(), max = Eigen::Vector3d::Zero();  ///< inside_box
  bool stays_below_top = false;                                                  ///< inside_box
  std::vector<std::string> bodies;                                               ///< stands
  double max_tilt_deg = 10;                                                      ///< stands
  std::vector<double> min_height;  ///< stands: one value, or one per body (m)
};

/// "none", "through_hoop", "inside_box", "stands".
const char* predicate_kind_name(PredicateSpec::Kind kind);

/// The config's `demonstration` block: how `rbaa evaluate` judges each run of a demonstration
/// scene (configs/demos/). Either or both of a predicate and a figure.
struct DemonstrationSpec {
  bool enabled = false;
  PredicateSpec predicate;
  /// The scene's figure per run: "angle" (the angle between the run's centre-of-mass velocity of
  /// `figure_body` at T, the run's end, and a reference run's at T, deg), or "" (none).
  std::string figure;
  std::string figure_body;  ///< "object" or a bodies[i].name; default evaluation.body
  /// Which run the figure is measured against (figure_against): the rigid reference (false,
  /// the default), or the reference run of the same simulator (true: a rigid run against the
  /// rigid reference, a deformable run against the deformable reference), which is the paper's
  /// separation between the reference's and the adversarial's outgoing directions where nothing
  /// turns the velocity between the last contact and T.
  bool figure_against_own_simulator = false;
  /// figure_projection: horizontal. Both velocities are projected onto the plane normal to
  /// gravity first: free flight under gravity leaves that part unchanged, so a body flying on
  /// after its last contact keeps its figure (the 3D angle shrinks as both fall faster).
  bool figure_horizontal = false;
  /// object_copies: names of bodies (bodies[i].name, each once, not the object) that are copies
  /// of each run's object in `rbaa evaluate` and `rbaa export` (with_object_copies,
  /// scene_world.hpp): the object's mesh as that run uses it and that run's materials, at the
  /// body's own pose and velocities. Empty: every body is its own.
  std::vector<std::string> object_copies;
};

/// Closed interval [lo, hi].
struct Range {
  double lo = 0, hi = 0;
};

struct Scene {
  std::string name;
  std::string source;  ///< file the scene was loaded from (for error messages)
  /// The name of the first body (the `object` key's): "object" in every config; the name of a
  /// further body once swap_object (scene_world.hpp) has put that body in the object's place.
  std::string object_name = "object";

  MeshSource mesh;

  // Initial state of the reference object (its centre of mass is placed at `position`, after an
  // optional rotation of `rotation_angle_deg` degrees about `rotation_axis` about the centre).
  Eigen::Vector3d position = Eigen::Vector3d::Zero();          ///< m
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();          ///< m/s
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  ///< rad/s
  Eigen::Vector3d rotation_axis = Eigen::Vector3d::UnitX();
  double rotation_angle_deg = 0.0;
  DriveSpec driven;  ///< the object's driven vertices (object.driven), if any

  /// Further bodies (the config's `bodies` list), stacked after the object in the simulated mesh.
  std::vector<BodySpec> bodies;

  std::vector<Plane> planes;
  std::vector<ObstacleMesh> obstacle_meshes;  ///< read and placed by load_scene
  Eigen::Vector3d gravity{0.0, 0.0, -9.8};  ///< m/s^2; zero when the scene switches it off

  // Time stepping.
  double time_step = 0.01;  ///< h (s)
  double duration = 0.25;   ///< T (s)
  Integrator integrator = Integrator::kBdf2;
  MassModel mass = MassModel::kConsistent;
  /// Contact-resolving steps (SimulationSettings::contact_substeps): 0 off, else k sub-steps of
  /// h/k around contact.
  int contact_substeps = 0;

  // The demonstration (`rbaa evaluate`): its own step and duration, because an attack is built at
  // a step chosen for speed while a demonstration must be accurate enough that the stiff uniform
  // baseline agrees with its rigid twin (README, "Evaluating an attack").
  /// evaluation.time_step: auto (the default) refines the attack's step by factors of 4, at most
  /// evaluation_max_refinements times, until the baseline strays from its calibrated rigid twin
  /// by at most evaluation_baseline_tolerance of its path; a number fixes the step.
  bool evaluation_search_step = true;
  double evaluation_time_step = 0;  ///< s, when not searched; 0: the attack's step
  double evaluation_duration = 0;   ///< s; 0: 4 x the attack's duration
  double evaluation_baseline_tolerance = 0.005;
  int evaluation_max_refinements = 3;
  /// evaluation.body: the body whose centre of mass `rbaa evaluate` compares between runs (gaps,
  /// velocity angles): "" the object (after swap_object: the attacked body in its place), else a
  /// body's name, "object" included (the bat's struck ball).
  std::string evaluation_body;
  /// demonstration: the predicate and figure `rbaa evaluate` reports per run (outcome table).
  DemonstrationSpec demonstration;

  // Contact (IPC log barrier on unsigned distances).
  double d_hat = 1e-3;  ///< activation distance (m)
  double kappa = 0.0;   ///< barrier stiffness (J per unit of b); 0 = choose by the energy rule
  /// Coulomb coefficient of every pair of surfaces that sets none: planes and obstacle meshes
  /// without their own `friction`, pairs of bodies not in `friction_pairs`; 0: none.
  double friction = 0.0;
  /// contact.pairs: coefficients between named bodies, overriding `friction` for them (body 0 is
  /// the object, body i + 1 is bodies[i]).
  std::vector<BodyPairFriction> friction_pairs;
  double friction_eps_v = 1e-3;  ///< friction's smoothing speed (m/s)
  /// contact.friction_iterations: friction lagged up to this many times per step
  /// (SimulationSettings::friction_iterations; forward runs only: `rbaa attack` refuses > 1).
  int friction_iterations = 1;

  // Newton.
  double newton_tolerance = 1e-8;  ///< on ||dq||_inf / h, relative to the rest bbox diagonal per s
  int newton_max_iterations = 100;
  bool newton_rigid_predictor = true;  ///< SimulationSettings::rigid_predictor
  bool newton_chord_start = true;      ///< SimulationSettings::newton_chord_start

  // Reference material (the "as rigid as possible" baseline).
  double reference_Y = 1e13;
  double reference_nu = 0.28;
  double reference_rho = 2500.0;

  // Attack material bounds.
  Range Y_range{2.5e9, 6.5e11};
  Range nu_range{0.2, 0.4};
  Range rho_range{800.0, 11300.0};
  double alpha_min = 1e-3;

  // Attack (optimiser) settings, used by `rbaa attack`.
  /// The attacked body (attack.body): "object" or a name from `bodies`. Its elements are the
  /// design; every other body keeps its material (reference_material or its materials file).
  std::string attack_body = "object";
  /// The objective (top-level `objective`); default: the undirected term of the attacked body.
  ObjectiveSpec objective;
  std::vector<std::string> fields{"Y", "nu", "rho", "alpha"};
  int iterations = 50;
  double learning_rate = 0.05;
  double beta = 1e4;
  double adam_beta1 = 0.7;
  double adam_beta2 = 0.95;
  unsigned seed = 1;
  double perturbation = 0.1;  ///< std. dev. of the initial theta perturbation
  double alpha0 = 0.99;       ///< initial interior occupancy
  /// Initial Young's modulus and Poisson ratio (attack.Y0, attack.nu0); NaN: the middle of the
  /// range (SPEC section 4). Starting at the soft end makes the attack improve on the uniform
  /// soft object that `rbaa evaluate` uses as its control.
  double Y0 = std::numeric_limits<double>::quiet_NaN();
  double nu0 = std::numeric_limits<double>::quiet_NaN();
  /// attack.start: `given` starts from Y0, nu0; `best_uniform` first simulates the attacked body
  /// uniform at Y, nu in {lo, mid, hi} of their ranges (rho the reference's), starts from the one
  /// the objective likes best, and keeps the loop's best iterate if its last is worse
  /// (opt/uniform_start.hpp).
  bool start_best_uniform = false;
  double smoothing_gamma = 1.0;  ///< relative to the mean edge length squared
  bool boundary_by_vertex = false;  ///< fix elements with any boundary vertex (else: boundary face)
  double round_threshold = 0.5;
  /// attack.occupancy_penalty: w_k (weight P + connectivity_weight R) joins the loop's objective,
  /// P the volume-weighted greyness of interior alpha (peaking at round_threshold), R the
  /// interior volume share of the void paths the connectivity repair would fill (their emptiness);
  /// w_k = ramp * the largest |trajectory term| so far, ramp linear from 0 at a fraction
  /// ramp_start of the iterations to 1 at ramp_end (opt/occupancy_penalty.hpp). Both weights 0:
  /// off (P, R and the grey fraction are still reported).
  double occupancy_weight = 0;
  double occupancy_connectivity_weight = 0;
  double occupancy_ramp_start = 0.2;
  double occupancy_ramp_end = 0.8;
  /// attack.occupancy_penalty.repair_in_loop: after every Adam step the elements the
  /// connectivity repair would fill are set to alpha = (1 + round_threshold) / 2.
  bool occupancy_repair_in_loop = false;
  bool project_moments = true;  ///< project Adam steps onto the moments' tangent (attack_loop.hpp)
  /// Adam iterations on Y, nu, rho of the rounded, connected, re-fitted object (attack.cpp's
  /// polish stage); 0 turns it off. Only when alpha is optimised (otherwise nothing is rounded).
  int polish_iterations = 0;
  /// The final object re-simulated, with the reference, at the attack's step divided by this
  /// (attack.refinement_factor; 0 or 1: not done): whether its gap survives a finer step (issue
  /// 20 item 5). Reporting only: it does not change the result.
  int refinement_factor = 2;
};

/// Loads and validates a scene. `overrides` are "key.path=value" assignments applied to the YAML
/// before validation (the command line's --set), after a top-level `base: FILE` (a config beside
/// this one) has been merged under the document. Relative file paths are resolved against the
/// config's folder. Throws rbaa::InputError naming the file and key on unknown keys, wrong types,
/// NaN or out-of-range values.
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});

/// The name of body `index` of the scene's world: scene.object_name for 0, bodies[index - 1].name
/// after it.
std::string body_name(const Scene& scene, int index);

/// The config at `path` as one YAML document, its `base:` chain merged under it as load_scene
/// merges it (before any --set), re-emitted by yaml-cpp: comments and layout gone, every value of
/// every file it builds on in. Throws rbaa::InputError as load_scene does for an unreadable file,
/// bad YAML or a bad base.
std::string merged_config_text(const std::string& path);

/// Parses a scene from YAML text; `source` names it in errors and `base_dir` resolves paths.
Scene parse_scene(const std::string& yaml_text, const std::string& source,
                  const std::string& base_dir, const std::vector<std::string>& overrides = {});

}  // namespace rbaa
