#pragma once
// The first contact episode of a deformable run with each obstacle mesh, of each body with each
// plane and between each pair of bodies: where `rbaa evaluate` fits the rigid twin's mesh,
// body-plane and body-pair restitutions. (The object's planes also have the run's own bounces,
// sim/observables.hpp, which the evaluation fits them to.) An episode is a maximal run of
// positions in which the two surfaces are within d_hat (vertex-triangle, triangle-vertex and
// edge-edge distances of the pairs contact/'s broad phase finds; a surface vertex's distance to a
// plane), as find_bounces does for the object's planes.

#include <Eigen/Core>
#include <vector>

#include "rbaa/scene/simulate.hpp"
#include "rbaa/sim/world.hpp"

namespace rbaa {

struct ContactEpisode {
  enum class Kind { kMesh, kBodies, kPlane };
  Kind kind = Kind::kMesh;
  int body = 0;        ///< run.bodies index (0: the object)
  /// kMesh: the obstacle mesh's index; kBodies: the second body (> body); kPlane: the plane's.
  int other = 0;
  int first_step = 0;  ///< first position within d_hat
  int last_step = 0;   ///< last position of the run within d_hat
  /// Position whose velocity is read after the episode: settle_steps after last_step, fewer when
  /// either body comes within d_hat of anything again (BDF-2's velocity needs a few steps to
  /// settle after an impact).
  int out_step = 0;
  bool complete = false;  ///< in contact neither at the first position nor at the last
  /// Unit normal of the closest pair at first_step, from `other` towards `body` (on a faceted
  /// surface a facet's, not the net contact normal; a plane's own normal).
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  /// The closest point at first_step on `other`'s side (m), where a driven body's velocity is read
  /// (a plane's: the closest vertex's foot on it).
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
};

/// For each obstacle mesh the first episode of any body with it (the earliest body's), for each
/// pair of bodies its first episode, and for each body and plane their first episode, ordered by
/// first_step (meshes, then pairs, then planes on ties). Bodies as in run.bodies (one body, the
/// whole mesh, when empty). Throws rbaa::InputError if d_hat is not positive.
std::vector<ContactEpisode> first_contact_episodes(const SimulationRun& run,
                                                   const std::vector<ObstacleMesh>& meshes,
                                                   const std::vector<Plane>& planes, double d_hat,
                                                   int settle_steps = 5);

}  // namespace rbaa
