#include "rbaa/rigid/rigid_simulation.hpp"

#include <btBulletDynamicsCommon.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "rbaa/error.hpp"

namespace rbaa {
namespace {

btVector3 to_bt(const Eigen::Vector3d& v) { return btVector3(v.x(), v.y(), v.z()); }
Eigen::Vector3d from_bt(const btVector3& v) { return {v.x(), v.y(), v.z()}; }

btMatrix3x3 to_bt(const Eigen::Matrix3d& m) {
  return btMatrix3x3(m(0, 0), m(0, 1), m(0, 2), m(1, 0), m(1, 1), m(1, 2), m(2, 0), m(2, 1),
                     m(2, 2));
}
Eigen::Matrix3d from_bt(const btMatrix3x3& m) {
  Eigen::Matrix3d r;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) r(i, j) = m[i][j];
  }
  return r;
}

// Which object of the RigidWorld a Bullet object is: its user index holds the kind, its second
// user index the position in the world's list.
void tag(btCollisionObject& object, RigidContactSide side) {
  object.setUserIndex(static_cast<int>(side.kind));
  object.setUserIndex2(side.index);
}
RigidContactSide side_of(const btCollisionObject& object) {
  return {static_cast<RigidContactSide::Kind>(object.getUserIndex()), object.getUserIndex2()};
}

// Orders a pair as RigidTouch does: a body first, two bodies by index.
std::pair<RigidContactSide, RigidContactSide> ordered(RigidContactSide x, RigidContactSide y) {
  const bool x_body = x.kind == RigidContactSide::Kind::kBody;
  const bool y_body = y.kind == RigidContactSide::Kind::kBody;
  if (!x_body || (y_body && y.index < x.index)) std::swap(x, y);
  return {x, y};
}

// Bullet's dynamics world with three things done between collision detection and the solve,
// where the new contact points of the step exist but have no impulse yet:
// * every contact point gets its pair's Coulomb coefficient (rigid_friction), and named pairs of
//   bodies and (body, plane) pairs their own restitution. Bullet otherwise gives a pair the product
//   of the two objects' values (which cannot give ball-bat and ball-floor independent values once
//   the ball's own factor is shared) or a process-wide callback (global state, shared by every
//   world in the process); overwriting the points' combined values here touches only this world.
//   The solver reads them when it converts the points into constraints
//   (btSequentialImpulseConstraintSolver::convertContact, within the solve called below):
//   m_combinedFriction becomes each friction row's bound, mu times the point's normal impulse;
//   rolling and spinning friction rows exist only when m_combinedRollingFriction > 0, which stays
//   0 here.
// * every pair with a point the solver will treat (distance <= the manifold's processing
//   threshold, the solver's own test) is logged, for the calibration's contact episodes.
class TwinDynamicsWorld : public btDiscreteDynamicsWorld {
 public:
  using btDiscreteDynamicsWorld::btDiscreteDynamicsWorld;

  const RigidWorld* model = nullptr;                       // its friction coefficients
  std::map<std::pair<int, int>, double> pair_restitution;  // (body a, body b), a < b
  std::map<std::pair<int, int>, double> plane_restitution;  // (body, plane)
  bool log_touches = false;
  std::set<std::tuple<int, int, int, int>> touching;  // since the last clear: ordered pairs

  void solveConstraints(btContactSolverInfo& info) override {
    btDispatcher* dispatcher = getDispatcher();
    for (int i = 0; i < dispatcher->getNumManifolds(); ++i) {
      btPersistentManifold* m = dispatcher->getManifoldByIndexInternal(i);
      if (m->getNumContacts() == 0) continue;
      const auto [x, y] = ordered(side_of(*m->getBody0()), side_of(*m->getBody1()));
      const double mu = rigid_friction(*model, x, y);
      for (int p = 0; p < m->getNumContacts(); ++p) {
        btManifoldPoint& point = m->getContactPoint(p);
        point.m_combinedFriction = mu;
        point.m_combinedRollingFriction = 0;
        point.m_combinedSpinningFriction = 0;
      }
      const auto* named = y.kind == RigidContactSide::Kind::kBody    ? &pair_restitution
                          : y.kind == RigidContactSide::Kind::kPlane ? &plane_restitution
                                                                     : nullptr;
      if (named && !named->empty()) {
        const auto it = named->find({x.index, y.index});
        if (it != named->end()) {
          for (int p = 0; p < m->getNumContacts(); ++p) {
            m->getContactPoint(p).m_combinedRestitution = it->second;
          }
        }
      }
      if (!log_touches) continue;
      for (int p = 0; p < m->getNumContacts(); ++p) {
        if (m->getContactPoint(p).getDistance() <= m->getContactProcessingThreshold()) {
          touching.insert({static_cast<int>(x.kind), x.index, static_cast<int>(y.kind), y.index});
          break;
        }
      }
    }
    btDiscreteDynamicsWorld::solveConstraints(info);
  }
};

// Owns everything a Bullet world needs; Bullet does not own its parts.
struct BulletWorld {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  TwinDynamicsWorld world{&dispatcher, &broadphase, &solver, &configuration};
  std::vector<std::unique_ptr<btTriangleMesh>> triangle_meshes;  // outlive their BVH shapes
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btDefaultMotionState>> motion_states;
  std::vector<std::unique_ptr<btRigidBody>> bodies;

  BulletWorld() {
    // A convex body meets a plane at one contact point per step by default (its deepest vertex),
    // so a box landing flat is pushed at one corner first and leaves spinning (4 rad/s for a
    // step, 0.02 rad/s after, in RigidSimulation.FlatLandingBoxDoesNotSpin). Perturbing the
    // contact normal three times collects the whole face before the impulses are solved.
    configuration.setPlaneConvexMultipointIterations(3, 3);
  }
  ~BulletWorld() {
    for (auto& body : bodies) world.removeRigidBody(body.get());
  }
};

std::unique_ptr<btCollisionShape> make_child_shape(const RigidShape& shape, double margin) {
  switch (shape.kind) {
    case RigidShapeKind::kSphere:
      return std::make_unique<btSphereShape>(shape.radius);  // its margin is its radius
    case RigidShapeKind::kBox: {
      // btBoxShape keeps its margin inside the given extents.
      auto box = std::make_unique<btBoxShape>(to_bt(shape.half_extents));
      box->setMargin(margin);
      box->initializePolyhedralFeatures();
      return box;
    }
    case RigidShapeKind::kConvexHull: {
      auto hull = std::make_unique<btConvexHullShape>();
      for (Eigen::Index i = 0; i < shape.points.rows(); ++i) {
        hull->addPoint(to_bt(Eigen::Vector3d(shape.points.row(i).transpose())), false);
      }
      hull->recalcLocalAabb();
      hull->setMargin(margin);
      hull->initializePolyhedralFeatures();
      return hull;
    }
  }
  throw InputError("unknown rigid shape");
}

// A static obstacle: Bullet's mass-0 body, which never moves. Its friction factor is 0: every
// contact point gets its pair's coefficient before the solve (TwinDynamicsWorld).
void add_obstacle(BulletWorld& w, std::unique_ptr<btCollisionShape> shape, double restitution,
                  RigidContactSide side) {
  btRigidBody::btRigidBodyConstructionInfo ci(0.0, nullptr, shape.get());
  ci.m_friction = 0;
  auto body = std::make_unique<btRigidBody>(ci);
  tag(*body, side);
  body->setRestitution(restitution);
  w.world.addRigidBody(body.get());
  w.shapes.push_back(std::move(shape));
  w.bodies.push_back(std::move(body));
}

std::unique_ptr<btCollisionShape> make_mesh_shape(BulletWorld& w, const ObstacleMesh& mesh) {
  if (mesh.F.rows() == 0 || mesh.V.rows() == 0) {
    throw InputError(mesh.name + ": an obstacle mesh needs at least one triangle");
  }
  if (mesh.F.minCoeff() < 0 || mesh.F.maxCoeff() >= mesh.V.rows()) {
    throw InputError(mesh.name + ": a triangle refers to a vertex that does not exist");
  }
  // btTriangleMesh copies the vertices (as doubles: BT_USE_DOUBLE_PRECISION) and indices.
  auto triangles = std::make_unique<btTriangleMesh>();
  triangles->preallocateVertices(static_cast<int>(mesh.V.rows()));
  triangles->preallocateIndices(static_cast<int>(3 * mesh.F.rows()));
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) {
    triangles->findOrAddVertex(btVector3(mesh.V(i, 0), mesh.V(i, 1), mesh.V(i, 2)), false);
  }
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    triangles->addTriangleIndices(mesh.F(f, 0), mesh.F(f, 1), mesh.F(f, 2));
  }
  auto shape = std::make_unique<btBvhTriangleMeshShape>(triangles.get(), true);
  // No margin, as a plane's: the triangles are where the file puts them.
  shape->setMargin(0);
  w.triangle_meshes.push_back(std::move(triangles));
  return shape;
}

// A dynamic body. Its Bullet frame is the principal frame at the centre of mass; the collision
// shape, given in placed mesh coordinates, sits in it through the compound's child transform
// y = A^T (x - c).
btRigidBody* add_body(BulletWorld& w, const RigidBody& r, int index,
                      const RigidSettings& settings) {
  if (r.kinematic) validate_prescribed_motion(r.drive, "rigid body " + r.name + "'s drive");
  const RigidMassProperties& mass = r.mass;
  if (!(mass.mass > 0) || !(mass.principal_moments.minCoeff() > 0)) {
    throw InputError("rigid body " + r.name + " needs positive mass and principal moments");
  }
  const Eigen::Matrix3d A = mass.principal_axes;
  const Eigen::Vector3d c0 = mass.centre;
  auto child = make_child_shape(r.shape, settings.margin);
  auto compound = std::make_unique<btCompoundShape>();
  const Eigen::Vector3d child_origin = A.transpose() * (r.shape.kind == RigidShapeKind::kConvexHull
                                                            ? Eigen::Vector3d(-c0)
                                                            : Eigen::Vector3d(r.shape.centre - c0));
  compound->addChildShape(btTransform(to_bt(Eigen::Matrix3d(A.transpose())), to_bt(child_origin)),
                          child.get());
  auto motion = std::make_unique<btDefaultMotionState>(btTransform(to_bt(A), to_bt(c0)));
  // A kinematic body has Bullet's infinite mass (0) and takes its pose from its motion state.
  btRigidBody::btRigidBodyConstructionInfo ci(
      r.kinematic ? 0.0 : mass.mass, motion.get(), compound.get(),
      r.kinematic ? btVector3(0, 0, 0) : to_bt(mass.principal_moments));
  ci.m_linearDamping = 0;
  ci.m_angularDamping = 0;
  ci.m_restitution = settings.restitution;
  ci.m_friction = 0;  // as an obstacle's (add_obstacle)
  auto body = std::make_unique<btRigidBody>(ci);
  tag(*body, {RigidContactSide::Kind::kBody, index});
  if (r.kinematic) {
    // Mass 0 made it static; kinematic instead (moved by its motion state, never integrated).
    body->setCollisionFlags((body->getCollisionFlags() & ~btCollisionObject::CF_STATIC_OBJECT) |
                            btCollisionObject::CF_KINEMATIC_OBJECT);
  }
  body->setActivationState(DISABLE_DEACTIVATION);
  body->setFlags(body->getFlags() | BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY);
  body->setLinearVelocity(to_bt(r.velocity));
  body->setAngularVelocity(to_bt(r.angular_velocity));
  body->setCcdMotionThreshold(0);
  // Bullet also solves "speculative" contacts that are still apart; combined with restitution
  // they slow the body before it arrives, so that it lands with almost no speed and bounces
  // with none. Only touching contacts are solved here.
  body->setContactProcessingThreshold(0);
  w.world.addRigidBody(body.get());
  btRigidBody* added = body.get();
  w.shapes.push_back(std::move(child));
  w.shapes.push_back(std::move(compound));
  w.motion_states.push_back(std::move(motion));
  w.bodies.push_back(std::move(body));
  return added;
}

// The pose at time t of a kinematic body (Bullet frame: the principal frame A at the centre c0 at
// t = 0): x0 -> drive.position(x0, t) is the rotation R(t) about the axis through the drive's
// centre, so the frame turns to R(t) A and its origin goes where the drive carries c0.
btTransform kinematic_pose(const RigidBody& r, double t) {
  return btTransform(to_bt(Eigen::Matrix3d(r.drive.rotation(t) * r.mass.principal_axes)),
                     to_bt(r.drive.position(r.mass.centre, t)));
}

// Throws unless every restitution is a finite number >= 0, every pair names two different bodies
// of the world, once, and every (body, plane) pair a body and a plane of the world, once.
void validate_restitutions(const RigidSettings& settings, int num_bodies, int num_planes) {
  auto check = [](double e, const std::string& what) {
    if (!(e >= 0) || !std::isfinite(e)) {
      std::ostringstream msg;
      msg << "rigid settings: " << what << " must be a finite number >= 0, got " << e;
      throw InputError(msg.str());
    }
  };
  check(settings.restitution, "the body restitution");
  for (size_t i = 0; i < settings.plane_restitution.size(); ++i) {
    check(settings.plane_restitution[i], "plane " + std::to_string(i) + "'s restitution");
  }
  for (size_t i = 0; i < settings.mesh_restitution.size(); ++i) {
    check(settings.mesh_restitution[i], "obstacle mesh " + std::to_string(i) + "'s restitution");
  }
  std::set<std::pair<int, int>> seen;
  for (const BodyPairRestitution& p : settings.pair_restitution) {
    const std::string name =
        "the restitution of bodies (" + std::to_string(p.a) + ", " + std::to_string(p.b) + ")";
    if (p.a < 0 || p.b < 0 || p.a >= num_bodies || p.b >= num_bodies || p.a == p.b) {
      throw InputError("rigid settings: " + name + " must name two different bodies of the " +
                       std::to_string(num_bodies) + " in the world");
    }
    if (!seen.insert(std::minmax(p.a, p.b)).second) {
      throw InputError("rigid settings: " + name + " is given twice");
    }
    check(p.restitution, name);
  }
  std::set<std::pair<int, int>> seen_planes;
  for (const BodyPlaneRestitution& p : settings.body_plane_restitution) {
    const std::string name = "the restitution of body " + std::to_string(p.body) +
                             " against plane " + std::to_string(p.plane);
    if (p.body < 0 || p.body >= num_bodies || p.plane < 0 || p.plane >= num_planes) {
      throw InputError("rigid settings: " + name + " must name one of the " +
                       std::to_string(num_bodies) + " bodies and one of the " +
                       std::to_string(num_planes) + " planes in the world");
    }
    if (!seen_planes.insert({p.body, p.plane}).second) {
      throw InputError("rigid settings: " + name + " is given twice");
    }
    check(p.restitution, name);
  }
}

// Throws unless every friction coefficient is a finite number >= 0 and every named pair names two
// different bodies of the world, once.
void validate_friction(const RigidWorld& world) {
  auto check = [](double mu, const std::string& what) {
    if (!(mu >= 0) || !std::isfinite(mu)) {
      std::ostringstream msg;
      msg << "rigid world: " << what << " must be a finite number >= 0, got " << mu;
      throw InputError(msg.str());
    }
  };
  for (size_t i = 0; i < world.planes.size(); ++i) {
    check(world.planes[i].friction, "plane " + std::to_string(i) + "'s friction");
  }
  for (size_t i = 0; i < world.obstacle_meshes.size(); ++i) {
    check(world.obstacle_meshes[i].friction, "obstacle mesh " + std::to_string(i) + "'s friction");
  }
  check(world.body_friction, "the friction between bodies");
  const int num_bodies = static_cast<int>(world.bodies.size());
  std::set<std::pair<int, int>> seen;
  for (const BodyPairFriction& p : world.pair_friction) {
    const std::string name =
        "the friction of bodies (" + std::to_string(p.a) + ", " + std::to_string(p.b) + ")";
    if (p.a < 0 || p.b < 0 || p.a >= num_bodies || p.b >= num_bodies || p.a == p.b) {
      throw InputError("rigid world: " + name + " must name two different bodies of the " +
                       std::to_string(num_bodies) + " in the world");
    }
    if (!seen.insert(std::minmax(p.a, p.b)).second) {
      throw InputError("rigid world: " + name + " is given twice");
    }
    check(p.friction, name);
  }
}

}  // namespace

double rigid_friction(const RigidWorld& world, RigidContactSide first, RigidContactSide second) {
  const auto [x, y] = ordered(first, second);
  switch (y.kind) {
    case RigidContactSide::Kind::kPlane:
      return world.planes.at(y.index).friction;
    case RigidContactSide::Kind::kMesh:
      return world.obstacle_meshes.at(y.index).friction;
    case RigidContactSide::Kind::kBody:
      break;
  }
  const int num_bodies = static_cast<int>(world.bodies.size());
  if (x.index < 0 || x.index >= num_bodies || y.index < 0 || y.index >= num_bodies) {
    throw std::out_of_range("rigid_friction: no body " + std::to_string(x.index) + " or " +
                            std::to_string(y.index) + " in the world");
  }
  for (const BodyPairFriction& p : world.pair_friction) {
    if (std::minmax(p.a, p.b) == std::minmax(x.index, y.index)) return p.friction;
  }
  return world.body_friction;
}

std::vector<std::vector<RigidState>> simulate_rigid(const RigidWorld& world,
                                                    const RigidSettings& settings, double duration,
                                                    std::vector<RigidTouch>* touches) {
  if (world.bodies.empty()) throw InputError("rigid world: no bodies to simulate");
  if (!(world.time_step > 0) || !(duration >= 0)) {
    std::ostringstream msg;
    msg << "rigid world: the time step must be positive and the duration not negative, got "
        << world.time_step << " s and " << duration << " s";
    throw InputError(msg.str());
  }
  if (!(settings.internal_step > 0) || !(settings.margin >= 0)) {
    std::ostringstream msg;
    msg << "rigid settings: the internal step must be positive and the margin not negative, got "
        << settings.internal_step << " s and " << settings.margin << " m";
    throw InputError(msg.str());
  }
  validate_restitutions(settings, static_cast<int>(world.bodies.size()),
                        static_cast<int>(world.planes.size()));
  validate_friction(world);
  if (touches) touches->clear();
  const double h = world.time_step;
  // The largest internal step not above the requested one that divides the output step.
  const int substeps = static_cast<int>(std::ceil(h / settings.internal_step - 1e-9));
  const double dt = h / substeps;
  const int steps = static_cast<int>(std::llround(duration / h));

  BulletWorld w;
  w.world.setGravity(to_bt(world.gravity));
  w.world.getDispatchInfo().m_enableSatConvex = true;
  btContactSolverInfo& info = w.world.getSolverInfo();
  // Bullet gives zero restitution below 0.2 m/s by default; the cube hits at 0.1 m/s.
  info.m_restitutionVelocityThreshold = 0;
  // Enough projected Gauss-Seidel sweeps that simultaneous contacts (two star tips) converge to
  // the impact law's unique answer instead of one that depends on round-off.
  info.m_numIterations = settings.solver_iterations;
  info.m_splitImpulse = settings.split_impulse;
  // Bullet splits the positional correction off the velocity solve only for contacts deeper
  // than this (negative) threshold; a large positive one splits every contact, so Baumgarte's
  // correction never feeds energy into the rebound.
  info.m_splitImpulsePenetrationThreshold = 1e30;
  // Contact points are born inside the breaking threshold, before the bodies touch; Bullet
  // drops restitution for points older than two steps, which at small steps is every impact.
  info.m_restingContactRestitutionThreshold = std::numeric_limits<int>::max();

  for (size_t p = 0; p < world.planes.size(); ++p) {
    const Plane& plane = world.planes[p];
    add_obstacle(w, std::make_unique<btStaticPlaneShape>(to_bt(plane.normal), plane.offset),
                 p < settings.plane_restitution.size() ? settings.plane_restitution[p] : 1.0,
                 {RigidContactSide::Kind::kPlane, static_cast<int>(p)});
  }
  for (size_t m = 0; m < world.obstacle_meshes.size(); ++m) {
    add_obstacle(w, make_mesh_shape(w, world.obstacle_meshes[m]),
                 m < settings.mesh_restitution.size() ? settings.mesh_restitution[m] : 1.0,
                 {RigidContactSide::Kind::kMesh, static_cast<int>(m)});
  }
  std::vector<btRigidBody*> bodies;
  for (size_t b = 0; b < world.bodies.size(); ++b) {
    bodies.push_back(add_body(w, world.bodies[b], static_cast<int>(b), settings));
  }
  w.world.model = &world;
  for (const BodyPairRestitution& p : settings.pair_restitution) {
    w.world.pair_restitution[std::minmax(p.a, p.b)] = p.restitution;
  }
  for (const BodyPlaneRestitution& p : settings.body_plane_restitution) {
    w.world.plane_restitution[{p.body, p.plane}] = p.restitution;
  }
  w.world.log_touches = touches != nullptr;

  auto sample = [&](size_t b, double t) {
    const btTransform& T = bodies[b]->getWorldTransform();
    RigidState s;
    s.time = t;
    s.position = from_bt(T.getOrigin());
    s.orientation =
        Eigen::Quaterniond(from_bt(T.getBasis()) * world.bodies[b].mass.principal_axes.transpose())
            .normalized();
    s.velocity = from_bt(bodies[b]->getLinearVelocity());
    s.angular_velocity = from_bt(bodies[b]->getAngularVelocity());
    if (const RigidBody& r = world.bodies[b]; r.kinematic) {
      // Bullet's kinematic velocities are chords over the last internal step; the drive's exact.
      s.velocity = r.drive.point_velocity(r.mass.centre, t);
      s.angular_velocity = r.drive.angular_speed(t) * r.drive.axis;
    }
    return s;
  };
  std::vector<std::vector<RigidState>> states(bodies.size());
  for (size_t b = 0; b < bodies.size(); ++b) {
    states[b].reserve(steps + 1);
    states[b].push_back(sample(b, 0.0));
  }
  // Kinematic bodies: before each internal step their motion states get the pose at its end;
  // Bullet reads it at the step's start and gives the body the velocity that reaches it, which
  // the contact solver uses, then leaves the body exactly there.
  auto step_to = [&](double t) {
    for (size_t b = 0; b < bodies.size(); ++b) {
      if (world.bodies[b].kinematic) {
        bodies[b]->getMotionState()->setWorldTransform(kinematic_pose(world.bodies[b], t));
      }
    }
    w.world.stepSimulation(dt, 0);
  };
  for (int n = 1; n <= steps; ++n) {
    for (int k = 0; k < substeps; ++k) step_to((n - 1) * h + (k + 1) * dt);
    for (size_t b = 0; b < bodies.size(); ++b) states[b].push_back(sample(b, n * h));
    if (touches) {
      for (const auto& [xk, xi, yk, yi] : w.world.touching) {
        touches->push_back({n,
                            {static_cast<RigidContactSide::Kind>(xk), xi},
                            {static_cast<RigidContactSide::Kind>(yk), yi}});
      }
      w.world.touching.clear();
    }
  }
  return states;
}

}  // namespace rbaa
