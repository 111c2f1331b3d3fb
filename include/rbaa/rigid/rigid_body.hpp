#pragma once
// Rigid-body view of a tet mesh with a material field: what every rigid-body simulator sees
// (mass, centre of mass, principal inertia) and the collision shape. Built from the object's own
// moments, never copied from another object's.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "rbaa/geometry/moments.hpp"
#include "rbaa/mesh/tet_mesh.hpp"
#include "rbaa/sim/world.hpp"

namespace rbaa {

/// Mass properties in principal form: I_centre = axes diag(principal_moments) axes^T.
struct RigidMassProperties {
  double mass = 0;                                               ///< m0 (kg)
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();              ///< m1 / m0 in the mesh frame (m)
  Eigen::Vector3d principal_moments = Eigen::Vector3d::Zero();   ///< ascending (kg m^2)
  Eigen::Matrix3d principal_axes = Eigen::Matrix3d::Identity();  ///< columns, det = +1
};

/// Mass, centre, and the eigen-decomposition of m2 moved to the centre (parallel-axis shift).
/// Principal moments equal within `degenerate_tolerance` (relative) get a canonical basis built
/// from the mesh axes (identity when all three are equal), and every axis a canonical sign, so
/// that objects with equal inertia get the same frame. With `grid_bits` > 0 the mass, each
/// principal moment, each coordinate of the centre (on the radius of gyration's scale) and each
/// entry of the axes (then made orthonormal again) are rounded to a power-of-two grid of
/// 2^-grid_bits of their scale (6e-8 at 24), so that objects whose moments agree to round-off get
/// bit-identical rigid twins; 0 gives the values as computed.
RigidMassProperties rigid_mass_properties(const Moments& moments,
                                          double degenerate_tolerance = 1e-8, int grid_bits = 24);

/// The collision shape handed to the rigid simulator.
enum class RigidShapeKind { kSphere, kBox, kConvexHull };

struct RigidShape {
  RigidShapeKind kind = RigidShapeKind::kConvexHull;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();        ///< sphere/box centre, mesh frame (m)
  double radius = 0;                                       ///< sphere (m)
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();  ///< axis-aligned box (m)
  Vertices points;  ///< convex hull: its vertices (extreme surface vertices, rounded to the
                    ///< surface's grid, sorted), mesh frame (#P by 3)

  std::string describe() const;
};

/// Chooses the collision shape from the surface: an analytic sphere when every surface vertex
/// lies on one sphere within `sphere_tolerance` of the size (a meshed sphere's vertices sit on
/// facets of the polyhedron CGAL was given, ~1e-4 inside), an analytic box when the surface is an
/// axis-aligned box (within `box_tolerance`), otherwise the convex hull of the surface vertices.
/// All three are fitted to the extreme surface vertices rounded to a grid of at most 6e-8 of the
/// surface's extent, so that two surfaces equal up to round-off (the same object placed by other
/// turns) get bit-identical shapes, whose rigid twins then stay identical.
/// Against half-space obstacles the hull is exact: a plane first touches a body at a hull vertex.
/// Against triangle-mesh obstacles it is exact only for convex bodies: an obstacle's edge can reach
/// into a dent of a concave body, which the hull fills in.
RigidShape rigid_shape_from_surface(const TetMesh& mesh, double sphere_tolerance = 1e-3,
                                    double box_tolerance = 1e-9);

/// One body of the twin at t = 0. Its mass properties and shape are those of its placed mesh
/// (world coordinates, so the initial orientation is the identity and mass.centre is where its
/// centre of mass starts).
struct RigidBody {
  std::string name;  ///< for messages: "object", "'ball'"
  RigidMassProperties mass;
  RigidShape shape;
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();          ///< of the centre of mass (m/s)
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  ///< rad/s (world)
  /// A kinematic body: its pose is not integrated but follows `drive` from its t = 0 pose (a mesh
  /// point x0 is at drive.position(x0, t)); it pushes dynamic bodies and is not pushed back.
  /// velocity and angular_velocity are then the drive's at t = 0.
  bool kinematic = false;
  PrescribedMotion drive{};
};

/// The twins of the bodies of a stacked mesh (sim/world.hpp's Body ranges), each from its own
/// vertices, elements and densities (`density`: #T, per element of the stacked mesh), with its
/// Body's initial velocity and spin. A driven Body becomes a kinematic twin on its drive.
std::vector<RigidBody> rigid_bodies(const TetMesh& stacked, const std::vector<Body>& bodies,
                                    const Eigen::VectorXd& density);

}  // namespace rbaa
