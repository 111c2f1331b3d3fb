#pragma once
// A demonstration's verdict on one run (issue 17): predicates such as "the ball passes down
// through the hoop" or "the stack stays up", judged on the bodies' paths alone, so that a rigid
// (Bullet) run and a deformable (FEM) run are judged alike. A path is a body's centre of mass and
// rotation over time, sampled wherever the run sampled it.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "rbaa/scene/scene.hpp"

namespace rbaa {

/// One body's motion in one run: N samples of its centre of mass and of its rotation from its
/// initial pose (x(t) = centre(t) + rotation(t) (x0 - centre(0)) for a rigid body).
struct BodyPath {
  std::string name;                          ///< "object" or the scene's bodies[i].name
  std::vector<double> time;                  ///< s
  std::vector<Eigen::Vector3d> centre;       ///< centre of mass (m)
  std::vector<Eigen::Quaterniond> rotation;  ///< from the initial pose
  std::vector<Eigen::Vector3d> velocity;     ///< of the centre of mass (m/s); may be empty
  /// Largest distance of a rest vertex from the rest centre of mass (m): the radius of the
  /// smallest sphere about the centre of mass that holds the body.
  double bounding_radius = 0;
};

/// A body's rest shape: its name (as in BodyPath) and its vertices at t = 0 (world, #V by 3).
struct BodyShape {
  std::string name;
  Eigen::MatrixXd V;
};

/// Largest distance of a vertex (rows of V, #V by 3) from `centre` (m).
double bounding_radius(const Eigen::MatrixXd& V, const Eigen::Vector3d& centre);

/// A predicate's verdict, with the number it turned on and a one-line reason.
struct PredicateOutcome {
  bool holds = false;
  std::string detail;  ///< e.g. "crosses the hoop's plane downwards at 0.052 m from its centre"
};

/// Whether the path's centre of mass crosses the disc of radius `radius` about `centre`, normal
/// `axis` (unit), against `axis` (from axis.(x - centre) > 0 to <= 0 between two samples, the
/// crossing point linearly interpolated), at most radius - path.bounding_radius from the
/// centre: the body's bounding sphere passes through the opening. Crossings along `axis`, and
/// crossings outside that radius, do not count; a counting crossing followed by a crossing back
/// along `axis` within `radius` (a ball that dipped in and rimmed out) is cancelled. The last
/// counting crossing not cancelled decides.
PredicateOutcome through_hoop(const BodyPath& path, const Eigen::Vector3d& centre,
                              const Eigen::Vector3d& axis, double radius);

/// Whether the path's last centre of mass lies in the box [min, max] (faces included); with
/// `stays_below_top`, also that from its first sample inside the box on it never rises above
/// max.z (a body that bounced out over the top and fell back in does not count).
PredicateOutcome inside_box(const BodyPath& path, const Eigen::Vector3d& min,
                            const Eigen::Vector3d& max, bool stays_below_top);

/// Whether at the path's end its initial pose's +z (rotation(T) e_z) lies within max_tilt_deg
/// of world +z and its centre of mass is above min_height (m).
PredicateOutcome stands(const BodyPath& path, double max_tilt_deg, double min_height);

/// The scene's predicate on one run's paths (one per body, found by name). Throws
/// rbaa::InputError when a named body has no path or a path is empty. kNone holds trivially.
PredicateOutcome evaluate_predicate(const PredicateSpec& spec, const std::vector<BodyPath>& paths);

/// The path named `name`; throws rbaa::InputError naming it when there is none.
const BodyPath& find_path(const std::vector<BodyPath>& paths, const std::string& name);

/// One row of the outcome table: a run's verdict and its figure.
struct DemonstrationOutcome {
  std::string run;        ///< e.g. "deformable adversarial"
  std::string simulator;  ///< "rigid" or "deformable"
  std::string object;     ///< "reference", "adversarial" or "soft control"
  bool has_predicate = false;
  PredicateOutcome predicate;
  /// The figure (DemonstrationSpec::figure "angle"): the angle between this run's final
  /// centre-of-mass velocity of figure_body and a reference run's (deg, see
  /// demonstration_outcomes); NaN when none.
  double figure = 0;
};

/// The angle between two vectors (deg; 0 when either is zero), accurate for tiny angles.
double angle_between_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b);

/// The angle between a and b (deg) after projecting both onto the plane normal to `normal`
/// (a - (a.n) n with n = normal / |normal|); with normal zero, the plain angle.
double projected_angle_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                           const Eigen::Vector3d& normal);

/// One run's paths, named for the outcome table; `paths` empty when the run was not made.
struct DemonstrationRun {
  std::string run, simulator, object;  ///< as DemonstrationOutcome's
  std::vector<BodyPath> paths;
};

/// The outcome table: per run that was made, the predicate and the figure: the angle between
/// the centre-of-mass velocity at T (the run's end) of demo.figure_body and that of the rigid
/// reference (or, with figure_against_own_simulator, of the reference run with the same simulator),
/// projected normal to `gravity` with figure_horizontal. A figure whose reference run is missing is
/// NaN.
std::vector<DemonstrationOutcome> demonstration_outcomes(const DemonstrationSpec& demo,
                                                         const std::vector<DemonstrationRun>& runs,
                                                         const Eigen::Vector3d& gravity);

}  // namespace rbaa
