#pragma once
// Rigid bodies among half-space and triangle-mesh obstacles in Bullet (double precision): the
// rigid-body simulator every adversarial object must fool. It takes the physical model
// (sim/world.hpp's obstacles, the bodies' mass properties and shapes), never the config; Bullet
// types stay inside src/rigid.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "rbaa/rigid/rigid_body.hpp"
#include "rbaa/sim/world.hpp"

namespace rbaa {

/// The restitution of one pair of bodies (indices in RigidWorld::bodies, a != b, either order).
struct BodyPairRestitution {
  int a = 0, b = 1;
  double restitution = 1.0;
};

/// The restitution of one body against one plane (indices in RigidWorld::bodies and ::planes).
struct BodyPlaneRestitution {
  int body = 0, plane = 0;
  double restitution = 1.0;
};

/// Bullet combines the restitutions of the two objects in a contact by their product: a body
/// against obstacle i has restitution * plane_restitution[i] (or mesh_restitution[i]); two bodies
/// have restitution^2, unless pair_restitution names the pair: then exactly its value (a product
/// of per-body factors cannot give every pair its own value, so the twin overwrites the pair's
/// contact points before each solve); likewise a body against a plane that body_plane_restitution
/// names has exactly its value, in place of restitution * plane_restitution[i] (bodies of one
/// scene meet the same floor with different rebounds: each is fitted to its own). Friction is not
/// here but in RigidWorld: it is the scene's physical coefficient, the deformable simulator's too,
/// while these are the twin's numerics and its fitted (calibrated) restitutions.
struct RigidSettings {
  double internal_step = 1e-3;  ///< Bullet's fixed step (s); outputs are sampled at the world's h
  double restitution = 1.0;     ///< body restitution; Bullet multiplies it with the obstacle's
  /// Restitution of each plane (index as in RigidWorld::planes); missing entries are 1.
  std::vector<double> plane_restitution;
  /// Restitution of each obstacle mesh (index as in RigidWorld::obstacle_meshes); missing are 1.
  std::vector<double> mesh_restitution;
  /// Restitution of named pairs of bodies, in place of restitution^2; at most one entry a pair.
  std::vector<BodyPairRestitution> pair_restitution;
  /// Restitution of named (body, plane) pairs, in place of restitution * plane_restitution[plane];
  /// at most one entry a pair.
  std::vector<BodyPlaneRestitution> body_plane_restitution;
  double margin = 1e-4;  ///< collision margin (m), at most d_hat (Bullet's 0.04 m default
                         ///< is nearly the cube's half size)
  /// Split impulse with a generous penetration threshold: Bullet's default Baumgarte correction
  /// (erp 0.2) pushes bodies apart with extra energy and spoils the restitution.
  bool split_impulse = true;
  int solver_iterations = 200;  ///< projected Gauss-Seidel sweeps per step (Bullet default 10)
};

/// What the twin simulates: bodies (the object first) among static obstacles under gravity,
/// sampled every time_step.
///
/// Coulomb friction is given per pair of surfaces, as the deformable simulator has it: a body
/// against plane i has planes[i].friction, against obstacle mesh i obstacle_meshes[i].friction,
/// two bodies pair_friction's value when it names them, else body_friction. Each contact point
/// gets exactly its pair's coefficient, not Bullet's product of per-object factors (a plane with
/// friction, which every body meets with the same mu, would force the bodies' factors equal, and
/// so one coefficient on every pair of bodies); no rolling or spinning friction.
struct RigidWorld {
  std::vector<RigidBody> bodies;
  std::vector<Plane> planes;
  std::vector<ObstacleMesh> obstacle_meshes;  ///< V and F are used (placed), open surfaces too
  double body_friction = 0.0;                 ///< Coulomb coefficient of pairs of bodies
  /// Coefficients of named pairs of bodies (indices in `bodies`), in place of body_friction; at
  /// most one entry a pair.
  std::vector<BodyPairFriction> pair_friction;
  Eigen::Vector3d gravity{0.0, 0.0, -9.8};  ///< m/s^2
  double time_step = 0.01;                  ///< h between output samples (s)
};

/// State of a body at one output time, in its mesh frame: the mesh point x0 (placed rest mesh
/// coordinates) is at position + orientation (x0 - mass.centre).
struct RigidState {
  double time = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();               ///< centre of mass (m)
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< mesh frame rotation
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();               ///< m/s
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();       ///< rad/s (world)
};

/// One side of a contact: a body, a plane or an obstacle mesh (index in RigidWorld's list).
struct RigidContactSide {
  enum class Kind { kBody, kPlane, kMesh };
  Kind kind = Kind::kBody;
  int index = 0;
  friend bool operator==(const RigidContactSide& x, const RigidContactSide& y) {
    return x.kind == y.kind && x.index == y.index;
  }
};

/// The Coulomb coefficient the twin gives contacts between `first`, a body, and `second` (a body,
/// plane or mesh of `world`; RigidWorld's rule). Throws std::out_of_range for an index the world
/// has not.
double rigid_friction(const RigidWorld& world, RigidContactSide first, RigidContactSide second);

/// A pair that touched (a contact point at distance <= 0 when Bullet's solver ran, i.e. one it
/// applied an impulse to) during the internal steps from output sample `sample` - 1 to `sample`.
/// `first` is a body; `second` an obstacle or a body with a larger index.
struct RigidTouch {
  int sample = 0;
  RigidContactSide first, second;
};

/// Simulates the world for `duration` seconds; returns, per body in the world's order, its states
/// at t = 0, h, 2h, ... (h = world.time_step), and, if `touches` is given, every pair that touched
/// between two samples (once a sample, in sample order). Throws rbaa::InputError naming the body
/// or value at fault (no bodies, non-positive mass or inertia, bad step or margin, empty
/// obstacle mesh, a negative or non-finite restitution or friction coefficient, a pair
/// restitution or friction naming a missing body, one body twice or one pair twice, a body-plane
/// restitution naming a missing body or plane, or one pair twice).
std::vector<std::vector<RigidState>> simulate_rigid(const RigidWorld& world,
                                                    const RigidSettings& settings, double duration,
                                                    std::vector<RigidTouch>* touches = nullptr);

}  // namespace rbaa
