#pragma once
// `rbaa evaluate`: the paper's demonstration. Four runs of one scene: the reference and the
// adversarial object, each as a rigid body (Bullet) and as a deformable body (FEM). As rigid
// bodies the two must move identically; as deformable bodies they should not.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <functional>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

#include "rbaa/eval/contact_episodes.hpp"
#include "rbaa/eval/demonstration.hpp"
#include "rbaa/eval/rigid_twin.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/material/material_field.hpp"
#include "rbaa/mesh/tet_mesh.hpp"
#include "rbaa/rigid/rigid_simulation.hpp"
#include "rbaa/scene/scene.hpp"

namespace rbaa {

/// One run as the comparisons see it: the compared body's path (demonstration.hpp) sampled at
/// the scene's time step (N + 1 samples, velocities included), named after the run ("rigid
/// reference", ...), with the run's wall time.
struct RunTrace : BodyPath {
  double seconds = 0;  ///< wall time
};

/// How two runs differ at the end time T.
struct RunComparison {
  std::string a, b;
  double position_gap = 0;    ///< |x_a(T) - x_b(T)| (m)
  double max_position_gap = 0;  ///< max over all samples (m)
  double velocity_angle_deg = 0;  ///< angle between v_a(T) and v_b(T)
  double orientation_gap_deg = 0; ///< angle of R_a(T) R_b(T)^T
};

/// What a fitted restitution (or a twin's friction) belongs to: a plane, an obstacle mesh or a
/// pair of bodies.
enum class RestitutionContact { kPlane, kMesh, kBodies };

/// "plane", "mesh", "bodies" (report.json's names).
const char* restitution_contact_name(RestitutionContact contact);

/// The rigid restitution of one plane, obstacle mesh or pair of bodies, fitted to the deformable
/// run's first contact episode with it (a plane's: its first bounce).
struct RestitutionCalibration {
  /// false when there is no clean episode (the normal velocity did not reverse, the episode did
  /// not end) or the rigid twin never meets that contact: the restitution then stays 1, but for
  /// a further body's plane, which keeps the plane's own (the object's fit against it, or 1) and
  /// reports that value.
  bool calibrated = false;
  RestitutionContact contact = RestitutionContact::kPlane;
  /// The report's: "plane 0" (the object's), "plane 0 (ball)", "mesh backboard", "bodies
  /// object-ball".
  std::string name;
  int plane = -1;    ///< kPlane: RigidWorld::planes index
  int mesh = -1;     ///< kMesh: RigidWorld::obstacle_meshes index
  /// kBodies: the pair (RigidWorld::bodies indices, 0 the object, a < b); kMesh: body_a is the
  /// body whose episode was fitted (the mesh's first); kPlane: body_a is the body (0 the object,
  /// whose value is the plane's own; a further body's is its own against the plane).
  int body_a = -1, body_b = -1;
  double time = 0;                ///< of the run's first contact (s)
  /// -v_n,out / v_n,in of the baseline's first contact with the plane, gravity taken off over the
  /// whole episode (so not the `restitution` rbaa simulate reports for a bounce, whose
  /// find_bounces takes it off over the settle steps only), or, for a corner episode, the ratio
  /// along this plane's normal across the episode (a fit target for the twin, which meets the
  /// same corner; no restitution of the plane alone).
  /// For a mesh or a pair: the same ratio of the relative velocity along the episode's contact
  /// normal (calibrate_contact_restitution).
  double deformable_rebound = 0;
  /// The same ratio for the rigid reference, fitted; NaN if its twin was not run to one (the twin
  /// never met that contact, or the run's episode gave nothing to fit).
  double rigid_rebound = std::numeric_limits<double>::quiet_NaN();
  double restitution = 1.0;       ///< the Bullet restitution that achieves it
  int iterations = 0;             ///< rigid runs the fit took
  /// Every restitution that gives the rebound (to the tolerance), ascending; `restitution` is one
  /// of them when calibrated.
  std::vector<double> roots;
  std::vector<double> later_deformable_rebounds;  ///< restitutions of later one-plane bounces
};

/// The Coulomb coefficient the rigid twins give one plane, obstacle mesh or pair of bodies: every
/// contact point between them gets exactly this (RigidWorld).
struct TwinFriction {
  RestitutionContact contact = RestitutionContact::kPlane;  ///< which kind of contact
  std::string name;  ///< as a calibration's: "plane 0", "mesh backboard", "bodies object-ball"
  int plane = -1;    ///< kPlane: RigidWorld::planes index
  int mesh = -1;     ///< kMesh: RigidWorld::obstacle_meshes index
  int body_a = -1, body_b = -1;  ///< kBodies: RigidWorld::bodies indices, a < b
  double friction = 0;
};

/// A deformable run against a rigid twin calibrated to that run itself: the same object's rigid
/// body (its own moments), each plane's restitution fitted to the run's own first rebound off it.
/// What remains between the two is what no rigid simulator with a tuned restitution explains.
struct OwnTwin {
  std::vector<RestitutionCalibration> calibrations;
  RunTrace rigid;
  RunComparison gap;          ///< deformable run vs its own twin
  double path_length = 0;     ///< of the deformable run's centre of mass (m)
  double unexplained = 0;     ///< gap.max_position_gap / max(path_length, bounding radius)
};

/// One step tried for the stiff baseline: how far it strays from its calibrated rigid twin.
struct BaselineTrial {
  double time_step = 0;      ///< s
  double path_length = 0;    ///< of the baseline's centre of mass (m)
  /// largest baseline-vs-rigid gap / path_length (the path counted at least as long as the
  /// body's bounding radius: a body that hardly moves is not divided by round-off)
  double disagreement = 0;
  double seconds = 0;        ///< wall time of the baseline, calibration and rigid runs
};

struct EvaluationOptions {
  double duration = 0;   ///< s; <= 0: the scene's evaluation.duration, else 4 x the attack's
  /// s; > 0 fixes the step. Otherwise the scene's evaluation settings decide: a fixed
  /// evaluation.time_step, the attack's step, or (search_time_step or evaluation.time_step: auto)
  /// the attack's step refined by 4 until the baseline agrees with the rigid reference.
  double time_step = 0;
  bool search_time_step = false;
  /// Also simulate the reference shape in uniform material at the scene's softest allowed Young's
  /// modulus (same moments): the share of a gap that softness alone explains.
  bool soft_control = true;
  std::ostream* progress = nullptr;  ///< one line per step tried by the search
  /// Plane, mesh and body-pair restitutions are overwritten by the calibration; friction is the
  /// scene's, per plane, mesh and pair of bodies (rigid_world, Evaluation::rigid_friction).
  RigidSettings rigid;
  double calibration_tolerance = 1e-3;  ///< relative rebound mismatch accepted
};

struct Evaluation {
  double duration = 0;
  double time_step = 0;         ///< of the deformable runs and of the traces' samples (s)
  std::vector<BaselineTrial> step_search;  ///< every step tried, coarsest first; the last is used
  double baseline_tolerance = 0;           ///< the search's bar on BaselineTrial::disagreement
  double attack_time_step = 0;  ///< the scene's own step, at which attacks are built (s)
  double kappa = 0;
  Moments reference_moments, adversarial_moments;
  std::string rigid_shape;        ///< which Bullet collision shape, and why
  double rigid_internal_step = 0;
  /// The twins' Coulomb coefficient of every plane, obstacle mesh and pair of bodies (the
  /// scene's: rigid_world), in that order, as the twins' Bullet world gives it.
  std::vector<TwinFriction> rigid_friction;
  /// One per plane the baseline bounces off, obstacle mesh it meets and pair of bodies that
  /// touch, in the order of their first contacts (each fitted with the earlier values in place). A single restitution cannot reproduce BDF-2's
  /// rebounds, which depend on where in a step the impact falls (SPEC section 2).
  std::vector<RestitutionCalibration> calibrations;
  RunTrace rigid_reference, rigid_adversarial, deformable_reference, deformable_adversarial;
  RunComparison rigid_vs_rigid, deformable_vs_deformable, deformable_vs_rigid;
  /// The rigid simulator's own sensitivity: the rigid reference run again with its mass and
  /// principal moments scaled by 1 + rigid_perturbation and its centre of mass moved along x by
  /// as much as the adversarial's lies from the reference's and its principal axes turned by
  /// rigid_axes_turn; rigid_perturbation is the largest relative difference between
  /// the adversarial's and the reference's rigid inputs (mass, centre over the radius of
  /// gyration, principal moments; at least 1e-15; the values before the twins' rounding to a
  /// grid, rigid_mass_properties), against the rigid reference; copies of the object
  /// (demonstration.object_copies) are perturbed alike. The twins themselves get bit-identical
  /// inputs when the objects agree to well within that grid, so this is the gap the rounding
  /// spares them: how far Bullet amplifies differences of the adversarial's size (a resting stack
  /// of cubes far, a ball in flight hardly).
  double rigid_perturbation = 0;
  /// The angle between the two objects' principal axes (rad), by which the sensitivity run also
  /// turns the reference twin's axes.
  double rigid_axes_turn = 0;
  RunComparison rigid_sensitivity;
  /// The deformable adversarial object against the rigid reference: what a rigid-body simulator
  /// predicts for the object against what happens to it.
  RunComparison adversarial_vs_rigid;
  /// The control (EvaluationOptions::soft_control): uniform, Y = the scene's lowest, reference nu
  /// and rho, against the baseline. Empty trace when not run.
  RunTrace deformable_soft;
  RunComparison soft_vs_deformable;
  double soft_Y = 0;
  /// Each deformable run against a rigid twin calibrated to its own rebounds (issue 20): the
  /// baseline's is rigid_reference; the adversarial object's and the soft control's (empty
  /// when not run) are fitted here. A uniform object should be explained well; an adversarial
  /// one, if its effect is more than a changed restitution, should not.
  OwnTwin reference_own_twin, adversarial_own_twin, soft_own_twin;
  double attack_advantage = 0;  ///< deformable_vs_deformable gap / deformable_vs_rigid gap
  /// How well the stiff baseline agrees with the rigid reference: deformable_vs_rigid's largest
  /// gap over the baseline's path length. Above ~1 % the comparison measures the time
  /// discretisation more than the object; a smaller evaluation step helps (README).
  double baseline_path_length = 0;  ///< m
  double baseline_disagreement = 0;
  /// The demonstration (scene.demonstration), one row per run: rigid and deformable, reference,
  /// adversarial and soft control (the control's rigid body is the reference's: same surface,
  /// same moments, same calibration). Empty when the scene has no demonstration.
  std::vector<DemonstrationOutcome> outcomes;
  /// The runs the outcomes were judged on (every body's path; a run not made has none) and every
  /// body's rest shape, for the final-poses picture of a demonstration whose predicate is
  /// `stands`. Empty otherwise.
  std::vector<DemonstrationRun> demonstration_runs;
  std::vector<BodyShape> body_shapes;
  /// Every body's moments (the object, then scene.bodies) in the deformable reference and
  /// adversarial runs, from each run's own stacked mesh and materials: a body of
  /// demonstration.object_copies has that run's object's mass (and its inertia, turned to the
  /// body's pose); the others keep theirs.
  std::vector<Moments> reference_body_moments, adversarial_body_moments;
  /// The adversarial object as evaluated (placed at the scene's pose), for its pictures.
  TetMesh adversarial_mesh;
  MaterialField adversarial_materials;
};

/// Runs the four simulations (five with the soft control). `reference_mesh`/`adversarial_mesh` are
/// placed at the scene's initial pose; the reference uses the scene's uniform reference material.
/// The adversarial object is then translated so that its own centre of mass is at scene.position
/// (place_centre_of_mass; round-off for an attack's moment-matched object). Throws
/// rbaa::InputError if the adversarial object's outer surface is not the reference's or its
/// materials do not fit its mesh. In a scene with a demonstration block the adversarial object
/// may come placed at its attack config's pose (the same shape, translated): it is first moved
/// by the difference of the two bounding boxes' centres. The bodies of
/// demonstration.object_copies are copies of each run's object (with_object_copies): the
/// reference's, the adversarial's and the soft control's, as deformable bodies and as twins.
Evaluation evaluate(const Scene& scene, const TetMesh& reference_mesh,
                    const TetMesh& adversarial_mesh, const MaterialField& adversarial_materials,
                    const EvaluationOptions& options = {});

/// Compares two traces sampled at the same times.
RunComparison compare_runs(const RunTrace& a, const RunTrace& b);

/// How far a rigid twin's run (every body's states, simulate_rigid_bodies) strays from the run it
/// is fitted to; smaller is closer. Picks among restitutions that all give the fitted rebound.
using TwinCloseness = std::function<double(const std::vector<std::vector<RigidState>>&)>;

/// The closeness of a twin's run (states[b][k]: body b at grid position k, the object first) to
/// `run` over grid positions first .. last: the largest distance of any body's centre of mass from
/// the run's at the same position (run.observables: the object's centre and the further bodies'),
/// over the positions and bodies both hold. Reads `run` when called: it must outlive the result.
TwinCloseness twin_closeness(const SimulationRun& run, int first, int last);

/// Fits the restitution of plane `plane` (settings.plane_restitution) so that the rigid
/// reference's first rebound off it (the ratio of the centre of mass's normal velocities after and
/// before) equals `target`. `further`: the scene's other bodies' twins (simulate_rigid).
/// The twin's rebound is not monotonic in the restitution (a non-round body that leaves its
/// first corner meets no second one), so every restitution in [0, 1] that gives `target` is
/// found; `closeness` picks among them (the closest run), else the one nearest `target`. Above 1
/// a restitution adds energy at every later contact too, so it is tried (up to 3) only for a
/// `target` above 1 (the run gained energy: a driven body's face springing back); otherwise a
/// rebound no restitution up to 1 gives is not fitted (calibrated false; the restitution the
/// nearest rebound's). `target_start`: the sample the target's incoming velocity was read at
/// (rigid_first_rebound's `start`), if known.
RestitutionCalibration calibrate_restitution(const RigidMassProperties& mass,
                                             const RigidShape& shape, const Scene& scene,
                                             RigidSettings settings, double duration, int plane,
                                             double target, double tolerance,
                                             const std::vector<RigidBody>& further = {},
                                             const TwinCloseness& closeness = nullptr,
                                             int target_start = -1);

/// The first rebound ratio of a rigid trace off plane `plane` (NaN if none, or if the trace ends
/// within the episode): -(v_out . n) / (v_in . n), v_in the velocity before the episode's first
/// impact, v_out after its last with the gravity gained in between taken off (v_out - g (t_out -
/// t_in)), as the deformable targets are. An episode runs from the first step whose change of
/// normal velocity is an impact through the next impacts while the body still approaches the
/// plane, as the deformable run's does (impact_end), or while the next impact is at most three
/// steps away. Without `touches_plane` an impact changes the normal velocity by more than
/// 10 |g| h (h the states' spacing); with it, an impact is a step k (states k to k + 1) for which
/// it is true and whose normal velocity changed by more than 0.01 |g| h, both in all and beyond
/// gravity's own change: in a scene with other bodies or obstacles a blow from them changes the
/// normal velocity too, and a slow impact changes it by less than 10 |g| h. After the bridge of
/// three steps, a body that turned away and falls back begins another bounce. `start`: the
/// sample the deformable run's incoming velocity was read at; v_in is read there instead when the
/// first impact comes at most three samples after it (the same free fall, gravity off over the
/// same interval: a ratio matched from samples a step apart leaves the twin about g h off).
double rigid_first_rebound(const std::vector<RigidState>& states, const Plane& plane,
                           const Eigen::Vector3d& gravity,
                           const std::function<bool(int)>& touches_plane = nullptr, int start = -1);

/// Fits the restitution of an obstacle mesh (settings.mesh_restitution[episode.other]), of a body
/// against a plane (an entry of settings.body_plane_restitution) or of a pair of bodies (an entry
/// of settings.pair_restitution) to `episode` of the deformable `run` (contact_episodes.hpp), so
/// that the rigid twin's first episode of the same pair (Bullet's own contacts, RigidTouch) has
/// the same rebound ratio
///
///   -(w_out . n) / (w_in . n),  w = u_body - u_other,  n = (w_out - w_in) / |w_out - w_in|,
///
/// u a free body's centre-of-mass velocity, a driven body's velocity at the material point of the
/// episode's contact point, 0 for a mesh; w_out without the gravity the free sides gained over the
/// episode (not the contact's doing; both runs from the run's sample before the episode when the
/// twin's contact comes at most three samples after it); n the direction of the episode's
/// impulse, each run's own (frictionless: the contact normal; for two spheres the ratio is then
/// Bullet's restitution). A plane's n is its normal, and the twin's episode rigid_first_rebound's
/// on that body's states. Every restitution in [0, 1] (up to 3 for a rebound above 1) that gives it
/// is found, and one picked, as for planes. Not fitted (restitution 1) when the run's episode is
/// not clean (unfinished, w_in . n >= 0, or w_out . n <= 0) or the twin never meets that pair.
/// `further` and the body indices as simulate_rigid_bodies'.
RestitutionCalibration calibrate_contact_restitution(
    const SimulationRun& run, const ContactEpisode& episode, const RigidMassProperties& mass,
    const RigidShape& shape, const Scene& scene, RigidSettings settings, double duration,
    double tolerance, const std::vector<RigidBody>& further = {},
    const TwinCloseness& closeness = nullptr);

/// DIR/report.json, DIR/summary.md, DIR/<run>.csv and DIR/paths.{gp,png}.
void write_evaluation(const Evaluation& evaluation, const Scene& scene, const std::string& dir);

}  // namespace rbaa
