#pragma once
// Conservative continuous collision detection of primitive pairs moving linearly from x0 at t = 0
// to x1 at t = 1: additive CCD (Li, Kaufman and Jiang 2021, "Codimensional Incremental Potential
// Contact", section 5). With L a bound on how fast the pair's distance d(t) can shrink, d(t) >=
// d(t_k) - L (t - t_k), so advancing t_{k+1} = t_k + (d(t_k) - delta) / L never takes d below
// delta. The iterates increase towards the first time t* at which d reaches delta, from below.
//
// L is the largest relative speed of any two points of the two primitives after the pair's mean
// displacement is removed (a rigid translation cannot close a gap): for point-triangle
// |dp| + max_i |dt_i|, for edge-edge max_i |dea_i| + max_j |deb_j|, each a displacement x1 - x0.
//
// The answer is for a line search's max_step_size: the largest step fraction found to keep the
// pair apart, with d(t) >= delta on all of [0, t] (up to the rounding of the distance itself).

#include <Eigen/Core>

namespace rbaa::contact {

struct AdditiveCcdSettings {
  /// xi (m): separation the pair must keep; 0 for plain non-intersection.
  double min_distance = 0.0;
  /// The stop distance is delta = xi + min_gap_ratio (d(0) - xi): how much of the start gap a
  /// step may close (0.1 keeps 10 %, like vertex_plane_ccd's min_ratio). Must be in (0, 1).
  double min_gap_ratio = 0.1;
  /// Stop once d(t) - delta <= tolerance (d(0) - xi): how close to t* the answer must get, as a
  /// fraction of the start gap. Smaller costs more iterations when the approach is oblique.
  double tolerance = 0.01;
  /// Iteration cap; reaching it returns the current (still safe) t.
  int max_iterations = 100000;
  /// First try a separating-plane certificate that the pair stays beyond delta + tolerance
  /// (d(0) - xi) over the whole step (then the answer is 1, as the iteration's would be, at O(1)
  /// cost instead of ~L / d0 iterations). false: the iteration alone (tests compare the two).
  bool plane_certificate = true;
};

struct CcdResult {
  /// A safe step fraction in [0, 1]: 1 when the speed bound or the plane certificate (then
  /// with iterations == 0) proves d >= delta over the whole step, 0 when d(0) <= xi already;
  /// otherwise a t with delta <= d(t) <= delta + tolerance (d(0) - xi) (unless max_iterations
  /// stopped it first) and d >= delta on [0, t].
  double toi = 1.0;
  int iterations = 0;
  /// False when max_iterations stopped the search before the tolerance was met.
  bool converged = true;
};

/// Point p against triangle (t0, t1, t2), each moving x0 -> x1.
CcdResult point_triangle_ccd(const Eigen::Vector3d& p_t0, const Eigen::Vector3d& t0_t0,
                             const Eigen::Vector3d& t1_t0, const Eigen::Vector3d& t2_t0,
                             const Eigen::Vector3d& p_t1, const Eigen::Vector3d& t0_t1,
                             const Eigen::Vector3d& t1_t1, const Eigen::Vector3d& t2_t1,
                             const AdditiveCcdSettings& settings = {});

/// Edge (ea0, ea1) against edge (eb0, eb1), each moving x0 -> x1.
CcdResult edge_edge_ccd(const Eigen::Vector3d& ea0_t0, const Eigen::Vector3d& ea1_t0,
                        const Eigen::Vector3d& eb0_t0, const Eigen::Vector3d& eb1_t0,
                        const Eigen::Vector3d& ea0_t1, const Eigen::Vector3d& ea1_t1,
                        const Eigen::Vector3d& eb0_t1, const Eigen::Vector3d& eb1_t1,
                        const AdditiveCcdSettings& settings = {});

/// The toi alone, for a form's max_step_size.
inline double point_triangle_max_step_size(
    const Eigen::Vector3d& p_t0, const Eigen::Vector3d& t0_t0, const Eigen::Vector3d& t1_t0,
    const Eigen::Vector3d& t2_t0, const Eigen::Vector3d& p_t1, const Eigen::Vector3d& t0_t1,
    const Eigen::Vector3d& t1_t1, const Eigen::Vector3d& t2_t1,
    const AdditiveCcdSettings& settings = {}) {
  return point_triangle_ccd(p_t0, t0_t0, t1_t0, t2_t0, p_t1, t0_t1, t1_t1, t2_t1, settings).toi;
}

inline double edge_edge_max_step_size(const Eigen::Vector3d& ea0_t0, const Eigen::Vector3d& ea1_t0,
                                      const Eigen::Vector3d& eb0_t0, const Eigen::Vector3d& eb1_t0,
                                      const Eigen::Vector3d& ea0_t1, const Eigen::Vector3d& ea1_t1,
                                      const Eigen::Vector3d& eb0_t1, const Eigen::Vector3d& eb1_t1,
                                      const AdditiveCcdSettings& settings = {}) {
  return edge_edge_ccd(ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ea1_t1, eb0_t1, eb1_t1, settings)
      .toi;
}

}  // namespace rbaa::contact
