#pragma once
// The active contact pairs at a configuration: primitive pairs closer than d_hat. Round 1 has one
// pair type, surface vertex vs analytic plane; vertex-triangle and edge-edge pairs (obstacle meshes,
// body-body contact) and their lagged friction data will be further lists here, each with its own
// distance, derivatives and CCD beside vertex_plane.hpp, so that the contact form and the solver
// keep their shape.

#include <Eigen/Core>

#include <vector>

#include "rbaa/sim/world.hpp"

namespace rbaa {

struct VertexPlanePair {
  int vertex;      ///< mesh vertex index
  int plane;       ///< index into the scene's planes
  double distance; ///< distance at the configuration the set was built at
};

/// Candidate primitives (surface vertices, obstacles) and the pairs active at one configuration.
class ContactSet {
 public:
  ContactSet(std::vector<int> surface_vertices, std::vector<Plane> planes, double d_hat)
      : surface_vertices_(std::move(surface_vertices)), planes_(std::move(planes)), d_hat_(d_hat) {}

  /// Rebuilds the active pairs (distance < d_hat) at q, in a fixed order (vertex, then plane).
  void build(const Eigen::VectorXd& q);
  const std::vector<VertexPlanePair>& vertex_plane_pairs() const { return vertex_plane_; }
  bool empty() const { return vertex_plane_.empty(); }

  /// Smallest distance over every candidate pair at q (+infinity without obstacles).
  double min_distance(const Eigen::VectorXd& q) const;
  /// Same, per plane: #planes minima.
  std::vector<double> min_distance_per_plane(const Eigen::VectorXd& q) const;
  /// Largest fraction of the step q0 -> q1 that no pair closes below a tenth of its gap.
  double max_step_size(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const;

  const std::vector<int>& surface_vertices() const { return surface_vertices_; }
  const std::vector<Plane>& planes() const { return planes_; }
  double d_hat() const { return d_hat_; }

 private:
  std::vector<int> surface_vertices_;
  std::vector<Plane> planes_;
  double d_hat_;
  std::vector<VertexPlanePair> vertex_plane_;
};

}  // namespace rbaa
