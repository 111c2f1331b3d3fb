#pragma once
// Rigid-body observables of a deformable trajectory: centre of mass, momenta, the best-fit
// rotation from the rest pose, and the restitution of every bounce.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <limits>
#include <string>
#include <vector>

#include "rbaa/sim/world.hpp"
#include "rbaa/sim/trajectory.hpp"

namespace rbaa {

/// sum_i m_i x_i / sum_i m_i with the vertex masses (#V): exact for the consistent mass too.
/// Throws rbaa::InputError unless q has 3 #V entries (a body's slice, not a longer vector).
Eigen::Vector3d centre_of_mass(const Eigen::VectorXd& q, const Eigen::VectorXd& vertex_masses);

/// Linear momentum sum_i (M v)_i, given the stacked product Mv (3 #V).
Eigen::Vector3d linear_momentum(const Eigen::VectorXd& Mv);

/// Angular momentum about the origin sum_i x_i x (M v)_i.
Eigen::Vector3d angular_momentum(const Eigen::VectorXd& q, const Eigen::VectorXd& Mv);

/// The rotation R minimising sum_i m_i |R (X_i - X_c) - (x_i - x_c)|^2 (mass-weighted Kabsch,
/// centred at the respective centres of mass), as a unit quaternion with w >= 0.
Eigen::Quaterniond best_fit_rotation(const Eigen::VectorXd& rest, const Eigen::VectorXd& q,
                                     const Eigen::VectorXd& vertex_masses);

/// What a contact episode was, and so whether it has a restitution.
enum class BounceKind {
  kBounce,      ///< one plane, normal velocity reversed (in < 0 < out): restitution = -out / in
  kCorner,      ///< two or more planes within one episode: no single restitution
  kNoReversal,  ///< one plane, but the normal velocity did not go from towards it to away
  kUnfinished,  ///< still in contact at the end of the run
};

/// "bounce", "corner", "no_reversal", "unfinished" (report.json's names).
const char* bounce_kind_name(BounceKind kind);

/// One contact episode: a maximal run of positions in which some surface vertex is within d_hat
/// of some plane. Normal velocities are the centre of mass's along each touched plane's normal,
/// at the last position before the episode and after it. A restitution -out / in means a bounce
/// only for a contact with one plane whose normal velocity reversed: in a corner the other
/// plane's push changes the velocity along this one's normal too (a cube tilted into a corner
/// read -0.32 on both planes when each plane was measured alone).
struct Bounce {
  BounceKind kind = BounceKind::kBounce;
  std::vector<int> planes;                  ///< touched during the episode, ascending
  int first_step = 0;                       ///< first position index in contact
  int last_step = 0;                        ///< last position index in contact
  /// Position whose velocity normal_velocity_out reads (settle_steps after the contact, fewer
  /// before a next contact; the last position of an unfinished one).
  int out_step = 0;
  std::vector<double> normal_velocity_in;   ///< per entry of `planes` (m/s)
  std::vector<double> normal_velocity_out;  ///< per entry of `planes` (m/s)
  /// -out / in for kBounce; NaN for every other kind.
  double restitution = std::numeric_limits<double>::quiet_NaN();
  std::string note;  ///< why there is no restitution (empty for kBounce)

  bool complete() const { return kind != BounceKind::kUnfinished; }
};

/// Where one impact ends, the rule find_bounces and eval's first_contact_episodes share. From
/// `first`, a position in contact, it runs through the positions in contact (`visit(k)` is called
/// on each) and on through positions out of contact at which the body still approaches what it
/// touched (`approaching(k)`) to the next run in contact (a tumbling body's next corner: at a fine
/// step its corners are separate runs), until it turns away or the n positions end. Returns one
/// past the last position in contact.
template <class InContact, class Visit, class Approaching>
int impact_end(int first, int n, InContact&& in_contact, Visit&& visit, Approaching&& approaching) {
  int k = first;
  for (;;) {
    for (; k < n && in_contact(k); ++k) visit(k);
    int next = k;
    for (; next < n && !in_contact(next); ++next) {
      if (!approaching(next)) return k;
    }
    if (next >= n) return k;
    k = next;
  }
}

/// Contact episodes of a trajectory, in time order. `distances[k][p]`: minimum distance of the
/// surface to plane p at position k; `com_velocity[k]`: the centre of mass velocity at position
/// k. An episode runs from the first position within d_hat of a plane until the body is out of
/// d_hat moving away from a plane it touched: contacts separated by positions at which it still
/// approaches every plane it touched are one episode (one impact of several corners). The
/// outgoing velocity is read `settle_steps` steps after the episode (fewer if another
/// contact starts), minus the gravity of those steps: BDF-2's velocity needs a few steps to
/// settle after a bounce.
std::vector<Bounce> find_bounces(const std::vector<std::vector<double>>& distances,
                                 const std::vector<Eigen::Vector3d>& com_velocity,
                                 const std::vector<Plane>& planes, double d_hat,
                                 const Eigen::Vector3d& gravity, double time_step,
                                 int settle_steps = 5);

}  // namespace rbaa
