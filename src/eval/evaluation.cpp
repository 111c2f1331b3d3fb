#include "rbaa/eval/evaluation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <ostream>
#include <sstream>

#include "rbaa/error.hpp"
#include "rbaa/mesh/topology.hpp"
#include "rbaa/scene/scene_mesh.hpp"
#include "rbaa/scene/scene_world.hpp"
#include "rbaa/sim/barrier_stiffness.hpp"
#include "rbaa/scene/simulate.hpp"
#include "rbaa/sim/observables.hpp"

namespace rbaa {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double angle_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double na = a.norm(), nb = b.norm();
  if (!(na > 0) || !(nb > 0)) return 0.0;
  // atan2 of |a x b| and a.b stays accurate for tiny angles, unlike acos.
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / M_PI;
}

// A body's path in a rigid run (Bullet's states, on the grid of h). Unnamed, no bounding radius.
BodyPath rigid_body_path(const std::vector<RigidState>& states) {
  BodyPath p;
  for (const RigidState& s : states) {
    p.time.push_back(s.time);
    p.centre.push_back(s.position);
    p.velocity.push_back(s.velocity);
    p.rotation.push_back(s.orientation);
  }
  return p;
}

// A body's path as a run's trace: named for the comparisons, with the run's wall time.
RunTrace trace_from_path(const std::string& name, BodyPath p, double seconds) {
  RunTrace t;
  static_cast<BodyPath&>(t) = std::move(p);
  t.name = name;
  t.seconds = seconds;
  return t;
}

RunTrace trace_from_rigid(const std::string& name, const std::vector<RigidState>& states, double seconds) {
  return trace_from_path(name, rigid_body_path(states), seconds);
}

// Body `body`'s path in a deformable run (the whole mesh for a run of one body), on the grid of
// h: the centre of mass and best-fit rotation of its vertices (weighted by the run's vertex
// masses), its centre-of-mass velocity, its bounding radius from the rest positions. Unnamed.
BodyPath deformable_body_path(const SimulationRun& run, int body) {
  int begin = 0, count = static_cast<int>(run.vertex_masses.size());
  if (!run.bodies.empty()) {
    const Body& b = run.bodies.at(body);
    begin = b.vertex_begin;
    count = b.num_vertices();
  }
  const Eigen::VectorXd m = run.vertex_masses.segment(begin, count);
  const auto part = [&](const Eigen::VectorXd& x) {
    return Eigen::VectorXd(x.segment(3 * begin, 3 * count));
  };
  const Trajectory& traj = run.trajectory;
  const Eigen::VectorXd rest = part(traj.q[0]);
  BodyPath p;
  for (int k : traj.grid_frames()) {  // step by step with the rigid twin
    const Eigen::VectorXd x = part(traj.q[k]);
    p.time.push_back(traj.time(k));
    p.centre.push_back(centre_of_mass(x, m));
    p.velocity.push_back(body_velocity(run, body, k));
    p.rotation.push_back(best_fit_rotation(rest, x, m));
  }
  const Eigen::MatrixXd V =
      Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(rest.data(),
                                                                                  count, 3);
  p.bounding_radius = bounding_radius(V, p.centre.front());
  return p;
}

// The trace of body `body` of a deformable run (0: the object, i > 0: the scene's bodies[i - 1]).
// For the object this is its observables' motion to the bit (simulate.cpp computes them with the
// same masses, grid frames and functions).
RunTrace trace_from_deformable(const std::string& name, const SimulationRun& run, int body = 0) {
  return trace_from_path(name, deformable_body_path(run, body), run.seconds());
}

// Every body's path in a deformable run (the object, then the scene's bodies), for the
// demonstration's predicates.
std::vector<BodyPath> paths_from_deformable(const Scene& scene, const SimulationRun& run) {
  const int bodies = std::max<int>(1, static_cast<int>(run.bodies.size()));
  std::vector<BodyPath> paths;
  for (int i = 0; i < bodies; ++i) {
    paths.push_back(deformable_body_path(run, i));
    paths.back().name = body_name(scene, i);
  }
  return paths;
}

// A deformable run as the evaluation keeps it: the trace of body `traced` and, for a
// demonstration (scene.demonstration.enabled), every body's path, each body's path built once
// (the trace is the traced body's path, renamed after the run).
struct DeformableRunRecord {
  RunTrace trace;
  std::vector<BodyPath> paths;  ///< empty outside a demonstration
};

DeformableRunRecord record_deformable(const std::string& name, const Scene& scene, const SimulationRun& run,
                                      int traced) {
  DeformableRunRecord r;
  if (!scene.demonstration.enabled) {
    r.trace = trace_from_deformable(name, run, traced);
    return r;
  }
  r.paths = paths_from_deformable(scene, run);
  r.trace = trace_from_path(name, r.paths.at(traced), run.seconds());
  return r;
}

// Every body's path in a rigid run, with the bounding radii of the same bodies' deformable paths
// (the same surfaces about the same centres of mass).
std::vector<BodyPath> paths_from_rigid(const std::vector<std::vector<RigidState>>& states,
                                       const std::vector<BodyPath>& shapes) {
  std::vector<BodyPath> paths;
  for (size_t i = 0; i < states.size() && i < shapes.size(); ++i) {
    BodyPath p = rigid_body_path(states[i]);
    p.name = shapes[i].name;
    p.bounding_radius = shapes[i].bounding_radius;
    paths.push_back(std::move(p));
  }
  return paths;
}

// The body evaluation.body names: 0 the object (also when it names none), i > 0 the scene's
// bodies[i - 1].
int evaluated_body(const Scene& scene) {
  if (scene.evaluation_body == scene.object_name) return 0;
  for (size_t i = 0; i < scene.bodies.size(); ++i) {
    if (scene.bodies[i].name == scene.evaluation_body) return static_cast<int>(i) + 1;
  }
  return 0;
}

// The twins of a world's further bodies (bodies[1..]) when its object has `object` materials:
// a copy of the object (SceneWorld::copies) takes them.
std::vector<RigidBody> further_twins(const SceneWorld& world, const MaterialField& object) {
  return rigid_bodies(world.mesh, std::vector<Body>(world.bodies.begin() + 1, world.bodies.end()),
                      world.materials(object).effective_density());
}

// Every body's moments in a deformable run (run.bodies: the object, then the scene's), from the
// run's own stacked mesh and materials.
std::vector<Moments> body_moments(const SimulationRun& run) {
  const Eigen::VectorXd density = run.materials.effective_density();
  std::vector<Moments> out;
  for (const Body& b : run.bodies) {
    TetMesh mesh;
    mesh.V = run.mesh.V.middleRows(b.vertex_begin, b.num_vertices());
    mesh.T = run.mesh.T.middleRows(b.element_begin, b.num_elements()).array() - b.vertex_begin;
    out.push_back(compute_moments(mesh, Eigen::VectorXd(density.segment(b.element_begin, b.num_elements()))));
  }
  return out;
}

// The report's names of contacts: "mesh backboard" (the file's stem, else its index),
// "bodies object-ball" (body 0 the object, i + 1 scene.bodies[i]).
std::string mesh_contact_name(const Scene& scene, int mesh) {
  const std::string stem =
      std::filesystem::path(scene.obstacle_meshes.at(mesh).file).stem().string();
  return "mesh " + (stem.empty() ? std::to_string(mesh) : stem);
}
std::string bodies_contact_name(const Scene& scene, int a, int b) {
  return "bodies " + body_name(scene, a) + "-" + body_name(scene, b);
}
// "plane 0" for the object (as its bounces have always been named), "plane 0 (ball)" for a
// further body's contact with it.
std::string plane_contact_name(const Scene& scene, int body, int plane) {
  const std::string name = "plane " + std::to_string(plane);
  return body == 0 ? name : name + " (" + body_name(scene, body) + ")";
}

}  // namespace

RunComparison compare_runs(const RunTrace& a, const RunTrace& b) {
  RunComparison c;
  c.a = a.name;
  c.b = b.name;
  const size_t n = std::min(a.centre.size(), b.centre.size());
  if (n == 0) return c;
  for (size_t i = 0; i < n; ++i) c.max_position_gap = std::max(c.max_position_gap, (a.centre[i] - b.centre[i]).norm());
  c.position_gap = (a.centre[n - 1] - b.centre[n - 1]).norm();
  c.velocity_angle_deg = angle_deg(a.velocity[n - 1], b.velocity[n - 1]);
  c.orientation_gap_deg = a.rotation[n - 1].angularDistance(b.rotation[n - 1]) * 180.0 / M_PI;
  return c;
}

namespace {

// w_out without the gravity the free sides of a contact gained from t_in to t_out: `free` is 1 for
// a free body against an obstacle or a driven body, 0 for two free bodies (both fall alike), -1
// for a driven body against a free one. Every rebound the calibration reads, the deformable run's
// and the twin's, of planes, meshes and pairs, takes gravity off this way over its whole episode,
// so the two runs' ratios measure the contact alone and agree on what gravity did. (Taking it off
// over the settle steps only, as find_bounces does, read a plane's rebound 0.525 where the same
// drop onto a mesh floor read 0.560, and left the fitted twin flying 2 g h slow.)
Eigen::Vector3d without_gravity(const Eigen::Vector3d& w_out, double free,
                                const Eigen::Vector3d& gravity, double t_in, double t_out) {
  return w_out - free * (t_out - t_in) * gravity;
}

// -(out . n) / (w_in . n): NaN unless the pair approached along n (w_in . n < 0).
double rebound_along(const Eigen::Vector3d& w_in, const Eigen::Vector3d& out,
                     const Eigen::Vector3d& n) {
  const double in = w_in.dot(n);
  if (!(in < 0)) return std::nan("");
  return -out.dot(n) / in;
}

// A free body's rebound off a plane (normal n) across an episode from t_in to t_out.
double plane_rebound(const Eigen::Vector3d& v_in, const Eigen::Vector3d& v_out,
                     const Eigen::Vector3d& n, const Eigen::Vector3d& gravity, double t_in,
                     double t_out) {
  return rebound_along(v_in, without_gravity(v_out, 1.0, gravity, t_in, t_out), n);
}

// The sample a twin's rebound reads its incoming velocity at: the deformable run's (`start`, the
// position before its episode) when the twin's first impact comes at most three samples after
// it, else the sample before that impact. Both runs then take gravity off over the same interval
// from the same free fall, and a matched ratio makes the twin leave with the run's velocity: the
// deformable body enters d_hat a step before Bullet's impulse, and a ratio read a step apart
// differs by about g h (1 + r) / |v_in| (the twin of a ball meeting a mesh floor at 1.2 m/s left
// 1.7 g h fast).
int rebound_start(int start, int first_impact) {
  return start >= 0 && start <= first_impact && first_impact - start <= 3 ? start : first_impact;
}

}  // namespace

double rigid_first_rebound(const std::vector<RigidState>& states, const Plane& plane,
                           const Eigen::Vector3d& gravity,
                           const std::function<bool(int)>& touches_plane, int start) {
  // Without a touch log an impact is a change of the normal velocity by far more than gravity
  // makes in one step (10 |g| h). Bullet's touch log says which steps met the plane, so there an
  // impact is a touched step whose normal velocity changed by more than a small bar, both in all
  // (a body at rest on the plane changes by nothing) and beyond gravity's own change (a contact
  // point Bullet keeps within its margin before the impact acts on nothing): 10 |g| h missed
  // every impact slower than about 5 |g| h (a ball meeting the floor at 0.392 m/s at h = 0.01 s,
  // -0.392 -> +0.402, read "not fitted").
  // A bounce of a non-round body is often several impacts (it rocks onto another corner): the
  // episode runs through the impacts and on while the body still approaches the plane, as in
  // the deformable run (impact_end), or while the next impact is at most three steps away (the
  // deformable body is still within d_hat there: its contact lasts some steps where the twin's
  // is one impulse). The rebound compares the normal velocities before and after the whole
  // episode, gravity taken off over it (without_gravity), as the deformable run's target is.
  const int n = static_cast<int>(states.size()) - 1;  // impact(k) compares states k and k + 1
  const double h = n > 0 ? states[1].time - states[0].time : 0.0;
  const double g_step = gravity.norm() * h, g_normal_step = gravity.dot(plane.normal) * h;
  auto normal_velocity = [&](int k) { return states[k].velocity.dot(plane.normal); };
  auto impact = [&](int k) {
    const double in = normal_velocity(k), out = normal_velocity(k + 1);
    if (!touches_plane) return std::abs(out - in) > 10 * g_step + 1e-9 * std::abs(in);
    const double bar = 1e-2 * g_step + 1e-9 * std::abs(in);
    return touches_plane(k) && std::abs(out - in) > bar && std::abs(out - in - g_normal_step) > bar;
  };
  for (int k = 0; k < n; ++k) {
    if (!(normal_velocity(k) < 0) || !impact(k)) continue;
    int last = k;
    // Approaching at every step since the last impact: a body that turned away and falls back (a
    // slow bounce whose hop is shorter than the three steps) begins another bounce. Kept as the
    // steps are asked for, each read once per impact: every step in (last, checked] approaches,
    // and `turned` is the first after `last` that does not (-1 until one is read).
    int checked = k, turned = -1;
    auto approaching = [&](int j) {
      if (turned >= 0) return j < turned;
      for (; checked < j; ++checked) {
        if (!(normal_velocity(checked + 1) < 0)) {
          turned = checked + 1;
          return false;
        }
      }
      return true;
    };
    auto goes_on = [&](int j) { return j <= last + 3 || approaching(j); };
    auto visit = [&](int j) {
      last = checked = j;
      turned = -1;
    };
    const int end = impact_end(k, n, impact, visit, goes_on);
    int j = end;
    while (j < n && goes_on(j)) ++j;
    if (j >= n) return std::nan("");  // the trace ended within the episode
    const int from = rebound_start(start, k);
    return plane_rebound(states[from].velocity, states[end].velocity, plane.normal, gravity,
                         states[from].time, states[end].time);
  }
  return std::nan("");
}

namespace {

// Body `body`'s first rebound off plane `plane` in a twin's run (rigid_first_rebound on its
// states), an impact confirmed by Bullet's touches of that (body, plane) pair: impact k changes
// the velocity from sample k to k + 1, so the touches logged at sample k + 1 (1 .. the last).
double rigid_plane_rebound(const std::vector<std::vector<RigidState>>& states,
                           const std::vector<RigidTouch>& touches, int body, int plane,
                           const Scene& scene, int start) {
  const RigidContactSide first{RigidContactSide::Kind::kBody, body};
  const RigidContactSide second{RigidContactSide::Kind::kPlane, plane};
  std::vector<char> touched(states.front().size(), 0);
  for (const RigidTouch& t : touches) {
    if (t.first == first && t.second == second) touched.at(t.sample) = 1;
  }
  return rigid_first_rebound(
      states.at(body), scene.planes[plane], scene.gravity,
      [&](int k) { return touched.at(k + 1) != 0; }, start);
}

}  // namespace

const char* restitution_contact_name(RestitutionContact contact) {
  switch (contact) {
    case RestitutionContact::kPlane:
      return "plane";
    case RestitutionContact::kMesh:
      return "mesh";
    case RestitutionContact::kBodies:
      return "bodies";
  }
  return "?";
}

namespace {

// Every restitution e in [0, 1] with rebound(e) = target to the tolerance, into c.roots, and
// the one `closeness(e)` (smaller is closer) picks, else the nearest to target. Above 1 Bullet's
// restitution adds energy at every contact with that obstacle, later ones too, so it is searched
// (up to 3) only for a rebound above 1, which gained energy in the run itself (a driven body's
// face springing back). The twin's rebound is piecewise smooth in e: it jumps where the body,
// leaving its first corner a little faster or slower, meets another corner or none. So a scan
// brackets every change of sign of f = rebound - target on a grid (0.1 apart to 1, 0.25 beyond,
// and the target itself: exact for a sphere), false position (Illinois) closes each bracket, and
// a bracket that closes on a jump instead of a root is dropped. With no root, c stays
// uncalibrated at the e with the least |f| (restitution 1 if the twin never meets the contact:
// rebound NaN everywhere). The callers count their rigid runs in c.iterations.
template <class Rebound>
void fit_restitution(Rebound&& rebound, double target, double tolerance,
                     const std::function<double(double)>& closeness, RestitutionCalibration& c) {
  c.deformable_rebound = target;
  const double close_enough = tolerance * std::abs(target);
  std::vector<double> grid;
  for (int i = 0; i <= 10; ++i) grid.push_back(0.1 * i);
  const double top = target > 1 ? 3.0 : 1.0;
  for (int i = 1; 1.0 + 0.25 * i <= top; ++i) grid.push_back(1.0 + 0.25 * i);
  if (target > 0 && target < top) grid.push_back(target);
  std::sort(grid.begin(), grid.end());
  grid.erase(std::unique(grid.begin(), grid.end()), grid.end());

  double best_e = 1.0, best_f = std::nan("");
  auto f = [&](double e) {
    const double value = rebound(e) - target;
    if (!std::isnan(value) && !(std::abs(value) >= std::abs(best_f))) {
      best_e = e;
      best_f = value;
    }
    return value;
  };
  std::vector<std::pair<double, double>> roots;  // (e, f)
  std::vector<double> values;
  for (double e : grid) values.push_back(f(e));
  for (size_t i = 0; i < grid.size(); ++i) {
    if (std::abs(values[i]) <= close_enough) roots.push_back({grid[i], values[i]});
  }
  for (size_t i = 0; i + 1 < grid.size(); ++i) {
    double a = grid[i], fa = values[i], b = grid[i + 1], fb = values[i + 1];
    if (std::isnan(fa) || std::isnan(fb) || std::abs(fa) <= close_enough ||
        std::abs(fb) <= close_enough || !((fa < 0) != (fb < 0))) {
      continue;
    }
    for (int it = 0; it < 40 && std::abs(b - a) > 1e-9; ++it) {
      const double e = b - fb * (b - a) / (fb - fa);
      const double fe = f(e);
      if (std::isnan(fe)) break;
      if (std::abs(fe) <= close_enough) {
        roots.push_back({e, fe});
        break;
      }
      if ((fe < 0) != (fb < 0)) {
        a = b;
        fa = fb;
      } else {
        fa *= 0.5;
      }
      b = e;
      fb = fe;
    }
  }
  std::sort(roots.begin(), roots.end());
  for (const auto& r : roots) c.roots.push_back(r.first);
  if (roots.empty()) {
    if (std::isnan(best_f)) return;  // the rigid body never meets that contact
    c.restitution = best_e;
    c.rigid_rebound = best_f + target;
    return;
  }
  size_t pick = 0;
  double pick_score = INFINITY;
  for (size_t i = 0; i < roots.size(); ++i) {
    const double score = roots.size() > 1 && closeness ? closeness(roots[i].first)
                                                       : std::abs(roots[i].first - target);
    if (score < pick_score) {
      pick = i;
      pick_score = score;
    }
  }
  c.calibrated = true;
  c.restitution = roots[pick].first;
  c.rigid_rebound = roots[pick].second + target;
}

}  // namespace

RestitutionCalibration calibrate_restitution(const RigidMassProperties& mass,
                                             const RigidShape& shape, const Scene& scene,
                                             RigidSettings settings, double duration, int plane,
                                             double target, double tolerance,
                                             const std::vector<RigidBody>& further,
                                             const TwinCloseness& closeness, int target_start) {
  RestitutionCalibration c;
  c.contact = RestitutionContact::kPlane;
  c.plane = plane;
  c.body_a = 0;
  c.name = plane_contact_name(scene, 0, plane);
  if (settings.plane_restitution.size() < scene.planes.size()) settings.plane_restitution.resize(scene.planes.size(), 1.0);
  // The episode starts at an impact with this plane, Bullet's own contact (RigidTouch), not at a
  // blow from another body or obstacle that the object then carries down onto the plane.
  auto rebound = [&](double e) {
    settings.plane_restitution[plane] = e;
    ++c.iterations;
    std::vector<RigidTouch> touches;
    const auto states =
        simulate_rigid_bodies(mass, shape, scene, settings, duration, further, &touches);
    return rigid_plane_rebound(states, touches, 0, plane, scene, target_start);
  };
  std::function<double(double)> twin_closeness;
  if (closeness) {
    twin_closeness = [&](double e) {
      settings.plane_restitution[plane] = e;
      ++c.iterations;
      return closeness(simulate_rigid_bodies(mass, shape, scene, settings, duration, further));
    };
  }
  fit_restitution(rebound, target, tolerance, twin_closeness, c);
  return c;
}

namespace {

// How a contact episode's pair is seen by both runs: which sides are free bodies (they fall under
// gravity) and, for a driven side, the material point whose drive velocity stands for its
// velocity (the episode's contact point carried back to t = 0 by the drive).
struct EpisodeSides {
  bool body_free = true, other_free = false;
  const PrescribedMotion* body_drive = nullptr;
  const PrescribedMotion* other_drive = nullptr;
  Eigen::Vector3d material_point = Eigen::Vector3d::Zero();  // rest position (drive's t = 0)
};

// x0 with drive.position(x0, t) = x: x0 = centre + R(t)^T (x - centre - t velocity).
Eigen::Vector3d drive_rest_point(const PrescribedMotion& drive, const Eigen::Vector3d& x, double t) {
  return drive.centre + drive.rotation(t).transpose() * (x - drive.centre - t * drive.velocity);
}

EpisodeSides episode_sides(const std::vector<Body>& bodies, const ContactEpisode& e, double t) {
  EpisodeSides s;
  auto driven = [&](int b) -> const PrescribedMotion* {
    return b < static_cast<int>(bodies.size()) && bodies[b].is_driven() ? &bodies[b].drive : nullptr;
  };
  s.body_drive = driven(e.body);
  s.body_free = s.body_drive == nullptr;
  if (e.kind == ContactEpisode::Kind::kBodies) {
    s.other_drive = driven(e.other);
    s.other_free = s.other_drive == nullptr;
  }
  const PrescribedMotion* drive = s.body_drive ? s.body_drive : s.other_drive;
  if (drive) s.material_point = drive_rest_point(*drive, e.point, t);
  return s;
}

// -(w_out . n) / (w_in . n) along the direction n of the episode's impulse, w_out - w_in, with
// the gravity the free sides gained between t_in and t_out taken off w_out; NaN unless the pair
// approached along it (w_in . n < 0). Frictionless, n is the net contact normal, which on a
// faceted surface is not the closest pair's (measured 8 deg apart for two 300-tet balls, whose
// rigid twins are spheres).
double episode_rebound(const Eigen::Vector3d& w_in, const Eigen::Vector3d& w_out,
                       const EpisodeSides& s, const Eigen::Vector3d& gravity, double t_in,
                       double t_out) {
  const double free = (s.body_free ? 1.0 : 0.0) - (s.other_free ? 1.0 : 0.0);
  const Eigen::Vector3d out = without_gravity(w_out, free, gravity, t_in, t_out);
  const Eigen::Vector3d impulse = out - w_in;
  if (!(impulse.norm() > 0)) return std::nan("");
  return rebound_along(w_in, out, impulse.normalized());
}

// The first episode of a pair in a rigid run's touches: the samples from its first touch to its
// last with gaps of at most three samples bridged (a non-round body rocks onto another corner a
// few steps later), as rigid_first_rebound does; {-1, -1} if the pair never touched or still
// touches within three samples of the end.
std::pair<int, int> rigid_episode(const std::vector<RigidTouch>& touches, RigidContactSide first,
                                  RigidContactSide second, int num_samples) {
  std::vector<int> samples;
  for (const RigidTouch& t : touches) {
    if (t.first == first && t.second == second) samples.push_back(t.sample);
  }
  if (samples.empty()) return {-1, -1};
  int last = samples[0];
  for (size_t i = 1; i < samples.size() && samples[i] <= last + 4; ++i) last = samples[i];
  if (last + 4 >= num_samples) return {-1, -1};
  return {samples[0], last};
}

}  // namespace

RestitutionCalibration calibrate_contact_restitution(
    const SimulationRun& run, const ContactEpisode& episode, const RigidMassProperties& mass,
    const RigidShape& shape, const Scene& scene, RigidSettings settings, double duration,
    double tolerance, const std::vector<RigidBody>& further, const TwinCloseness& closeness) {
  RestitutionCalibration c;
  const bool mesh = episode.kind == ContactEpisode::Kind::kMesh;
  const bool plane = episode.kind == ContactEpisode::Kind::kPlane;
  const bool obstacle = mesh || plane;  // `other` is no body
  const int num_bodies = 1 + static_cast<int>(further.size());
  const int num_obstacles =
      static_cast<int>(mesh ? scene.obstacle_meshes.size() : scene.planes.size());
  if (episode.body < 0 || episode.body >= num_bodies ||
      (obstacle ? episode.other < 0 || episode.other >= num_obstacles
                : episode.other <= episode.body || episode.other >= num_bodies)) {
    throw InputError(scene.source +
                     ": a contact episode names a body, mesh or plane the scene has not");
  }
  c.contact = mesh    ? RestitutionContact::kMesh
              : plane ? RestitutionContact::kPlane
                      : RestitutionContact::kBodies;
  c.body_a = episode.body;
  if (mesh) {
    c.mesh = episode.other;
    c.name = mesh_contact_name(scene, episode.other);
  } else if (plane) {
    c.plane = episode.other;
    c.name = plane_contact_name(scene, episode.body, episode.other);
  } else {
    c.body_b = episode.other;
    c.name = bodies_contact_name(scene, episode.body, episode.other);
  }
  const double h = scene.time_step;
  c.time = episode.first_step * h;
  c.deformable_rebound = std::nan("");

  std::vector<Body> bodies = run.bodies;
  const EpisodeSides sides = episode_sides(bodies, episode, c.time);
  if (!sides.body_free && !sides.other_free) return c;  // two driven sides: no impulse to fit

  // The run's rebound: centre-of-mass velocities of the free sides from its trajectory. An
  // episode indexes the grid of h; with contact-resolving steps the trajectory also holds the
  // sub-steps between, so grid position k is frame grid[k].
  const std::vector<int> grid = run.trajectory.grid_frames();
  auto deformable_velocity = [&](int b, const PrescribedMotion* drive, int k) -> Eigen::Vector3d {
    const double t = run.trajectory.time(grid.at(k));
    if (drive) return drive->point_velocity(sides.material_point, t);
    if (bodies.empty()) return run.observables.at(k).com_velocity;
    return body_velocity(run, b, grid.at(k));
  };
  auto relative = [&](auto&& velocity, int k) -> Eigen::Vector3d {
    Eigen::Vector3d w = velocity(episode.body, sides.body_drive, k);
    if (!obstacle) w -= velocity(episode.other, sides.other_drive, k);
    return w;
  };
  if (!episode.complete) return c;
  // A plane's rebound is along its normal, as the object's bounces are (a frictional impulse is
  // not normal to it); a mesh's and a pair's along the episode's impulse.
  auto rebound_of = [&](const Eigen::Vector3d& w_in, const Eigen::Vector3d& w_out, double t_in,
                        double t_out) {
    return plane ? plane_rebound(w_in, w_out, scene.planes[episode.other].normal, scene.gravity,
                                 t_in, t_out)
                 : episode_rebound(w_in, w_out, sides, scene.gravity, t_in, t_out);
  };
  const int k_in = episode.first_step - 1, k_out = episode.out_step;
  const double target =
      rebound_of(relative(deformable_velocity, k_in), relative(deformable_velocity, k_out),
                 run.trajectory.time(grid.at(k_in)), run.trajectory.time(grid.at(k_out)));
  c.deformable_rebound = target;
  if (!(target > 0)) return c;  // no reversal: nothing a restitution reproduces

  const RigidContactSide first{RigidContactSide::Kind::kBody, episode.body};
  const RigidContactSide second{mesh    ? RigidContactSide::Kind::kMesh
                                : plane ? RigidContactSide::Kind::kPlane
                                        : RigidContactSide::Kind::kBody,
                                episode.other};
  if (mesh) {
    if (settings.mesh_restitution.size() < scene.obstacle_meshes.size()) {
      settings.mesh_restitution.resize(scene.obstacle_meshes.size(), 1.0);
    }
  } else if (plane) {
    auto& named = settings.body_plane_restitution;
    named.erase(std::remove_if(named.begin(), named.end(),
                               [&](const BodyPlaneRestitution& p) {
                                 return p.body == episode.body && p.plane == episode.other;
                               }),
                named.end());
    named.push_back({episode.body, episode.other, 1.0});
  } else {
    auto& pairs = settings.pair_restitution;
    pairs.erase(std::remove_if(pairs.begin(), pairs.end(),
                               [&](const BodyPairRestitution& p) {
                                 return std::minmax(p.a, p.b) ==
                                        std::minmax(episode.body, episode.other);
                               }),
                pairs.end());
    pairs.push_back({episode.body, episode.other, 1.0});
  }
  auto set_restitution = [&](double e) {
    if (mesh) {
      settings.mesh_restitution[episode.other] = e;
    } else if (plane) {
      settings.body_plane_restitution.back().restitution = e;
    } else {
      settings.pair_restitution.back().restitution = e;
    }
    ++c.iterations;
  };
  auto rebound = [&](double e) {
    set_restitution(e);
    std::vector<RigidTouch> touches;
    const auto states =
        simulate_rigid_bodies(mass, shape, scene, settings, duration, further, &touches);
    if (plane) {
      // As the object's planes: the body's own first bounce off it, rocking corners and all.
      return rigid_plane_rebound(states, touches, episode.body, episode.other, scene, k_in);
    }
    const auto [n_first, n_last] =
        rigid_episode(touches, first, second, static_cast<int>(states.front().size()));
    if (n_first < 1) return std::nan("");
    auto rigid_velocity = [&](int b, const PrescribedMotion* drive, int k) -> Eigen::Vector3d {
      if (drive) return drive->point_velocity(sides.material_point, states[b][k].time);
      return states[b][k].velocity;
    };
    const int from = rebound_start(k_in, n_first - 1);
    return episode_rebound(relative(rigid_velocity, from), relative(rigid_velocity, n_last), sides,
                           scene.gravity, states[0][from].time, states[0][n_last].time);
  };
  std::function<double(double)> twin_closeness;
  if (closeness) {
    twin_closeness = [&](double e) {
      set_restitution(e);
      return closeness(simulate_rigid_bodies(mass, shape, scene, settings, duration, further));
    };
  }
  fit_restitution(rebound, target, tolerance, twin_closeness, c);
  return c;
}

TwinCloseness twin_closeness(const SimulationRun& run, int first, int last) {
  return [&run, first, last](const std::vector<std::vector<RigidState>>& states) {
    const std::vector<StepObservables>& seen = run.observables;
    if (seen.empty()) return 0.0;
    // The object and the further bodies whose centres the run's observables hold.
    const size_t tracked = std::min(states.size(), 1 + seen.front().body_centres.size());
    double gap = 0;
    for (size_t b = 0; b < tracked; ++b) {
      const int stop = std::min(
          {last, static_cast<int>(states[b].size()) - 1, static_cast<int>(seen.size()) - 1});
      for (int k = std::max(first, 0); k <= stop; ++k) {
        const Eigen::Vector3d& centre =
            b == 0 ? seen[k].centre_of_mass : seen[k].body_centres[b - 1];
        gap = std::max(gap, (states[b][k].position - centre).norm());
      }
    }
    return gap;
  };
}

namespace {

// The object's rebound off `plane` in bounce b of a deformable run: its centre-of-mass velocity
// before the contact and where find_bounces reads it after (b.out_step), gravity taken off over
// the whole episode (without_gravity), as rigid_first_rebound does on the twin; NaN unless it
// approached the plane.
double object_rebound(const SimulationRun& run, const Bounce& b, const Plane& plane,
                      const Eigen::Vector3d& gravity) {
  const StepObservables& in = run.observables.at(std::max(0, b.first_step - 1));
  const StepObservables& out = run.observables.at(b.out_step);
  return plane_rebound(in.com_velocity, out.com_velocity, plane.normal, gravity, in.time, out.time);
}

// Fits each plane's restitution (rigid.plane_restitution, reset to 1 first) to the object's first
// rebound off it in a deformable run, each further body's against each plane it touches
// (rigid.body_plane_restitution, reset to none) to that body's first episode with the plane, and
// each obstacle mesh's and pair of bodies' (rigid.mesh_restitution and rigid.pair_restitution,
// reset to 1 and none) to the run's first episode with it, in the order of the contacts, so that
// the rigid twin starts every contact as the run did. Bullet gets each (body, plane) pair's own
// value: the object's is the plane's restitution (times the body's 1), a further body's an entry
// of body_plane_restitution, which overrides that product for its contact points; one plane met
// by bodies with different rebounds thus keeps each body's (the cube stack's ground met by the
// bottom cube alone was left at 1, elastic, and the resting stack fell). A corner episode has
// no restitution, but the rigid twin meets the same corner: its rebound ratio along each touched
// plane's normal across the episode is what rigid_first_rebound measures on the twin, so that
// ratio is the target (when the normal velocity reversed). A plane the object touches without a
// rebound to fit is listed, not fitted. A scene with one body and no meshes has only planes.
std::vector<RestitutionCalibration> calibrate_to_run(const SimulationRun& run,
                                                     const RigidMassProperties& mass,
                                                     const RigidShape& shape, const Scene& scene,
                                                     const std::vector<RigidBody>& further,
                                                     RigidSettings& rigid, double tolerance) {
  std::vector<RestitutionCalibration> calibrations;
  rigid.plane_restitution.assign(scene.planes.size(), 1.0);
  rigid.mesh_restitution.assign(scene.obstacle_meshes.size(), 1.0);
  rigid.pair_restitution.clear();
  rigid.body_plane_restitution.clear();
  std::vector<ContactEpisode> episodes;
  if (!scene.obstacle_meshes.empty() || !further.empty()) {
    episodes = first_contact_episodes(run, scene.obstacle_meshes, scene.planes, scene.d_hat);
    // The object's planes are its bounces' (corners, later rebounds).
    episodes.erase(std::remove_if(episodes.begin(), episodes.end(),
                                  [](const ContactEpisode& e) {
                                    return e.kind == ContactEpisode::Kind::kPlane && e.body == 0;
                                  }),
                   episodes.end());
  }
  // Every contact in time order: the planes' in the order of the bounces (as before), the
  // episodes' merged in by their first step.
  struct Contact {
    int step;
    const Bounce* bounce;  // with `plane` its entry; null for an episode
    size_t plane;
    const ContactEpisode* episode;
  };
  std::vector<Contact> contacts;
  for (const Bounce& b : run.bounces) {
    if (b.kind != BounceKind::kBounce && b.kind != BounceKind::kCorner) continue;
    for (size_t i = 0; i < b.planes.size(); ++i) contacts.push_back({b.first_step, &b, i, nullptr});
  }
  for (const ContactEpisode& e : episodes) contacts.push_back({e.first_step, nullptr, 0, &e});
  std::stable_sort(contacts.begin(), contacts.end(),
                   [](const Contact& x, const Contact& y) { return x.step < y.step; });
  // Where several restitutions give a contact's rebound, the twin that follows the run closest
  // (every body's centre of mass, at most; the run's observables hold them per grid position)
  // from the contact until the next contact after it begins (whose restitution is not yet
  // fitted) is kept.
  auto closeness_over = [&](int first, int own_end) -> TwinCloseness {
    int end = std::numeric_limits<int>::max();
    for (const Contact& later : contacts) {
      if (later.step > own_end) end = std::min(end, later.step);
    }
    return twin_closeness(run, first, end);
  };
  std::vector<size_t> plane_own;  // further bodies' plane contacts left at the plane's own value
  for (const Contact& contact : contacts) {
    if (contact.episode) {
      const ContactEpisode& e = *contact.episode;
      RestitutionCalibration c = calibrate_contact_restitution(
          run, e, mass, shape, scene, rigid, scene.duration, tolerance, further,
          closeness_over(e.first_step, e.out_step));
      if (c.contact == RestitutionContact::kMesh) {
        rigid.mesh_restitution[c.mesh] = c.restitution;
      } else if (c.contact == RestitutionContact::kPlane) {
        // Only a fit, or the nearest rebound the twin reached, overrides the plane's own value
        // for this body: an episode with nothing to fit (unclean, unfinished, no reversal, a
        // driven body) leaves it the plane's restitution, not 1 (review of 8d8355f).
        if (c.calibrated || std::isfinite(c.rigid_rebound)) {
          rigid.body_plane_restitution.push_back({c.body_a, c.plane, c.restitution});
        } else {
          plane_own.push_back(calibrations.size());
        }
      } else {
        rigid.pair_restitution.push_back({c.body_a, c.body_b, c.restitution});
      }
      calibrations.push_back(c);
      continue;
    }
    const Bounce& b = *contact.bounce;
    const int plane = b.planes[contact.plane];
    const double rebound = object_rebound(run, b, scene.planes[plane], scene.gravity);
    if (!(rebound > 0)) continue;
    bool seen = false;
    for (auto& c : calibrations) {
      if (c.contact == RestitutionContact::kPlane && c.body_a == 0 && c.plane == plane) {
        if (b.kind == BounceKind::kBounce) c.later_deformable_rebounds.push_back(rebound);
        seen = true;
      }
    }
    if (seen) continue;
    RestitutionCalibration c = calibrate_restitution(
        mass, shape, scene, rigid, scene.duration, plane, rebound, tolerance, further,
        closeness_over(b.first_step, b.last_step), std::max(0, b.first_step - 1));
    c.time = b.first_step * scene.time_step;
    rigid.plane_restitution[plane] = c.restitution;
    calibrations.push_back(c);
  }
  // Those report what the twin gives them: the body's restitution times the plane's, as the
  // object's bounces left it (not 1 unless that is what the twin uses).
  for (const size_t i : plane_own) {
    RestitutionCalibration& c = calibrations[i];
    c.restitution = rigid.restitution * rigid.plane_restitution.at(c.plane);
  }
  // Planes the object touched with no rebound to fit (no reversal, an unfinished contact), each at
  // its first contact: their restitution stays 1, and the report says so.
  for (const Bounce& b : run.bounces) {
    for (const int plane : b.planes) {
      const bool listed = std::any_of(calibrations.begin(), calibrations.end(), [&](const auto& c) {
        return c.contact == RestitutionContact::kPlane && c.body_a == 0 && c.plane == plane;
      });
      if (listed) continue;
      RestitutionCalibration c;
      c.contact = RestitutionContact::kPlane;
      c.plane = plane;
      c.body_a = 0;
      c.name = plane_contact_name(scene, 0, plane);
      c.time = b.first_step * scene.time_step;
      c.deformable_rebound =
          b.complete() ? object_rebound(run, b, scene.planes[plane], scene.gravity) : std::nan("");
      calibrations.push_back(c);
    }
  }
  return calibrations;
}

double path_length(const RunTrace& t) {
  double length = 0;
  for (size_t i = 1; i < t.centre.size(); ++i) length += (t.centre[i] - t.centre[i - 1]).norm();
  return length;
}

// The share of a run's path that its twin does not explain: gap / path length, the path counted
// at least as long as the body's bounding radius. A body that hardly moves would otherwise divide
// the twins' own resolution by round-off: a ball at rest, path 4.2e-18 m, twin 3.7e-10 m away
// (its centre on a grid of 2^-24 of its radius of gyration) read 8.9e7, i.e. 8.9e9 %.
double unexplained_share(double gap, double path, const RunTrace& t) {
  const double length = std::max(path, t.bounding_radius);
  return length > 0 ? gap / length : 0.0;
}

// A deformable run against the rigid twin calibrated to it.
OwnTwin own_twin(const SimulationRun& run, const RunTrace& trace, const std::string& name,
                 const RigidMassProperties& mass, const RigidShape& shape, const Scene& scene,
                 const std::vector<RigidBody>& further, RigidSettings rigid, double tolerance) {
  OwnTwin t;
  rigid.margin = std::min(rigid.margin, scene.d_hat);
  t.calibrations = calibrate_to_run(run, mass, shape, scene, further, rigid, tolerance);
  const auto start = std::chrono::steady_clock::now();
  t.rigid = trace_from_rigid(
      name, simulate_rigid(mass, shape, scene, rigid, scene.duration, further, evaluated_body(scene)),
      seconds_since(start));
  t.gap = compare_runs(trace, t.rigid);
  t.path_length = path_length(trace);
  t.unexplained = unexplained_share(t.gap.max_position_gap, t.path_length, trace);
  return t;
}

// The stiff baseline at one time step, the rigid reference calibrated to it, and how far the two
// stray apart.
struct BaselineAtStep {
  BaselineTrial trial;
  RunTrace baseline, rigid_reference;
  std::vector<RestitutionCalibration> calibrations;
  RigidSettings rigid;
  double rigid_internal_step = 0;
  std::vector<BodyPath> baseline_paths, rigid_paths;  ///< every body's, for a demonstration
  std::vector<Moments> body_moments;                 ///< the baseline's, every body's
};

BaselineAtStep run_baseline(const Scene& scene, const TetMesh& mesh, const MaterialField& materials,
                            const SimulationOptions& sim_options, const RigidMassProperties& mass,
                            const RigidShape& shape, const std::vector<RigidBody>& further,
                            RigidSettings rigid, double calibration_tolerance) {
  BaselineAtStep out;
  const auto start = std::chrono::steady_clock::now();
  const SimulationRun baseline = run_simulation(scene, mesh, materials, sim_options);
  const int traced = evaluated_body(scene);
  DeformableRunRecord record = record_deformable("deformable reference", scene, baseline, traced);
  out.baseline = std::move(record.trace);
  out.baseline_paths = std::move(record.paths);
  out.body_moments = body_moments(baseline);

  rigid.margin = std::min(rigid.margin, scene.d_hat);
  const int substeps = static_cast<int>(std::ceil(scene.time_step / rigid.internal_step - 1e-9));
  out.rigid_internal_step = scene.time_step / substeps;
  out.calibrations = calibrate_to_run(baseline, mass, shape, scene, further, rigid, calibration_tolerance);
  out.rigid = rigid;

  const auto rigid_start = std::chrono::steady_clock::now();
  const auto rigid_bodies_states =
      simulate_rigid_bodies(mass, shape, scene, rigid, scene.duration, further);
  out.rigid_reference = trace_from_rigid("rigid reference", rigid_bodies_states.at(traced),
                                         seconds_since(rigid_start));
  if (scene.demonstration.enabled) out.rigid_paths = paths_from_rigid(rigid_bodies_states, out.baseline_paths);
  const RunComparison gap = compare_runs(out.baseline, out.rigid_reference);
  out.trial.time_step = scene.time_step;
  out.trial.path_length = path_length(out.baseline);
  out.trial.disagreement = unexplained_share(gap.max_position_gap, out.trial.path_length, out.baseline);
  out.trial.seconds = seconds_since(start);
  return out;
}

// What the twins' Bullet world gives each plane, obstacle mesh and pair of its `num_bodies` bodies:
// asked of the world rigid_world builds, so that the report says what the twin used.
std::vector<TwinFriction> twin_friction(const Scene& scene, int num_bodies) {
  const RigidWorld world = rigid_world(scene, std::vector<RigidBody>(num_bodies));
  using Side = RigidContactSide;
  const Side object{Side::Kind::kBody, 0};
  std::vector<TwinFriction> out;
  for (int i = 0; i < static_cast<int>(world.planes.size()); ++i) {
    TwinFriction f{RestitutionContact::kPlane, "plane " + std::to_string(i)};
    f.plane = i;
    f.friction = rigid_friction(world, object, {Side::Kind::kPlane, i});
    out.push_back(f);
  }
  for (int i = 0; i < static_cast<int>(world.obstacle_meshes.size()); ++i) {
    TwinFriction f{RestitutionContact::kMesh, mesh_contact_name(scene, i)};
    f.mesh = i;
    f.friction = rigid_friction(world, object, {Side::Kind::kMesh, i});
    out.push_back(f);
  }
  for (int a = 0; a < num_bodies; ++a) {
    for (int b = a + 1; b < num_bodies; ++b) {
      TwinFriction f{RestitutionContact::kBodies, bodies_contact_name(scene, a, b)};
      f.body_a = a;
      f.body_b = b;
      f.friction = rigid_friction(world, {Side::Kind::kBody, a}, {Side::Kind::kBody, b});
      out.push_back(f);
    }
  }
  return out;
}

}  // namespace

Evaluation evaluate(const Scene& scene_given, const TetMesh& reference_mesh,
                    const TetMesh& adversarial_as_given, const MaterialField& adversarial_materials,
                    const EvaluationOptions& options) {
  // demonstration.object_copies: those bodies are copies of each run's object (make_world).
  const Scene scene_in = with_object_copies(scene_given);
  // The adversarial object takes the object's place; an attack on another body made a design
  // for that body: the caller puts it in the object's place first (swap_object).
  if (scene_in.attack_body != scene_in.object_name) {
    throw InputError(scene_in.source + ": key 'attack.body': the attacked body '" +
                     scene_in.attack_body + "' is not the object '" + scene_in.object_name +
                     "' (evaluate the scene swap_object(scene, attack.body) gives)");
  }
  validate_material_field(adversarial_materials, adversarial_as_given.num_tets(),
                          "adversarial materials");
  const TetMesh adversarial_moved =
      adversarial_in_scene(scene_in, reference_mesh, adversarial_as_given, "adversarial mesh");
  // object.position is the centre of mass: an object whose materials put it elsewhere than the
  // reference's centroid starts translated (an attack's object has the reference's moments, so
  // the translation is round-off).
  const TetMesh adversarial_mesh = place_centre_of_mass(
      scene_in, adversarial_moved, adversarial_materials.effective_density(), "adversarial mesh");
  Evaluation ev;
  Scene scene = scene_in;
  ev.attack_time_step = scene_in.time_step;
  // An explicit step (the command line's, else the config's) is used as it is; "auto" searches
  // from the attack's step down by factors of 4.
  const bool search = options.time_step > 0 ? false : options.search_time_step || scene_in.evaluation_search_step;
  const double first_step = options.time_step > 0                  ? options.time_step
                            : search                                ? scene_in.time_step
                            : scene_in.evaluation_time_step > 0     ? scene_in.evaluation_time_step
                                                                    : scene_in.time_step;
  ev.duration = options.duration > 0 ? options.duration
                : scene_in.evaluation_duration > 0 ? scene_in.evaluation_duration
                                                   : 4.0 * scene_in.duration;
  if (ev.duration < first_step) {
    std::ostringstream msg;
    msg << "evaluation: duration " << ev.duration << " s is shorter than one time step (" << first_step << " s)";
    throw InputError(msg.str());
  }
  scene.duration = ev.duration;
  ev.baseline_tolerance = scene_in.evaluation_baseline_tolerance;

  const MaterialField reference_materials = MaterialField::uniform(
      reference_mesh.num_tets(), scene.reference_Y, scene.reference_nu, scene.reference_rho, 1.0);
  ev.reference_moments = compute_moments(reference_mesh, reference_materials.effective_density());
  ev.adversarial_moments = compute_moments(adversarial_mesh, adversarial_materials.effective_density());
  ev.kappa = scene_barrier_stiffness(scene_in, reference_mesh);  // independent of h (SPEC section 2)

  // Rigid twins, each from its own mesh and materials.
  const RigidMassProperties ref_mass = rigid_mass_properties(ev.reference_moments);
  const RigidMassProperties adv_mass = rigid_mass_properties(ev.adversarial_moments);
  const RigidShape ref_shape = rigid_shape_from_surface(reference_mesh);
  const RigidShape adv_shape = rigid_shape_from_surface(adversarial_mesh);
  ev.rigid_shape = ref_shape.describe();
  if (ref_shape.kind == RigidShapeKind::kConvexHull) {
    ev.rigid_shape += " (exact against planes: a plane first touches a body at a hull vertex)";
  }
  // The scene's further bodies move in the twins as in the deformable runs (which stack them after
  // the object); the comparison is of one body alone: the object, or evaluation.body (the bat's
  // struck ball).
  // Copies of the object (demonstration.object_copies) are each run's object: the adversarial
  // twins' copies are built from the adversarial object's mesh and materials. The soft control's
  // are the reference's (its twin reads densities only, and its density is the reference's).
  const SceneWorld world = make_world(scene_in, reference_mesh);
  const std::vector<RigidBody> further = further_twins(world, reference_materials);
  const std::vector<RigidBody> adversarial_further =
      world.copies.empty() ? further
                           : further_twins(make_world(scene_in, adversarial_mesh), adversarial_materials);

  // Deformable runs with the reference scene's frozen kappa. The baseline decides the step: the
  // comparison means something only where the stiff uniform object and its calibrated rigid twin
  // agree, so a search refines until they stray by at most the tolerance over the baseline's path
  // (or the refinements run out: then the finest step is used and the report says so).
  SimulationOptions sim_options;
  sim_options.kappa = ev.kappa;
  // The twins take the scene's friction per plane, mesh and pair of bodies (rigid_world).
  const RigidSettings rigid_settings = options.rigid;
  ev.rigid_friction = twin_friction(scene_in, 1 + static_cast<int>(further.size()));
  const int refinements = search ? scene_in.evaluation_max_refinements : 0;
  BaselineAtStep chosen;
  for (int k = 0; k <= refinements; ++k) {
    scene.time_step = first_step / std::pow(4.0, k);
    if (search && options.progress) {
      *options.progress << "rbaa evaluate: baseline at step " << scene.time_step << " s ..." << std::flush;
    }
    chosen = run_baseline(scene, reference_mesh, reference_materials, sim_options, ref_mass, ref_shape,
                          further, rigid_settings, options.calibration_tolerance);
    ev.step_search.push_back(chosen.trial);
    if (search && options.progress) {
      *options.progress << " strays " << 100 * chosen.trial.disagreement << " % of its path from the rigid reference\n";
    }
    if (chosen.trial.disagreement <= ev.baseline_tolerance) break;
  }
  ev.time_step = scene.time_step;
  ev.deformable_reference = std::move(chosen.baseline);
  ev.rigid_reference = std::move(chosen.rigid_reference);
  ev.calibrations = std::move(chosen.calibrations);
  ev.rigid_internal_step = chosen.rigid_internal_step;
  ev.baseline_path_length = chosen.trial.path_length;
  ev.baseline_disagreement = chosen.trial.disagreement;

  const SimulationRun adversarial = run_simulation(scene, adversarial_mesh, adversarial_materials, sim_options);
  const int traced = evaluated_body(scene_in);
  DeformableRunRecord adversarial_record =
      record_deformable("deformable adversarial", scene_in, adversarial, traced);
  ev.deformable_adversarial = std::move(adversarial_record.trace);
  std::vector<BodyPath> soft_paths;
  if (options.soft_control) {
    ev.soft_Y = scene_in.Y_range.lo;
    const MaterialField soft = MaterialField::uniform(reference_mesh.num_tets(), ev.soft_Y, scene.reference_nu,
                                                      scene.reference_rho, 1.0);
    const SimulationRun soft_run = run_simulation(scene, reference_mesh, soft, sim_options);
    DeformableRunRecord soft_record = record_deformable("deformable soft uniform", scene_in, soft_run, traced);
    ev.deformable_soft = std::move(soft_record.trace);
    soft_paths = std::move(soft_record.paths);
    ev.soft_vs_deformable = compare_runs(ev.deformable_reference, ev.deformable_soft);
    ev.soft_own_twin = own_twin(soft_run, ev.deformable_soft, "rigid twin of the soft control", ref_mass,
                                ref_shape, scene, further, rigid_settings, options.calibration_tolerance);
  }
  ev.adversarial_own_twin = own_twin(adversarial, ev.deformable_adversarial, "rigid twin of the adversarial",
                                     adv_mass, adv_shape, scene, adversarial_further, rigid_settings,
                                     options.calibration_tolerance);
  const auto start = std::chrono::steady_clock::now();
  const auto rigid_adv = simulate_rigid_bodies(adv_mass, adv_shape, scene, chosen.rigid,
                                               ev.duration, adversarial_further);
  ev.rigid_adversarial =
      trace_from_rigid("rigid adversarial", rigid_adv.at(traced), seconds_since(start));
  if (scene_in.demonstration.enabled) {
    const std::vector<BodyPath>& adversarial_paths = adversarial_record.paths;
    std::vector<DemonstrationRun> runs = {
        {"rigid reference", "rigid", "reference", chosen.rigid_paths},
        {"rigid adversarial", "rigid", "adversarial",
         paths_from_rigid(rigid_adv, adversarial_paths)},
        {"rigid soft control (the reference's rigid body)", "rigid", "soft control",
         options.soft_control ? chosen.rigid_paths : std::vector<BodyPath>{}},
        {"deformable reference", "deformable", "reference", chosen.baseline_paths},
        {"deformable adversarial", "deformable", "adversarial", adversarial_paths},
        {"deformable soft control", "deformable", "soft control", soft_paths}};
    ev.outcomes = demonstration_outcomes(scene_in.demonstration, runs, scene_in.gravity);
    if (scene_in.demonstration.predicate.kind == PredicateSpec::Kind::kStands) {
      // Rest shapes from the reference's world (the adversarial object has the same surface).
      for (size_t i = 0; i < world.bodies.size(); ++i) {
        const Body& b = world.bodies[i];
        ev.body_shapes.push_back({body_name(scene_in, static_cast<int>(i)),
                                  world.mesh.V.middleRows(b.vertex_begin, b.num_vertices())});
      }
      ev.demonstration_runs = std::move(runs);
    }
  }

  ev.rigid_vs_rigid = compare_runs(ev.rigid_reference, ev.rigid_adversarial);
  {
    // Bullet's own sensitivity to differences of the adversarial's size in its inputs: the
    // differences before the twins' rounding (rigid_mass_properties), which the rounding removes.
    const RigidMassProperties ref_exact = rigid_mass_properties(ev.reference_moments, 1e-8, 0);
    const RigidMassProperties adv_exact = rigid_mass_properties(ev.adversarial_moments, 1e-8, 0);
    const double radius = std::sqrt(ref_exact.principal_moments.maxCoeff() / ref_exact.mass);
    double delta = std::max(std::abs(adv_exact.mass / ref_exact.mass - 1),
                            (adv_exact.centre - ref_exact.centre).norm() / radius);
    for (int i = 0; i < 3; ++i) {
      delta = std::max(delta, std::abs(adv_exact.principal_moments[i] / ref_exact.principal_moments[i] - 1));
    }
    ev.rigid_perturbation = std::max(delta, 1e-15);
    // Mass and moments scaled, and the centre (where the collision shape sits against the centre
    // of mass) moved by as much as the adversarial's moved, along x.
    RigidMassProperties perturbed = ref_mass;
    perturbed.mass *= 1 + ev.rigid_perturbation;
    perturbed.principal_moments *= 1 + ev.rigid_perturbation;
    const double centre_shift = (adv_exact.centre - ref_exact.centre).norm();
    perturbed.centre.x() += centre_shift;
    // And its principal axes turned by as much as the adversarial's are turned from them (a nearly
    // round body's axes follow small differences of its moments a long way), about x.
    const Eigen::AngleAxisd axes_turn(adv_exact.principal_axes * ref_exact.principal_axes.transpose());
    ev.rigid_axes_turn = axes_turn.angle();
    perturbed.principal_axes = Eigen::AngleAxisd(ev.rigid_axes_turn, Eigen::Vector3d::UnitX()) *
                               ref_mass.principal_axes;
    // Copies of the object (demonstration.object_copies) differ from the reference's by as much.
    std::vector<RigidBody> perturbed_further = further;
    for (int c : world.copies) {
      RigidMassProperties& m = perturbed_further.at(static_cast<size_t>(c - 1)).mass;
      m.mass *= 1 + ev.rigid_perturbation;
      m.principal_moments *= 1 + ev.rigid_perturbation;
      m.centre.x() += centre_shift;
    }
    const auto runs =
        simulate_rigid_bodies(perturbed, ref_shape, scene, chosen.rigid, ev.duration, perturbed_further);
    ev.rigid_sensitivity = compare_runs(
        ev.rigid_reference, trace_from_rigid("rigid reference, inputs perturbed", runs.at(traced), 0));
  }
  ev.deformable_vs_deformable = compare_runs(ev.deformable_reference, ev.deformable_adversarial);
  ev.deformable_vs_rigid = compare_runs(ev.deformable_reference, ev.rigid_reference);
  ev.adversarial_vs_rigid = compare_runs(ev.deformable_adversarial, ev.rigid_reference);
  ev.reference_own_twin.calibrations = ev.calibrations;
  ev.reference_own_twin.rigid = ev.rigid_reference;
  ev.reference_own_twin.gap = ev.deformable_vs_rigid;
  ev.reference_own_twin.path_length = ev.baseline_path_length;
  ev.reference_own_twin.unexplained = ev.baseline_disagreement;
  ev.reference_body_moments = std::move(chosen.body_moments);
  ev.adversarial_body_moments = body_moments(adversarial);
  ev.adversarial_mesh = adversarial_mesh;
  ev.adversarial_materials = adversarial_materials;
  ev.attack_advantage = ev.deformable_vs_rigid.position_gap > 0
                            ? ev.deformable_vs_deformable.position_gap / ev.deformable_vs_rigid.position_gap
                            : INFINITY;
  return ev;
}

}  // namespace rbaa
