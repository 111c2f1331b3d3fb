#pragma once
// The physical model a simulation runs on, between the scene (a config: what the user wrote) and
// the simulator (how it is integrated): the bodies, as vertex and element ranges of one stacked
// tet mesh, each with its initial motion; the obstacles, analytic half-spaces and static triangle
// meshes; gravity; the time integrator and mass model. scene/ turns a config into these; sim/,
// diff/ and rigid/ know only this header, never the config.

#include <Eigen/Core>

#include <string>
#include <vector>

namespace rbaa {

/// Half-space obstacle {x : normal . x >= offset}; normal is unit length.
struct Plane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset = 0.0;
  double friction = 0.0;  ///< Coulomb coefficient mu of bodies against it (0: frictionless)
};

/// A static triangle-mesh obstacle (obstacles.meshes[i]): the file's triangles placed in the world
/// by x = position + R (scale x_file), R the rotation of angle_deg about axis. Open surfaces are
/// allowed (a backboard may be one rectangle). V is #V by 3 (placed), F is #F by 3.
struct ObstacleMesh {
  std::string file;  ///< resolved path, for messages and the fingerprint
  std::string name;  ///< "obstacles.meshes[i] (FILE)", for messages
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d rotation_axis = Eigen::Vector3d::UnitZ();
  double rotation_angle_deg = 0.0;
  double scale = 1.0;
  double friction = 0.0;  ///< Coulomb coefficient mu of bodies against it (0: frictionless)
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> V;
  Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> F;
};

/// The Coulomb coefficient between two bodies a != b (indices in the model's list of bodies,
/// either order): a scene's contact.pairs[i], the rigid twin's named pairs.
struct BodyPairFriction {
  int a = 0, b = 0;
  double friction = 0;
};

enum class Integrator { kBdf1, kBdf2 };
enum class MassModel { kConsistent, kLumped };

/// A prescribed rigid motion from t = 0: rotation by angle(t) about the line through `centre`
/// along `axis` (right-handed), while that line translates at `velocity`. A point at x0 at t = 0 is
/// at
///
///   x(t) = centre + t velocity + R(axis, angle(t)) (x0 - centre),
///   angle(t) = integral_0^t omega(s) ds,
///
/// with omega = angular_velocity, or, when `angular_velocity_table` is given, the piecewise-linear
/// interpolation of its (time s, omega rad/s) rows (times strictly increasing; omega held at the
/// first row's value before it and at the last row's after it). Times before 0 (BDF's start-up
/// history) extend the motion backwards by the same rule.
struct PrescribedMotion {
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();      ///< unit
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();     ///< m, a point of the axis at t = 0
  double angular_velocity = 0.0;                        ///< rad/s, without a table
  std::vector<Eigen::Vector2d> angular_velocity_table;  ///< (t s, omega rad/s) rows, or empty
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();   ///< m/s, of the axis

  /// omega(t) (rad/s).
  double angular_speed(double t) const;
  /// angle(t) (rad).
  double angle(double t) const;
  /// R(axis, angle(t)): the turn the motion gives by time t, d x(t) / d x0.
  Eigen::Matrix3d rotation(double t) const;
  /// x(t) of the point that is at x0 at t = 0.
  Eigen::Vector3d position(const Eigen::Vector3d& x0, double t) const;
  /// dx/dt at t of the point that is at x0 at t = 0.
  Eigen::Vector3d point_velocity(const Eigen::Vector3d& x0, double t) const;
};

/// Throws rbaa::InputError naming `who` unless the axis is finite and unit length, the centre,
/// velocity and speeds are finite, and the table's times strictly increase.
void validate_prescribed_motion(const PrescribedMotion& motion, const std::string& who);

/// One body of a stacked mesh: vertices [vertex_begin, vertex_end) and elements [element_begin,
/// element_end), moving at t = 0 rigidly with `velocity` and spinning with `angular_velocity`
/// about `centre` (its centre of mass).
///
/// A driven body has kinematic (Dirichlet) vertices: `driven_vertices` (stacked-mesh vertex ids,
/// within the body's range, ascending, no repeats) follow `drive` from their initial positions
/// exactly; the simulator eliminates them from Newton's unknowns, and the adjoint treats their
/// positions as known functions of time. The whole body starts carried by its drive (velocity and
/// BDF past of every vertex the drive's, whatever the body's initial motion says; scene/ sets that
/// to the drive's rigid motion at t = 0 too).
struct Body {
  std::string name;  ///< for messages: "bodies[1] (ball)", or "object"
  int vertex_begin = 0, vertex_end = 0;
  int element_begin = 0, element_end = 0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();            ///< m
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();          ///< m/s
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  ///< rad/s
  std::vector<int> driven_vertices;  ///< stacked-mesh vertex ids; empty: a free body
  PrescribedMotion drive;            ///< the driven vertices' motion

  int num_vertices() const { return vertex_end - vertex_begin; }
  int num_elements() const { return element_end - element_begin; }
  bool is_driven() const { return !driven_vertices.empty(); }
};

/// The dofs (3 v + k, ascending) of every body's driven vertices.
std::vector<int> driven_dofs(const std::vector<Body>& bodies);

/// The body id of every vertex (#V entries; a vertex outside every body gets -1).
std::vector<int> vertex_body_ids(const std::vector<Body>& bodies, int num_vertices);

/// Per-dof initial velocities (3 #V) of the bodies' rigid motions at positions q; vertices outside
/// every body are at rest.
Eigen::VectorXd initial_velocities(const Eigen::VectorXd& q, const std::vector<Body>& bodies);

/// Per-vertex initial velocities (3 #V) of a body moving with `velocity` and spinning with
/// `angular_velocity` (rad/s) about `centre`.
Eigen::VectorXd rigid_velocities(const Eigen::VectorXd& q, const Eigen::Vector3d& centre,
                                 const Eigen::Vector3d& velocity,
                                 const Eigen::Vector3d& angular_velocity);

}  // namespace rbaa
