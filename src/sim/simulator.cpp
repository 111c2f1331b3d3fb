#include "rbaa/sim/simulator.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "rbaa/error.hpp"
#include "rbaa/mesh/topology.hpp"
#include "rbaa/sim/mass_matrix.hpp"
#include "rbaa/sim/observables.hpp"
#include "rbaa/sim/rigid_rotation_correction.hpp"

namespace rbaa {

namespace {

void check_positive(double value, const char* what) {
  if (!(std::isfinite(value) && value > 0)) {
    std::ostringstream msg;
    msg << "simulation: " << what << " is " << value << "; it must be a positive finite number";
    throw InputError(msg.str());
  }
}

const SimulationSettings& validated(const SimulationSettings& s) {
  check_positive(s.time_step, "the time step h");
  check_positive(s.d_hat, "the barrier activation distance d_hat");
  check_positive(s.friction_eps_v, "friction's smoothing speed eps_v");
  check_positive(s.newton_tolerance, "the Newton tolerance");
  if (!(s.exact_hessian_factor > 0)) throw InputError("simulation: the exact-Hessian switch factor must be > 0");
  if (s.num_steps < 0) throw InputError("simulation: negative number of steps");
  if (s.newton_max_iterations < 1) throw InputError("simulation: Newton needs at least 1 iteration");
  if (s.friction_iterations < 1 || s.friction_iterations > 100) {
    throw InputError("simulation: friction iterations " + std::to_string(s.friction_iterations) +
                     " is not from 1 to 100");
  }
  if (s.contact_substeps != 0 &&
      (s.contact_substeps < 2 || s.contact_substeps > 1024 ||
       (s.contact_substeps & (s.contact_substeps - 1)) != 0)) {
    throw InputError("simulation: contact sub-steps " + std::to_string(s.contact_substeps) +
                     " is not 0 (off) or a power of two from 2 to 1024");
  }
  if (!s.gravity.allFinite()) throw InputError("simulation: gravity is not finite");
  if (!std::isfinite(s.kappa) || s.kappa < 0) {
    throw InputError("simulation: the barrier stiffness kappa must be finite and >= 0");
  }
  if (!s.planes.empty() && !(s.kappa > 0)) {
    throw InputError("simulation: the barrier stiffness kappa must be positive when there are planes");
  }
  if (!s.obstacle_meshes.empty() && !(s.kappa > 0)) {
    throw InputError("simulation: the barrier stiffness kappa must be positive when there are obstacle meshes");
  }
  for (std::size_t m = 0; m < s.obstacle_meshes.size(); ++m) {
    const ObstacleMesh& o = s.obstacle_meshes[m];
    if (o.F.rows() == 0 || !o.V.allFinite() || o.F.minCoeff() < 0 || o.F.maxCoeff() >= o.V.rows()) {
      throw InputError("simulation: obstacle mesh " + std::to_string(m) +
                       " needs finite vertices and triangles indexing them");
    }
  }
  for (std::size_t p = 0; p < s.planes.size(); ++p) {
    const Plane& plane = s.planes[p];
    if (!plane.normal.allFinite() || !std::isfinite(plane.offset) ||
        std::abs(plane.normal.norm() - 1.0) > 1e-9) {
      throw InputError("simulation: plane " + std::to_string(p) +
                       " needs a finite unit normal and a finite offset");
    }
  }
  return s;
}

void check_bodies(const std::vector<Body>& bodies, const TetMesh& rest) {
  int vertex = 0, element = 0;
  for (const Body& b : bodies) {
    if (b.vertex_begin != vertex || b.element_begin != element || b.num_vertices() < 4 ||
        b.num_elements() < 1) {
      throw InputError("simulation: body " + b.name +
                       " is not the next non-empty vertex and element range of the mesh");
    }
    for (int e = b.element_begin; e < b.element_end; ++e) {
      if (rest.T.row(e).minCoeff() < b.vertex_begin || rest.T.row(e).maxCoeff() >= b.vertex_end) {
        throw InputError("simulation: element " + std::to_string(e) + " of body " + b.name +
                         " uses a vertex of another body");
      }
    }
    for (std::size_t i = 0; i < b.driven_vertices.size(); ++i) {
      const int v = b.driven_vertices[i];
      if (v < b.vertex_begin || v >= b.vertex_end || (i > 0 && v <= b.driven_vertices[i - 1])) {
        throw InputError("simulation: body " + b.name + "'s driven vertex " + std::to_string(v) +
                         " is not in its vertex range or not in ascending order");
      }
    }
    if (b.is_driven()) validate_prescribed_motion(b.drive, "simulation: body " + b.name);
    vertex = b.vertex_end;
    element = b.element_end;
  }
  if (!bodies.empty() && (vertex != rest.num_vertices() || element != rest.num_tets())) {
    throw InputError("simulation: the bodies do not cover the mesh");
  }
}

// The tolerance's length: the rest bounding-box diagonal of the smallest body (of the mesh when
// it is one body), so that a small body far from a large one is solved as tightly as alone.
double tolerance_length(const SimulationSettings& s, const TetMesh& rest) {
  if (s.bodies.size() < 2) return bounding_box_diagonal(rest);
  double length = std::numeric_limits<double>::infinity();
  for (const Body& b : s.bodies) {
    const auto V = rest.V.middleRows(b.vertex_begin, b.num_vertices());
    length = std::min(length, (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm());
  }
  return length;
}

NewtonSettings newton_settings(const SimulationSettings& s, const TetMesh& rest) {
  check_bodies(s.bodies, rest);
  NewtonSettings n;
  n.time_step = s.time_step;
  n.velocity_tolerance = s.newton_tolerance * tolerance_length(s, rest);
  n.max_iterations = s.newton_max_iterations;
  n.exact_hessian_factor = s.exact_hessian_factor;
  n.chord_first_step = s.newton_chord_start;
  return n;
}

// The bodies without driven vertices: the rigid predictor and the rigid sub-step move these only.
std::vector<Body> free_bodies(const std::vector<Body>& bodies) {
  std::vector<Body> free;
  for (const Body& b : bodies) {
    if (!b.is_driven()) free.push_back(b);
  }
  return free;
}

// How a driven body's straight move a -> z checks out (Simulator::driven_start).
enum class DrivenMove { kClear, kIntersects, kUncertified };

// The halvings a capped check of a driven move may take: 2^8 = 256 pieces at most.
constexpr int kDrivenMoveHalvings = 8;

// is_step_valid on the straight move a -> z. A CCD search that its iteration cap stopped (a pair
// sliding past at a distance far below its motion, ~motion / distance iterations: 1e6 for
// parallel edges 1e-8 m apart sliding 1 cm) refuses a move it could not certify, not one that
// intersects; such a move is checked again in halves along the same path (each half needs half
// the iterations), up to `halvings` deep. Each piece keeps 1e-3 of its own start gap, so the
// pieces together still certify the path free of intersection. A check that fails with no search
// capped intersects; one still capped at the deepest level is uncertified. Both halves are
// checked unless the first intersects, so a move is uncertified only where no piece intersects.
DrivenMove check_driven_move(const IncrementalPotential& E, const Eigen::VectorXd& a,
                             const Eigen::VectorXd& z, int halvings) {
  const long caps = E.ccd_caps();
  if (E.is_step_valid(a, z)) return DrivenMove::kClear;
  if (E.ccd_caps() == caps) return DrivenMove::kIntersects;
  if (halvings == 0) return DrivenMove::kUncertified;
  const Eigen::VectorXd mid = 0.5 * (a + z);
  const DrivenMove first = check_driven_move(E, a, mid, halvings - 1);
  if (first == DrivenMove::kIntersects) return first;
  // An uncertified first half still has its second checked: a crossing there is the answer.
  const DrivenMove second = check_driven_move(E, mid, z, halvings - 1);
  return second != DrivenMove::kClear ? second : first;
}

}  // namespace

Simulator::Simulator(const TetMesh& rest, const MaterialField& materials,
                     const SimulationSettings& settings, const std::string& materials_source)
    : rest_(rest),
      settings_(validated(settings)),
      integrator_(settings.integrator, settings.time_step),
      newton_(newton_settings(settings, rest)),
      driven_dofs_(rbaa::driven_dofs(settings.bodies)),
      free_bodies_(free_bodies(settings.bodies)),
      units_per_step_(std::max(1, settings.contact_substeps)),
      next_units_(units_per_step_) {
  validate_material_field(materials, rest.num_tets(), materials_source);
  surface_vertices_ = boundary_vertices(rest_);
  hessian_ = std::make_unique<SparseHessian>(rest_.T, rest_.num_vertices());
  elastic_ = std::make_unique<ElasticForm>(rest_, materials);
  contact_ = std::make_unique<ContactForm>(
      ContactSet(surface_vertices_, settings_.planes, settings_.d_hat), settings_.kappa);
  if (!settings_.obstacle_meshes.empty()) {
    mesh_contact_ = std::make_unique<MeshObstacleForm>(rest_, settings_.obstacle_meshes,
                                                       settings_.d_hat, settings_.kappa);
  }
  if (settings_.bodies.size() > 1) {
    if (!(settings_.kappa > 0)) {
      throw InputError("simulation: the barrier stiffness kappa must be positive when there are several bodies");
    }
    body_contact_ = std::make_unique<BodyContactForm>(
        rest_, vertex_body_ids(settings_.bodies, rest_.num_vertices()), settings_.d_hat,
        settings_.kappa);
  }
  std::vector<double> mu;
  for (const Plane& plane : settings_.planes) mu.push_back(plane.friction);
  if (std::any_of(mu.begin(), mu.end(), [](double m) { return m != 0; })) {
    plane_friction_ = std::make_unique<PlaneFrictionForm>(
        surface_vertices_, settings_.planes, mu, settings_.d_hat, settings_.kappa,
        settings_.friction_eps_v, settings_.integrator, settings_.time_step);
  }
  std::vector<double> mesh_mu;
  for (const ObstacleMesh& m : settings_.obstacle_meshes) mesh_mu.push_back(m.friction);
  const Eigen::MatrixXd body_mu = body_contact_ ? settings_.body_friction : Eigen::MatrixXd();
  const auto num_bodies = static_cast<Eigen::Index>(settings_.bodies.size());
  if (body_contact_ && body_mu.size() > 0 &&
      (body_mu.rows() != num_bodies || body_mu.cols() != num_bodies)) {
    throw InputError("simulation: the body friction coefficients are not square over the bodies");
  }
  if (any_pair_friction(mesh_mu, body_mu)) {
    pair_friction_ = std::make_unique<PairFrictionForm>(
        mesh_contact_.get(), mesh_mu, body_contact_.get(), body_mu, settings_.friction_eps_v,
        settings_.integrator, settings_.time_step);
  }
  build_mass_forms(materials);
  newton_.set_step_transform([this](const Eigen::VectorXd& x, const Eigen::VectorXd& dq) {
    return rigid_rotation_correction(x, dq, vertex_masses_, rigid_clusters_);
  });
  // Driven bodies keep out of the rigid sub-step: their rigid motion is prescribed.
  const bool all_driven = !settings_.bodies.empty() && free_bodies_.empty();
  if (settings_.rigid_predictor && !all_driven)
    newton_.set_subspace_step([this](const Eigen::VectorXd& x, const Eigen::VectorXd& g,
                                     const Eigen::SparseMatrix<double>& H) {
      return rigid_newton_step(x, g, H, vertex_masses_, free_bodies_);
    });
  newton_.set_chord_frame([this](const Eigen::VectorXd& x, const Eigen::VectorXd& g,
                                 const NewtonSolver::ChordSolve& solve) {
    return rotated_chord_solve(x, g, solve);
  });
}

Eigen::VectorXd Simulator::rotated_chord_solve(const Eigen::VectorXd& x, const Eigen::VectorXd& g,
                                               const NewtonSolver::ChordSolve& solve) const {
  // The previous factor is of the Hessian at the last converged positions; each free body has
  // turned by its best-fit rotation R since, and its Hessian with it: H_x^-1 g ~ R H^-1 R^T g.
  const Eigen::VectorXd& from = integrator_.current();
  // Contact steps stay exact Newton from the first iteration (their factor changes with the
  // barrier's pairs, which no rotation accounts for).
  if (active_pairs(from) > 0 || active_pairs(x) > 0) return Eigen::VectorXd();
  std::vector<Body> bodies = free_bodies_;
  if (settings_.bodies.empty()) {
    Body whole;
    whole.vertex_end = rest_.num_vertices();
    bodies.push_back(whole);
  }
  std::vector<Eigen::Matrix3d> R;
  Eigen::VectorXd b = g;
  for (const Body& body : bodies) {
    const int v0 = body.vertex_begin, n = body.num_vertices();
    R.push_back(best_fit_rotation(from.segment(3 * v0, 3 * n), x.segment(3 * v0, 3 * n),
                                  vertex_masses_.segment(v0, n))
                    .toRotationMatrix());
    for (int v = v0; v < v0 + n; ++v) b.segment<3>(3 * v) = R.back().transpose() * g.segment<3>(3 * v);
  }
  Eigen::VectorXd y = solve(b);
  if (y.size() != g.size()) return y;
  for (std::size_t k = 0; k < bodies.size(); ++k) {
    for (int v = bodies[k].vertex_begin; v < bodies[k].vertex_end; ++v) {
      y.segment<3>(3 * v) = R[k] * Eigen::Vector3d(y.segment<3>(3 * v));
    }
  }
  return y;
}

void Simulator::build_mass_forms(const MaterialField& materials) {
  const Eigen::VectorXd density = materials.effective_density();
  vertex_masses_ = rbaa::vertex_masses(rest_, density);
  rigid_clusters_ = stiff_clusters(rest_, materials);
  const UnitElementMass unit(rest_, settings_.mass);
  inertia_ = std::make_unique<InertiaForm>(mass_matrix(rest_, density, settings_.mass, *hessian_), unit);
  gravity_ = std::make_unique<GravityForm>(vertex_masses_, settings_.gravity, unit);
  const double w = integrator_.potential_weight();
  potential_ = std::make_unique<IncrementalPotential>(*hessian_);
  potential_->set_fixed_dofs(driven_dofs_);
  potential_->add(*inertia_, 1.0);
  weighted_forms_ = {elastic_.get()};
  if (settings_.gravity.squaredNorm() > 0) weighted_forms_.push_back(gravity_.get());
  if (!settings_.planes.empty()) weighted_forms_.push_back(contact_.get());
  if (mesh_contact_) weighted_forms_.push_back(mesh_contact_.get());
  if (plane_friction_) weighted_forms_.push_back(plane_friction_.get());
  if (pair_friction_) weighted_forms_.push_back(pair_friction_.get());
  if (body_contact_) weighted_forms_.push_back(body_contact_.get());
  for (Form* f : weighted_forms_) potential_->add(*f, w);
}

void Simulator::use_step(const BdfStepRule& rule, double weight, double h) {
  for (Form* f : weighted_forms_) potential_->set_weight(*f, weight);
  if (plane_friction_) plane_friction_->set_step_rule(rule);
  if (pair_friction_) pair_friction_->set_step_rule(rule);
  newton_.set_time_step(h);
}

void Simulator::set_next_step(int units) {
  if (units < 1 || units > units_per_step_) {
    throw InputError("simulation: a step of " + std::to_string(units) + " units of h/" +
                     std::to_string(units_per_step_) + " is not between one unit and h");
  }
  next_units_ = units;
  const double h = units == units_per_step_ ? settings_.time_step
                                            : units * settings_.time_step / units_per_step_;
  integrator_.set_next_step(h);
  use_step(integrator_.next_rule(), integrator_.potential_weight(), h);
}

double Simulator::time_at(long units) const {
  // Constant steps keep n h exactly as before sub-steps existed.
  return units_per_step_ == 1 ? units * settings_.time_step
                              : units * settings_.time_step / units_per_step_;
}

void Simulator::set_materials(const MaterialField& materials, const std::string& source) {
  validate_material_field(materials, rest_.num_tets(), source);
  elastic_->set_materials(materials);
  Eigen::VectorXd q_hat = inertia_->predictor();
  build_mass_forms(materials);
  inertia_->set_predictor(q_hat);
}

Eigen::VectorXd Simulator::rest_positions() const {
  return Eigen::Map<const Eigen::VectorXd>(rest_.V.data(), num_dofs());
}

void Simulator::reset(const Eigen::VectorXd& q0, const Eigen::VectorXd& v0) {
  if (q0.size() != num_dofs() || v0.size() != num_dofs()) {
    throw InputError("simulation: initial state has the wrong size for the mesh");
  }
  if (!q0.allFinite() || !v0.allFinite()) {
    throw InputError("simulation: initial positions or velocities are not finite");
  }
  // A run's steps depend on its initial state alone, not on the run before it.
  newton_.forget_factor();
  for (int v : surface_vertices_) {
    for (std::size_t p = 0; p < settings_.planes.size(); ++p) {
      const Plane& plane = settings_.planes[p];
      const double d = plane.normal.dot(q0.segment<3>(3 * v)) - plane.offset;
      if (!(d > 0)) {
        std::ostringstream msg;
        msg << "simulation: the object starts intersecting or touching plane " << p
            << " (vertex " << v << " at distance " << d << " m)";
        throw InputError(msg.str());
      }
    }
  }
  if (mesh_contact_) {
    const ObstacleClearance c = mesh_contact_->clearance(q0, settings_.d_hat);
    if (c.intersecting || !(c.distance > 0)) {
      std::ostringstream msg;
      msg << "simulation: the object starts intersecting or touching " << mesh_contact_->mesh_name(c.mesh)
          << " (" << c.pair << (c.intersecting ? "" : " at distance " + std::to_string(c.distance) + " m") << ")";
      throw InputError(msg.str());
    }
  }
  if (body_contact_) body_contact_->check_separated(q0);
  // A driven body starts carried by its drive: every vertex of it has the drive's velocity and
  // the drive's (rigid) past instead of the ballistic one, so that BDF's first steps see the
  // prescribed motion exactly and the free vertices start in step with the driven ones.
  driven_origin_ = q0;
  Eigen::VectorXd v = v0;
  for (const Body& b : settings_.bodies) {
    if (!b.is_driven()) continue;
    for (int i = b.vertex_begin; i < b.vertex_end; ++i) {
      v.segment<3>(3 * i) = b.drive.point_velocity(q0.segment<3>(3 * i), 0.0);
    }
  }
  integrator_.initialize(q0, v, settings_.gravity);
  for (int k = 1; k < 4; ++k) {
    Eigen::VectorXd past = integrator_.past(k);
    set_driven_positions(past, -k * settings_.time_step, true);
    integrator_.set_past(k, past);
  }
  step_ = 0;
  units_ = 0;
  set_next_step(units_per_step_);
}

void Simulator::set_driven_positions(Eigen::VectorXd& q, double t, bool whole_bodies) const {
  for (const Body& b : settings_.bodies) {
    if (!b.is_driven()) continue;
    auto set = [&](int i) {
      q.segment<3>(3 * i) = b.drive.position(driven_origin_.segment<3>(3 * i), t);
    };
    if (whole_bodies) {
      for (int i = b.vertex_begin; i < b.vertex_end; ++i) set(i);
    } else {
      for (int i : b.driven_vertices) set(i);
    }
  }
}

Eigen::VectorXd Simulator::driven_start(const Eigen::VectorXd& q_n, double t,
                                        const std::string& context) const {
  // Each body's driven vertices in turn, so that the error names the body whose move fails.
  Eigen::VectorXd from = q_n;
  for (const Body& b : settings_.bodies) {
    if (!b.is_driven()) continue;
    Eigen::VectorXd to = from;
    for (int i : b.driven_vertices)
      to.segment<3>(3 * i) = b.drive.position(driven_origin_.segment<3>(3 * i), t);
    const DrivenMove move = check_driven_move(*potential_, from, to, kDrivenMoveHalvings);
    if (move == DrivenMove::kIntersects) {
      throw InputError(context + ": the prescribed motion of body " + b.name +
                       " would intersect: moving its driven vertices from the last step's "
                       "positions crosses or touches an obstacle or another body");
    }
    if (move == DrivenMove::kUncertified) {
      throw InputError(context + ": the prescribed motion of body " + b.name +
                       " could not be certified free of intersection: the CCD's iteration cap "
                       "stopped its check even on a 1/" +
                       std::to_string(1 << kDrivenMoveHalvings) +
                       " piece of the move (a pair sliding past at a distance far below its "
                       "motion in a step); a shorter time step helps");
    }
    from = std::move(to);
  }
  return from;
}

// A driven body moved rigidly by its drive's motion over the step, t0 -> t1: the drive maps a
// point x at t0 to c + t1 v + R(angle(t1) - angle(t0)) (x - c - t0 v).
void Simulator::apply_drive_step(const Eigen::VectorXd& q_n, double t0, double t1,
                                 Eigen::VectorXd& x) const {
  for (const Body& b : settings_.bodies) {
    if (!b.is_driven()) continue;
    const PrescribedMotion& m = b.drive;
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(m.angle(t1) - m.angle(t0), m.axis).toRotationMatrix();
    for (int i = b.vertex_begin; i < b.vertex_end; ++i) {
      x.segment<3>(3 * i) =
          m.centre + t1 * m.velocity + R * (q_n.segment<3>(3 * i) - m.centre - t0 * m.velocity);
    }
  }
  set_driven_positions(x, t1);
}

StepStats Simulator::advance() {
  const auto start = std::chrono::steady_clock::now();
  const long caps_before = potential_->ccd_caps();
  // The integrator re-derives the next step's rule and weight after every step (a step of h/4
  // after h has another weight than the h/4 after it): the forms take them from it each time.
  use_step(integrator_.next_rule(), integrator_.potential_weight(), integrator_.next_step());
  const Eigen::VectorXd& q_n = integrator_.current();
  const Eigen::VectorXd q_hat = integrator_.predictor();
  inertia_->set_predictor(q_hat);
  potential_->lag(q_n, integrator_.past(1));
  const double t0 = time(), t1 = time_at(units_ + next_units_);
  std::ostringstream context;
  context << "step " << step_ + 1 << " (t = " << t1 << " s)";

  // Driven vertices first move to their prescribed positions, alone (an error if that would
  // intersect); every start below keeps them there, and Newton never moves them.
  const Eigen::VectorXd q_start = driven_dofs_.empty() ? q_n : driven_start(q_n, t1, context.str());

  // Start from the ballistic guess q_hat + w g (the exact answer for a free, undeformed body:
  // M (q - q_hat) = w M g) when the straight path to it is admissible, else from q_n. Starting
  // there also keeps a free fall on the parabola to round-off: Newton's last, unapplied step
  // (below tolerance by design) then holds no rigid motion.
  const Eigen::VectorXd guess = ballistic_guess(q_hat);
  const double w = integrator_.potential_weight();
  Eigen::VectorXd x = q_start;
  if (potential_->max_step_size(q_start, guess) >= 1.0 &&
      potential_->is_step_valid(q_start, guess)) {
    x = guess;
  }
  // For a spinning body the ballistic guess is far from rigid: q_hat extrapolates every vertex
  // along a chord, stretching the body by ~theta^2 / 2 (1.6 mm on the 2000-tet ball spinning
  // after its bounce). At Y = 1e13 that stretch is stress, and its geometric stiffness stiffens
  // the Hessian's rotations ~1e6-fold over their inertia (measured 1.6e5 against 0.106 kg m^2), so
  // Newton corrected the step's rotation only once the stretch was gone: 5 iterations per
  // free-flight step. The previous shape moved rigidly onto the guess (its centre of mass and
  // best-fit rotation) has no such stretch; it is used when admissible and lower in energy. A
  // driven body moves by its drive's rigid motion over the step instead.
  if (settings_.rigid_predictor) {
    Eigen::VectorXd rigid = guess;
    if (settings_.bodies.empty() || !free_bodies_.empty()) {
      rigid = rigid_predictor(q_n, guess, vertex_masses_, free_bodies_);
    }
    if (!driven_dofs_.empty()) apply_drive_step(q_n, t0, t1, rigid);
    if (rigid.allFinite() && potential_->max_step_size(q_start, rigid) >= 1.0 &&
        potential_->is_step_valid(q_start, rigid) && potential_->value_difference(x, rigid) < 0) {
      x = rigid;
    }
  }
  NewtonResult r = newton_.minimize(*potential_, x, context.str());
  // Friction re-lagged from the solution (SimulationSettings::friction_iterations), until a
  // re-lagged solve takes no step: its first Newton iteration (the check) already converges. A
  // lag without pairs before and after changes nothing (free flight, frictionless scenes).
  auto lagged_pairs = [this] {
    return (plane_friction_ ? plane_friction_->num_lagged_pairs() : 0) +
           (pair_friction_ ? pair_friction_->num_lagged_pairs() : 0);
  };
  int relags = 0;
  for (int i = 1; i < settings_.friction_iterations; ++i) {
    const int before = lagged_pairs();
    potential_->relag(x);
    if (before == 0 && lagged_pairs() == 0) break;
    ++relags;
    const NewtonResult ri =
        newton_.minimize(*potential_, x, context.str() + ", friction lag " + std::to_string(i + 1));
    r.append(ri);
    if (ri.iterations <= 1) break;
  }
  integrator_.push(x);
  units_ += next_units_;
  ++step_;

  StepStats s;
  s.add(r);
  s.ccd_caps = potential_->ccd_caps() - caps_before;
  s.friction_relags = relags;
  s.min_distance = contact_->min_distance(x);
  if (mesh_contact_) s.min_distance = std::min(s.min_distance, mesh_contact_->min_distance(x));
  if (body_contact_) s.min_distance = std::min(s.min_distance, body_contact_->min_distance(x));
  s.active_pairs = active_pairs(x);
  if (!driven_dofs_.empty()) {
    // The step equation's residual at the driven dofs: w times the force the drives exert.
    const Eigen::VectorXd G = potential_->unconstrained_gradient(x);
    for (int d : driven_dofs_) s.dirichlet_force[d % 3] += G[d] / w;
  }
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return s;
}

Trajectory Simulator::run(const Eigen::VectorXd& q0, const Eigen::VectorXd& v0,
                          const StepCallback& callback) {
  reset(q0, v0);
  Trajectory t;
  t.time_step = settings_.time_step;
  t.integrator = settings_.integrator;
  t.kappa = settings_.kappa;
  for (int k = 1; k <= 3; ++k) t.history.push_back(integrator_.past(k));
  t.q.reserve(settings_.num_steps + 1);
  t.q.push_back(q0);
  if (settings_.contact_substeps > 0) {
    run_resolving(t, callback);
    return t;
  }
  for (int k = 0; k < settings_.num_steps; ++k) {
    const StepStats s = advance();
    t.q.push_back(integrator_.current());
    t.steps.push_back(s);
    if (callback) callback(step_, integrator_.current(), s);
  }
  return t;
}

int Simulator::active_pairs(const Eigen::VectorXd& x) const {
  int n = contact_->num_active_pairs(x);
  if (mesh_contact_) n += mesh_contact_->num_active_pairs(x);
  if (body_contact_) n += body_contact_->num_active_pairs(x);
  return n;
}

Eigen::VectorXd Simulator::ballistic_guess(const Eigen::VectorXd& q_hat) const {
  Eigen::VectorXd guess = q_hat;
  const double w = integrator_.potential_weight();
  for (int v = 0; v < rest_.num_vertices(); ++v) guess.segment<3>(3 * v) += w * settings_.gravity;
  if (!driven_dofs_.empty()) set_driven_positions(guess, time_at(units_ + next_units_));
  return guess;
}

bool Simulator::prediction_in_contact() const {
  // advance()'s ballistic guess: if flying there meets an obstacle or ends within d_hat, the
  // step will very likely end in contact.
  const Eigen::VectorXd guess = ballistic_guess(integrator_.predictor());
  return potential_->max_step_size(integrator_.current(), guess) < 1.0 || active_pairs(guess) > 0;
}

void Simulator::run_resolving(Trajectory& t, const StepCallback& callback) {
  // Dyadic steps: sizes of 2^j units of h/k, each starting at a multiple of itself, so every step
  // of h is covered exactly and any step ends on the grid when it is a whole h. A step whose
  // ballistic guess meets contact is halved before it is taken, and one that ends in contact is
  // taken again at half its size, until it is one unit; out of contact the size doubles (ratio
  // 2) whenever the time is a multiple of the doubled size.
  const int k = units_per_step_;
  ContactResolvingStats& r = t.resolving;
  r.substeps = k;
  t.times.push_back(time());
  t.grid.push_back(0);
  const long end = static_cast<long>(settings_.num_steps) * k;
  int size = k;
  bool was_in_contact = false;
  while (units_ < end) {
    const BdfIntegrator saved = integrator_;
    const long saved_units = units_;
    const int saved_step = step_;
    set_next_step(size);
    if (size > 1 && prediction_in_contact()) {
      // Halved before any Newton iteration is spent on it.
      ++r.predicted_halvings;
      size /= 2;
      continue;
    }
    const double h = integrator_.next_step();
    const StepStats s = advance();
    const bool in_contact = s.active_pairs > 0;
    if (in_contact && size > 1) {
      integrator_ = saved;
      units_ = saved_units;
      step_ = saved_step;
      ++r.rejected_steps;
      r.rejected_newton_iterations += s.newton_iterations;
      r.rejected_seconds += s.seconds;
      size /= 2;
      continue;
    }
    t.q.push_back(integrator_.current());
    t.steps.push_back(s);
    t.step_sizes.push_back(h);
    t.times.push_back(time());
    if (units_ % k == 0) t.grid.push_back(t.num_steps());
    if (size < k) ++r.refined_steps;
    if (in_contact && !was_in_contact) ++r.contacts;
    was_in_contact = in_contact;
    if (callback) callback(step_, integrator_.current(), s);
    if (!in_contact && size < k && units_ % (2 * size) == 0) size *= 2;
  }
}

}  // namespace rbaa
