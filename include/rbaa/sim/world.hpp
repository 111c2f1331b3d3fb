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

enum class Integrator { kBdf1, kBdf2 };
enum class MassModel { kConsistent, kLumped };

/// One body of a stacked mesh: vertices [vertex_begin, vertex_end) and elements [element_begin,
/// element_end), moving at t = 0 rigidly with `velocity` and spinning with `angular_velocity`
/// about `centre` (its centre of mass).
struct Body {
  std::string name;  ///< for messages: "bodies[1] (ball)", or "object"
  int vertex_begin = 0, vertex_end = 0;
  int element_begin = 0, element_end = 0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();            ///< m
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();          ///< m/s
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  ///< rad/s

  int num_vertices() const { return vertex_end - vertex_begin; }
  int num_elements() const { return element_end - element_begin; }
};

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
