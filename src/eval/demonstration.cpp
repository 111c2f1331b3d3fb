#include "rbaa/eval/demonstration.hpp"

#include <cmath>

#include "rbaa/error.hpp"
#include "rbaa/io/number_text.hpp"

namespace rbaa {
namespace {

std::string fmt(double x) { return format_significant(x, 4); }

void require_samples(const BodyPath& path) {
  if (path.centre.empty())
    throw InputError("demonstration: body '" + path.name + "' has an empty path");
}

}  // namespace

double bounding_radius(const Eigen::MatrixXd& V, const Eigen::Vector3d& centre) {
  double r = 0;
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    r = std::max(r, (V.row(i).transpose() - centre).norm());
  return r;
}

double angle_between_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  if (!(a.norm() > 0) || !(b.norm() > 0)) return 0.0;
  // atan2 of |a x b| and a.b stays accurate for tiny angles, unlike acos.
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / M_PI;
}

double projected_angle_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                           const Eigen::Vector3d& normal) {
  if (!(normal.norm() > 0)) return angle_between_deg(a, b);
  const Eigen::Vector3d n = normal.normalized();
  return angle_between_deg(a - a.dot(n) * n, b - b.dot(n) * n);
}

const BodyPath& find_path(const std::vector<BodyPath>& paths, const std::string& name) {
  for (const BodyPath& p : paths) {
    if (p.name == name) return p;
  }
  throw InputError("demonstration: the run has no path of body '" + name + "'");
}

PredicateOutcome through_hoop(const BodyPath& path, const Eigen::Vector3d& centre,
                              const Eigen::Vector3d& axis, double radius) {
  require_samples(path);
  const double allowed = radius - path.bounding_radius;
  PredicateOutcome out;
  double nearest = INFINITY;  // of the downward crossings, the one closest to the centre
  int crossings = 0;
  std::string scored;  // the last counting crossing's description; cleared by a rim-out
  bool rimmed_out = false;
  for (size_t k = 0; k + 1 < path.centre.size(); ++k) {
    const double s0 = axis.dot(path.centre[k] - centre);
    const double s1 = axis.dot(path.centre[k + 1] - centre);
    const bool down = s0 > 0 && s1 <= 0, up = s0 <= 0 && s1 > 0;
    if (!down && !up) continue;
    const double f = s0 / (s0 - s1);
    const Eigen::Vector3d d = path.centre[k] + f * (path.centre[k + 1] - path.centre[k]) - centre;
    const double off = (d - axis.dot(d) * axis).norm();
    const double t =
        path.time.size() > k + 1 ? path.time[k] + f * (path.time[k + 1] - path.time[k]) : NAN;
    if (up) {
      // Back up through the opening: a ball that dipped in and rimmed out has not scored.
      if (off <= radius && !scored.empty()) {
        scored.clear();
        rimmed_out = true;
      }
      continue;
    }
    ++crossings;
    nearest = std::min(nearest, off);
    if (off <= allowed) {
      scored = "passes down through the hoop at t = " + fmt(t) + " s, " + fmt(off) +
               " m from its centre (at most " + fmt(allowed) + " m: radius " + fmt(radius) +
               " less the body's bounding radius " + fmt(path.bounding_radius) + ")";
    }
  }
  out.holds = !scored.empty();
  if (out.holds) {
    out.detail = scored;
  } else if (crossings == 0) {
    out.detail = "never crosses the hoop's plane downwards";
  } else {
    out.detail = "crosses the hoop's plane downwards " + std::to_string(crossings) +
                 " time(s), nearest " + fmt(nearest) + " m from its centre (at most " +
                 fmt(allowed) + " m counts)" +
                 (rimmed_out ? ", and came back up through the opening" : "");
  }
  return out;
}

PredicateOutcome inside_box(const BodyPath& path, const Eigen::Vector3d& min,
                            const Eigen::Vector3d& max, bool stays_below_top) {
  require_samples(path);
  auto inside = [&](const Eigen::Vector3d& x) {
    return (x.array() >= min.array()).all() && (x.array() <= max.array()).all();
  };
  PredicateOutcome out;
  const Eigen::Vector3d& end = path.centre.back();
  const std::string at = "(" + fmt(end.x()) + ", " + fmt(end.y()) + ", " + fmt(end.z()) + ")";
  if (!inside(end)) {
    out.detail = "ends outside the box, at " + at;
    return out;
  }
  if (stays_below_top) {
    size_t first = 0;
    while (!inside(path.centre[first])) ++first;
    for (size_t k = first; k < path.centre.size(); ++k) {
      if (path.centre[k].z() > max.z()) {
        out.detail =
            "ends inside at " + at +
            " but rose above the box's top after entering it (z = " + fmt(path.centre[k].z()) +
            " m at sample " + std::to_string(k) + ")";
        return out;
      }
    }
  }
  out.holds = true;
  out.detail = "ends inside the box, at " + at;
  return out;
}

PredicateOutcome stands(const BodyPath& path, double max_tilt_deg, double min_height) {
  require_samples(path);
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d top =
      path.rotation.empty() ? up : Eigen::Vector3d(path.rotation.back() * up);
  const double tilt = angle_between_deg(top, up);
  const double height = path.centre.back().z();
  PredicateOutcome out;
  out.holds = tilt <= max_tilt_deg && height > min_height;
  out.detail = path.name + ": tilt " + fmt(tilt) + " deg (at most " + fmt(max_tilt_deg) +
               "), centre at z = " + fmt(height) + " m (above " + fmt(min_height) + ")";
  return out;
}

PredicateOutcome evaluate_predicate(const PredicateSpec& spec, const std::vector<BodyPath>& paths) {
  switch (spec.kind) {
    case PredicateSpec::Kind::kNone:
      return {true, "no predicate"};
    case PredicateSpec::Kind::kThroughHoop:
      return through_hoop(find_path(paths, spec.body), spec.centre, spec.axis, spec.radius);
    case PredicateSpec::Kind::kInsideBox:
      return inside_box(find_path(paths, spec.body), spec.min, spec.max, spec.stays_below_top);
    case PredicateSpec::Kind::kStands: {
      PredicateOutcome all{true, ""};
      for (size_t i = 0; i < spec.bodies.size(); ++i) {
        const double h = spec.min_height.size() == spec.bodies.size() ? spec.min_height[i]
                                                                      : spec.min_height.at(0);
        const PredicateOutcome one = stands(find_path(paths, spec.bodies[i]), spec.max_tilt_deg, h);
        all.holds = all.holds && one.holds;
        all.detail += (all.detail.empty() ? "" : "; ") + one.detail + (one.holds ? "" : " FALLS");
      }
      return all;
    }
  }
  return {};
}

std::vector<DemonstrationOutcome> demonstration_outcomes(const DemonstrationSpec& demo,
                                                         const std::vector<DemonstrationRun>& runs,
                                                         const Eigen::Vector3d& gravity) {
  // The reference run of each simulator ("rigid", "deformable"), where it was made.
  auto reference_of = [&](const std::string& simulator) -> const BodyPath* {
    for (const DemonstrationRun& r : runs) {
      if (r.simulator == simulator && r.object == "reference" && !r.paths.empty())
        return &find_path(r.paths, demo.figure_body);
    }
    return nullptr;
  };
  const Eigen::Vector3d normal = demo.figure_horizontal ? gravity : Eigen::Vector3d::Zero();
  std::vector<DemonstrationOutcome> rows;
  for (const DemonstrationRun& r : runs) {
    if (r.paths.empty()) continue;
    DemonstrationOutcome row;
    row.run = r.run;
    row.simulator = r.simulator;
    row.object = r.object;
    row.has_predicate = demo.predicate.kind != PredicateSpec::Kind::kNone;
    if (row.has_predicate) row.predicate = evaluate_predicate(demo.predicate, r.paths);
    row.figure = NAN;
    const BodyPath* reference =
        reference_of(demo.figure_against_own_simulator ? r.simulator : "rigid");
    if (demo.figure == "angle" && reference) {
      const BodyPath& own = find_path(r.paths, demo.figure_body);
      if (own.velocity.empty() || reference->velocity.empty())
        throw InputError("demonstration: body '" + demo.figure_body + "' has no velocities");
      row.figure = projected_angle_deg(own.velocity.back(), reference->velocity.back(), normal);
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace rbaa
