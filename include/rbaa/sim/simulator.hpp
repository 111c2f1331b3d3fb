#pragma once
// The forward simulator (SPEC section 2): the bodies of one stacked tet mesh (linear tets,
// per-element materials; some vertices may be driven by a prescribed motion) against analytic
// planes and static triangle meshes and each other, with IPC contact and lagged friction, BDF
// time stepping, one Newton minimisation per step.
//
//   Simulator sim(rest_mesh, materials, settings);
//   Trajectory t = sim.run(q0, v0);
//
// The forms, the integrator and the Newton solver stay reachable for the adjoint and the
// benchmarks.

#include <Eigen/Core>

#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "rbaa/material/material_field.hpp"
#include "rbaa/mesh/tet_mesh.hpp"
#include "rbaa/sim/bdf.hpp"
#include "rbaa/sim/body_contact_form.hpp"
#include "rbaa/sim/rigid_rotation_correction.hpp"
#include "rbaa/sim/contact_form.hpp"
#include "rbaa/sim/elastic_form.hpp"
#include "rbaa/sim/gravity_form.hpp"
#include "rbaa/sim/incremental_potential.hpp"
#include "rbaa/sim/inertia_form.hpp"
#include "rbaa/sim/mesh_obstacle_form.hpp"
#include "rbaa/sim/newton_solver.hpp"
#include "rbaa/sim/pair_friction_form.hpp"
#include "rbaa/sim/plane_friction_form.hpp"
#include "rbaa/sim/sparse_hessian.hpp"
#include "rbaa/sim/trajectory.hpp"
#include "rbaa/sim/world.hpp"

namespace rbaa {

struct SimulationSettings {
  double time_step = 0.01;  ///< h (s)
  int num_steps = 0;
  Integrator integrator = Integrator::kBdf2;
  MassModel mass = MassModel::kConsistent;
  Eigen::Vector3d gravity{0.0, 0.0, -9.8};  ///< m/s^2 (zero: off)
  std::vector<Plane> planes;
  /// Static triangle-mesh obstacles (placed); none: no mesh-obstacle form at all.
  std::vector<ObstacleMesh> obstacle_meshes;
  /// The bodies as vertex and element ranges of the mesh, in order and covering it; empty: the
  /// whole mesh is one body. With more than one, bodies touch through IPC contact, and the rigid
  /// predictor and sub-step move each body by its own rigid motion.
  std::vector<Body> bodies;
  double d_hat = 1e-3;  ///< m
  /// Friction's smoothing speed eps_v (m/s, plane_friction_form.hpp): Coulomb above it, a creep
  /// below. Used only when some plane, obstacle mesh or pair of bodies has a friction coefficient.
  double friction_eps_v = 1e-3;
  /// Coulomb coefficients between bodies: (i, j) for bodies[i] and bodies[j] (square over the
  /// bodies, symmetric; the diagonal is unused). Empty or all zero: frictionless between bodies.
  Eigen::MatrixXd body_friction;
  double kappa = 0;     ///< J per unit of b; must be > 0 when there are obstacles
  /// Newton tolerance on ||dq||_inf / h relative to the rest bounding-box diagonal per second.
  double newton_tolerance = 1e-8;
  int newton_max_iterations = 100;
  double exact_hessian_factor = std::numeric_limits<double>::infinity();  ///< see NewtonSettings
  /// Start each step from the previous shape moved rigidly onto the ballistic guess when that is
  /// lower in energy, and try a rigid-motion Newton sub-step before each factorisation
  /// (rigid_rotation_correction.hpp). Off: the ballistic guess and plain Newton (for comparison).
  bool rigid_predictor = true;
  /// Begin each step's Newton with a chord step on the previous step's factorisation, applied in
  /// each free body's rotated frame (NewtonSettings::chord_first_step): one factorisation per
  /// free-flight step of a stiff spinning body instead of two (configs/ball.yaml: 1.28 instead of
  /// 2.16 per step). Off: every Newton iteration factorises (for comparison).
  bool newton_chord_start = true;
  /// Contact-resolving steps: 0 keeps every step h. k >= 2 (a power of two) lets steps shrink
  /// to h/k around contact (variable-step BDF, bdf.hpp): a step that ends with a contact pair
  /// closer than d_hat (or whose ballistic guess comes that close: halved before Newton) is
  /// taken again at half its size, down to h/k; out of contact the size
  /// doubles back towards h (step ratios <= 2), each step starting at a multiple of its size so
  /// that the steps tile every step of h. The run records each step's size
  /// (Trajectory::step_sizes) and what the refinement cost (Trajectory::resolving). A body
  /// resting on something stays at h/k.
  int contact_substeps = 0;
  /// Friction lagged this many times per step (IPC's lagged iterations, PolyFEM's
  /// solver.contact.friction_iterations): 1 lags the pairs, normal forces and frames once, from
  /// q_n, so a pair that closes within a step has no friction in it and an impact's friction is
  /// bounded by the normal forces before it. k > 1 re-lags them from the step's solution and
  /// solves again, up to k - 1 times, stopping once a re-lagged solve needs no Newton step.
  /// Forward runs only: the adjoint and tangent passes differentiate the lag at q_n and refuse
  /// k > 1. 1 .. 100.
  int friction_iterations = 1;
};

class Simulator {
 public:
  using StepCallback = std::function<void(int step, const Eigen::VectorXd& q, const StepStats&)>;

  /// `rest`: the rest (stress-free) shape, usually the placed reference mesh. Throws
  /// rbaa::InputError on bad settings (non-finite or non-positive h, d_hat, tolerance; no kappa
  /// with planes; non-unit plane normals) or materials that do not fit the mesh (naming
  /// `materials_source`).
  Simulator(const TetMesh& rest, const MaterialField& materials, const SimulationSettings& settings,
            const std::string& materials_source = "materials");

  /// Starts from positions q0 and per-dof velocities v0 (3 #V), with the ballistic past. A driven
  /// body starts carried by its drive instead: all its vertices take the drive's velocity and
  /// (rigid) past, and its driven vertices then follow the drive from their positions in q0.
  /// Throws rbaa::InputError if a surface vertex starts on or beyond a plane.
  void reset(const Eigen::VectorXd& q0, const Eigen::VectorXd& v0);
  /// One time step of the integrator's next size (the scene's h unless set_next_step, which holds
  /// until set again; the forms take the step's own rule and weight each time); throws
  /// rbaa::SolverError naming the step when Newton fails. With driven vertices the step first moves
  /// them alone from q_n to their prescribed positions at t_{n+1} (rbaa::InputError naming the step
  /// and the body if that move is not admissible: it crosses, touches or closes to within 1e-3 of a
  /// gap to an obstacle or another body; a move whose CCD its iteration cap stopped is checked
  /// again in up to 256 pieces, each keeping 1e-3 of its own start gap, and is another InputError
  /// if still capped), then minimises over the other dofs with them fixed.
  StepStats advance();
  /// The size of the next step(s), in units of h / max(1, contact_substeps): 1 ..
  /// max(1, contact_substeps) of them (the weights, friction's rule and Newton's tolerance follow).
  void set_next_step(int units);
  /// Sets the potentials' weight, friction's rule and Newton's step to those of a step of size h
  /// with `rule` (the adjoint and the tangent replay recorded steps with it).
  void use_step(const BdfStepRule& rule, double weight, double h);
  /// Units of the scene's h (max(1, contact_substeps)).
  int units_per_step() const { return units_per_step_; }
  /// The simulated time of q_n.
  double time() const { return time_at(units_); }
  /// reset + settings.num_steps steps of h (with contact_substeps, each may be sub-stepped),
  /// recording everything.
  Trajectory run(const Eigen::VectorXd& q0, const Eigen::VectorXd& v0,
                 const StepCallback& callback = {});

  /// Replaces the materials (same mesh) and rebuilds the mass-dependent forms.
  void set_materials(const MaterialField& materials, const std::string& source = "materials");

  const SimulationSettings& settings() const { return settings_; }
  const TetMesh& rest_mesh() const { return rest_; }
  Eigen::VectorXd rest_positions() const;
  int num_dofs() const { return 3 * rest_.num_vertices(); }
  int step_index() const { return step_; }
  double velocity_tolerance() const { return newton_.settings().velocity_tolerance; }
  const Eigen::VectorXd& vertex_masses() const { return vertex_masses_; }
  const std::vector<int>& surface_vertices() const { return surface_vertices_; }
  /// The driven vertices' dofs (ascending): fixed in every step's minimisation, and known
  /// functions of time to the adjoint and the tangent.
  const std::vector<int>& driven_dofs() const { return driven_dofs_; }

  BdfIntegrator& integrator() { return integrator_; }
  IncrementalPotential& potential() { return *potential_; }
  NewtonSolver& newton() { return newton_; }
  SparseHessian& hessian_pattern() { return *hessian_; }
  InertiaForm& inertia_form() { return *inertia_; }
  ElasticForm& elastic_form() { return *elastic_; }
  GravityForm& gravity_form() { return *gravity_; }
  ContactForm& contact_form() { return *contact_; }
  /// The mesh-obstacle contact form, or null when the settings have no obstacle meshes.
  MeshObstacleForm* mesh_obstacle_form() { return mesh_contact_.get(); }
  /// Contact between the bodies, or null with fewer than two.
  BodyContactForm* body_contact_form() { return body_contact_.get(); }
  /// Friction against planes, or null when no plane has a friction coefficient.
  PlaneFrictionForm* plane_friction_form() { return plane_friction_.get(); }
  /// Friction on mesh-obstacle and body-body pairs, or null when no obstacle mesh and no pair of
  /// bodies has a friction coefficient.
  PairFrictionForm* pair_friction_form() { return pair_friction_.get(); }

 private:
  void build_mass_forms(const MaterialField& materials);
  // Newton's chord start (NewtonSettings::chord_first_step): the previous step's factor applied
  // in each free body's previous frame, R solve(R^T g), R its best-fit rotation since.
  Eigen::VectorXd rotated_chord_solve(const Eigen::VectorXd& x, const Eigen::VectorXd& g,
                                      const NewtonSolver::ChordSolve& solve) const;
  // Sets q's driven entries (every vertex of a driven body with `whole_bodies`) to where the drives
  // carry their initial positions by time t.
  void set_driven_positions(Eigen::VectorXd& q, double t, bool whole_bodies = false) const;
  // q_n with the driven vertices moved to time t, checked body by body (see advance()).
  Eigen::VectorXd driven_start(const Eigen::VectorXd& q_n, double t,
                               const std::string& context) const;
  // Moves each driven body of x to q_n's shape carried by its drive from t0 to t1.
  void apply_drive_step(const Eigen::VectorXd& q_n, double t0, double t1, Eigen::VectorXd& x) const;

  TetMesh rest_;
  SimulationSettings settings_;
  std::vector<int> surface_vertices_;
  Eigen::VectorXd vertex_masses_;
  RigidClusters rigid_clusters_;  // per stiff cluster finite rotations of Newton steps
  std::unique_ptr<SparseHessian> hessian_;
  std::unique_ptr<InertiaForm> inertia_;
  std::unique_ptr<ElasticForm> elastic_;
  std::unique_ptr<GravityForm> gravity_;
  std::unique_ptr<ContactForm> contact_;
  std::unique_ptr<MeshObstacleForm> mesh_contact_;
  std::unique_ptr<PlaneFrictionForm> plane_friction_;
  std::unique_ptr<PairFrictionForm> pair_friction_;
  std::unique_ptr<BodyContactForm> body_contact_;
  std::unique_ptr<IncrementalPotential> potential_;
  BdfIntegrator integrator_;
  NewtonSolver newton_;
  std::vector<int> driven_dofs_;
  std::vector<Body> free_bodies_;  // settings_.bodies without the driven ones
  Eigen::VectorXd driven_origin_;  // q0 of the last reset: where the drives start from
  double time_at(long units) const;
  // Contact pairs closer than d_hat at x (planes, obstacle meshes, other bodies).
  int active_pairs(const Eigen::VectorXd& x) const;
  // The next step's ballistic guess q_hat + w g (the exact step of a free, undeformed body), with
  // driven vertices where their drives put them at the step's end.
  Eigen::VectorXd ballistic_guess(const Eigen::VectorXd& q_hat) const;
  // Whether the next step's ballistic guess crosses into or ends within d_hat of contact.
  bool prediction_in_contact() const;
  // Runs settings_.num_steps steps of h with contact-resolving sub-steps, recording into t.
  void run_resolving(Trajectory& t, const StepCallback& callback);

  int step_ = 0;
  // Time in units of h / units_per_step_ (exact on the grid of h and of its sub-steps).
  long units_ = 0;
  int units_per_step_ = 1;
  int next_units_ = 1;
  std::vector<Form*> weighted_forms_;  // the forms weighted by the step's w
};

}  // namespace rbaa
