#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "rbaa/error.hpp"
#include "rbaa/eval/evaluation.hpp"
#include "rbaa/eval/final_poses_plot.hpp"
#include "rbaa/eval/material_sections.hpp"
#include "rbaa/eval/path_plot.hpp"
#include "rbaa/io/atomic_file.hpp"
#include "rbaa/io/number_text.hpp"

namespace rbaa {
namespace {

nlohmann::json moments_json(const Moments& m) {
  const MomentVector v = m.as_vector();
  return std::vector<double>(v.data(), v.data() + 10);
}

nlohmann::json comparison_json(const RunComparison& c) {
  return {{"runs", {c.a, c.b}},
          {"com_gap_m", c.position_gap},
          {"max_com_gap_m", c.max_position_gap},
          {"velocity_angle_deg", c.velocity_angle_deg},
          {"orientation_gap_deg", c.orientation_gap_deg}};
}

std::string file_name(const RunTrace& t) {
  std::string s = t.name;
  std::replace(s.begin(), s.end(), ' ', '_');
  return s + ".csv";
}

void write_trace_csv(const std::string& path, const RunTrace& t) {
  write_file_atomically(path, [&](std::ostream& out) {
    out << "time,com_x,com_y,com_z,vel_x,vel_y,vel_z,quat_w,quat_x,quat_y,quat_z\n";
    for (size_t i = 0; i < t.time.size(); ++i) {
      const auto& p = t.centre[i];
      const auto& v = t.velocity[i];
      const auto& q = t.rotation[i];
      out << exact(t.time[i]) << ',' << exact(p.x()) << ',' << exact(p.y()) << ',' << exact(p.z()) << ','
          << exact(v.x()) << ',' << exact(v.y()) << ',' << exact(v.z()) << ',' << exact(q.w()) << ','
          << exact(q.x()) << ',' << exact(q.y()) << ',' << exact(q.z()) << '\n';
    }
  });
}

std::string fmt(double x, int precision = 4) {
  std::ostringstream out;
  out << std::setprecision(precision) << x;
  return out.str();
}

}  // namespace

void write_evaluation(const Evaluation& ev, const Scene& scene, const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir + ": cannot create output folder (" + ec.message() + ")");

  std::vector<const RunTrace*> runs = {&ev.rigid_reference, &ev.rigid_adversarial, &ev.deformable_reference,
                                       &ev.deformable_adversarial};
  if (!ev.deformable_soft.time.empty()) runs.push_back(&ev.deformable_soft);
  nlohmann::json timing, files;
  for (const RunTrace* t : runs) {
    write_trace_csv(dir + "/" + file_name(*t), *t);
    timing[t->name] = t->seconds;
    files[t->name] = file_name(*t);
  }
  std::vector<PathSeries> series;
  for (const RunTrace* t : runs) {
    PathSeries s{t->name, Eigen::MatrixXd(t->centre.size(), 3), Eigen::VectorXd(t->centre.size())};
    for (size_t i = 0; i < t->centre.size(); ++i) {
      s.points.row(i) = t->centre[i].transpose();
      s.times[i] = i < t->time.size() ? t->time[i] : NAN;
    }
    series.push_back(std::move(s));
  }
  const std::string png = write_path_plot(dir + "/paths", scene.name + ": centre-of-mass paths",
                                          series, scene.planes, scene.obstacle_meshes);
  // A stack's verdict is where the bodies end: a panel per run with every body's final outline.
  const std::string poses_png =
      ev.demonstration_runs.empty()
          ? std::string()
          : write_final_poses_plot(dir + "/final_poses",
                                   scene.name + ": every body at T = " + fmt(ev.duration) + " s",
                                   ev.body_shapes, ev.demonstration_runs, scene.planes);
  const std::string materials_png =
      ev.adversarial_mesh.num_tets() == 0
          ? std::string()
          : write_material_sections(dir + "/adversarial_materials",
                                    scene.name + ": the adversarial object's materials through its centre of mass",
                                    ev.adversarial_mesh, ev.adversarial_materials,
                                    ev.adversarial_moments.centre_of_mass());

  // Which contact a calibration is: "plane": i, "mesh": i or "bodies": [a, b], and its name.
  auto contact_json = [](const RestitutionCalibration& c) {
    nlohmann::json j = {{"contact", c.name}, {"kind", restitution_contact_name(c.contact)}};
    switch (c.contact) {
      case RestitutionContact::kPlane:
        j["plane"] = c.plane;
        j["body"] = c.body_a;
        break;
      case RestitutionContact::kMesh:
        j["mesh"] = c.mesh;
        j["body"] = c.body_a;
        break;
      case RestitutionContact::kBodies:
        j["bodies"] = {c.body_a, c.body_b};
        break;
    }
    return j;
  };
  // Every plane's, mesh's and pair of bodies' Coulomb coefficient in the twins, named as the
  // calibrations name them.
  nlohmann::json friction = nlohmann::json::array();
  for (const TwinFriction& f : ev.rigid_friction) {
    nlohmann::json j = {{"contact", f.name}, {"kind", restitution_contact_name(f.contact)}};
    switch (f.contact) {
      case RestitutionContact::kPlane:
        j["plane"] = f.plane;
        break;
      case RestitutionContact::kMesh:
        j["mesh"] = f.mesh;
        break;
      case RestitutionContact::kBodies:
        j["bodies"] = {f.body_a, f.body_b};
        break;
    }
    j["friction"] = f.friction;
    friction.push_back(std::move(j));
  }
  nlohmann::json calibration = nlohmann::json::array();
  for (const auto& c : ev.calibrations) {
    nlohmann::json j = contact_json(c);
    j.update({{"time_s", c.time}, {"calibrated", c.calibrated},
              {"deformable_first_rebound", c.deformable_rebound}, {"rigid_first_rebound", c.rigid_rebound},
              {"restitution", c.restitution}, {"restitutions_giving_it", c.roots},
              {"iterations", c.iterations}, {"deformable_later_rebounds", c.later_deformable_rebounds}});
    calibration.push_back(std::move(j));
  }
  auto own_twin_json = [&](const OwnTwin& t) {
    nlohmann::json cal = nlohmann::json::array();
    for (const auto& c : t.calibrations) {
      nlohmann::json j = contact_json(c);
      j.update({{"deformable_first_rebound", c.deformable_rebound},
                {"rigid_first_rebound", c.rigid_rebound}, {"restitution", c.restitution},
                {"restitutions_giving_it", c.roots}, {"calibrated", c.calibrated}});
      cal.push_back(std::move(j));
    }
    return nlohmann::json{{"calibration", cal}, {"vs_own_twin", comparison_json(t.gap)},
                          {"path_length_m", t.path_length}, {"unexplained", t.unexplained}};
  };
  nlohmann::json own_twins = {{"reference", own_twin_json(ev.reference_own_twin)},
                              {"adversarial", own_twin_json(ev.adversarial_own_twin)}};
  if (!ev.deformable_soft.time.empty()) own_twins["soft_control"] = own_twin_json(ev.soft_own_twin);
  nlohmann::json search = nlohmann::json::array();
  for (const auto& t : ev.step_search) {
    search.push_back({{"time_step_s", t.time_step}, {"baseline_path_length_m", t.path_length},
                      {"baseline_disagreement", t.disagreement}, {"seconds", t.seconds}});
  }
  nlohmann::json outcomes = nullptr;
  if (scene.demonstration.enabled) {
    const DemonstrationSpec& demo = scene.demonstration;
    outcomes = {
        {"predicate", predicate_kind_name(demo.predicate.kind)},
        {"figure", demo.figure.empty() ? nlohmann::json(nullptr) : nlohmann::json(demo.figure)},
        {"figure_body", demo.figure_body},
        {"figure_against", demo.figure_against_own_simulator ? "own_simulator" : "rigid_reference"},
        {"figure_projection", demo.figure_horizontal ? "horizontal" : "none"},
        {"object_copies", demo.object_copies},
        {"runs", nlohmann::json::array()}};
    for (const DemonstrationOutcome& o : ev.outcomes) {
      outcomes["runs"].push_back({{"run", o.run},
                                  {"simulator", o.simulator},
                                  {"object", o.object},
                                  {"predicate", o.has_predicate ? nlohmann::json(o.predicate.holds)
                                                                : nlohmann::json(nullptr)},
                                  {"detail", o.has_predicate ? nlohmann::json(o.predicate.detail)
                                                             : nlohmann::json(nullptr)},
                                  {"figure_deg", std::isnan(o.figure) ? nlohmann::json(nullptr)
                                                                      : nlohmann::json(o.figure)}});
    }
  }
  nlohmann::json report = {
      {"scene", scene.name},
      {"outcomes", outcomes},
      {"compared_body", scene.evaluation_body.empty() ? scene.object_name : scene.evaluation_body},
      {"duration_s", ev.duration},
      {"time_step_s", ev.time_step},
      {"attack_time_step_s", ev.attack_time_step},
      {"kappa", ev.kappa},
      {"friction_iterations", scene.friction_iterations},
      {"moments", {{"reference", moments_json(ev.reference_moments)},
                   {"adversarial", moments_json(ev.adversarial_moments)}}},
      {"rigid", {{"simulator", "Bullet (double precision), semi-implicit Euler"},
                 {"internal_step_s", ev.rigid_internal_step},
                 {"friction", friction},
                 {"collision_shape", ev.rigid_shape}}},
      {"calibration", calibration},
      {"rigid_vs_rigid", comparison_json(ev.rigid_vs_rigid)},
      {"deformable_vs_deformable", comparison_json(ev.deformable_vs_deformable)},
      {"deformable_vs_rigid", comparison_json(ev.deformable_vs_rigid)},
      {"adversarial_vs_rigid", comparison_json(ev.adversarial_vs_rigid)},
      {"soft_control", ev.deformable_soft.time.empty()
                           ? nlohmann::json(nullptr)
                           : nlohmann::json{{"Y", ev.soft_Y}, {"vs_baseline", comparison_json(ev.soft_vs_deformable)},
                                            {"attack_over_softness", ev.soft_vs_deformable.position_gap > 0
                                                 ? ev.deformable_vs_deformable.position_gap / ev.soft_vs_deformable.position_gap
                                                 : INFINITY}}},
      {"own_calibrated_twins", own_twins},
      {"attack_advantage", ev.attack_advantage},
      {"baseline_path_length_m", ev.baseline_path_length},
      {"baseline_disagreement", ev.baseline_disagreement},
      {"baseline_tolerance", ev.baseline_tolerance},
      {"time_steps_tried", search},
      {"rigid_identical", ev.rigid_vs_rigid.max_position_gap <= 1e-9},
      {"rigid_sensitivity", {{"perturbation", ev.rigid_perturbation},
                             {"axes_turn_rad", ev.rigid_axes_turn},
                             {"vs_rigid_reference", comparison_json(ev.rigid_sensitivity)}}},
      {"timing_s", timing},
      {"files", files},
      {"plot", png.empty() ? nlohmann::json(nullptr) : nlohmann::json(std::filesystem::path(png).filename().string())},
      {"materials_plot", materials_png.empty() ? nlohmann::json(nullptr)
                                               : nlohmann::json(std::filesystem::path(materials_png).filename().string())},
      {"final_poses_plot", poses_png.empty() ? nlohmann::json(nullptr)
                                             : nlohmann::json(std::filesystem::path(poses_png).filename().string())}};
  write_file_atomically(dir + "/report.json", [&](std::ostream& out) { out << report.dump(2) << "\n"; });

  write_file_atomically(dir + "/summary.md", [&](std::ostream& out) {
    out << "# " << scene.name << ": rigid and deformable, reference and adversarial\n\n"
        << "Duration " << fmt(ev.duration) << " s, step " << fmt(ev.time_step) << " s (attack built at "
        << fmt(ev.attack_time_step) << " s)"
        << (scene.friction_iterations > 1
                ? ", deformable friction re-lagged up to " + std::to_string(scene.friction_iterations) +
                      " times per step (contact.friction_iterations)"
                : std::string())
        << ". Rigid: Bullet ("
        << ev.rigid_shape << "), internal step " << fmt(ev.rigid_internal_step)
        << " s, the scene's Coulomb friction per contact (";
    for (size_t i = 0; i < ev.rigid_friction.size(); ++i) {
      out << (i ? ", " : "") << ev.rigid_friction[i].name << " " << fmt(ev.rigid_friction[i].friction);
    }
    if (ev.rigid_friction.empty()) out << "nothing to touch";
    const std::string compared = !scene.evaluation_body.empty() ? scene.evaluation_body
                                 : scene.object_name;
    out << "). Compared: the "
        << (compared == "object" ? std::string("object's centre of mass")
                                 : "centre of mass of body '" + compared + "'")
        << ".\n\n"
        << "Restitution per plane (each body's against it: `plane 0 (ball)`), obstacle mesh and pair of bodies, "
           "fitted to the deformable baseline's first "
           "contact with it (a mesh's or a pair's rebound: the relative velocity along the contact's impulse; "
           "restitution in [0, 1], above 1 only for a rebound above 1; of several that fit, the one whose twin "
           "follows the baseline closest; not fitted: the restitution whose rebound came nearest, or, if the "
           "twin never meets that contact, 1 (a further body against a plane: the plane's own)):\n\n"
        << "| contact | first contact (s) | baseline rebound | rigid rebound | Bullet restitution | later baseline rebounds |\n"
        << "|---|---|---|---|---|---|\n";
    for (const auto& c : ev.calibrations) {
      out << "| " << c.name << " | " << fmt(c.time) << " | " << fmt(c.deformable_rebound, 6) << " | "
          << (std::isnan(c.rigid_rebound) ? std::string("-") : fmt(c.rigid_rebound, 6))
          << (c.calibrated ? "" : " (not fitted)") << " | " << fmt(c.restitution, 6) << " | ";
      for (double r : c.later_deformable_rebounds) out << fmt(r) << " ";
      out << "|\n";
    }
    if (scene.demonstration.enabled) {
      const DemonstrationSpec& demo = scene.demonstration;
      out << "\nDemonstration outcomes: predicate `" << predicate_kind_name(demo.predicate.kind)
          << "`"
          << (demo.figure.empty()
                  ? std::string()
                  : "; figure: the angle between the centre-of-mass velocity at T (the run's end, not just after a bounce) of body '" +
                        demo.figure_body + "' and " +
                        (demo.figure_against_own_simulator ? "the same simulator's reference run's"
                                                           : "the rigid reference's") +
                        (demo.figure_horizontal ? ", both projected onto the horizontal plane"
                                                : "") +
                        " (deg)")
          << ".";
      if (!demo.object_copies.empty()) {
        out << " Copies of each run's object (its mesh and materials at their own poses):";
        for (size_t i = 0; i < demo.object_copies.size(); ++i)
          out << (i ? ", " : " ") << "'" << demo.object_copies[i] << "'";
        out << ".";
      }
      out << "\n\n| run | predicate | figure (deg) | why |\n|---|---|---|---|\n";
      for (const DemonstrationOutcome& o : ev.outcomes) {
        out << "| " << o.run << " | "
            << (o.has_predicate ? (o.predicate.holds ? "true" : "false") : "-") << " | "
            << (std::isnan(o.figure) ? std::string("-") : fmt(o.figure)) << " | "
            << (o.has_predicate ? o.predicate.detail : std::string()) << " |\n";
      }
    }
    out << "\n"
        << "| pair | centre-of-mass gap at T (m) | max gap (m) | velocity angle at T (deg) | orientation gap at T (deg) |\n"
        << "|---|---|---|---|---|\n";
    std::vector<const RunComparison*> pairs = {&ev.rigid_vs_rigid, &ev.deformable_vs_deformable,
                                               &ev.deformable_vs_rigid, &ev.adversarial_vs_rigid};
    if (!ev.deformable_soft.time.empty()) pairs.push_back(&ev.soft_vs_deformable);
    for (const RunComparison* c : pairs) {
      out << "| " << c->a << " vs " << c->b << " | " << fmt(c->position_gap) << " | " << fmt(c->max_position_gap)
          << " | " << fmt(c->velocity_angle_deg) << " | " << fmt(c->orientation_gap_deg) << " |\n";
    }
    out << "\nThe adversarial object's deformable gap is " << fmt(ev.attack_advantage, 3)
        << " x the gap between the stiff deformable baseline and the rigid reference.\n";
    out << "The baseline strays from the rigid reference by at most " << fmt(100 * ev.baseline_disagreement, 3)
        << " % of its path (" << fmt(ev.baseline_path_length) << " m)"
        << (ev.baseline_disagreement <= ev.baseline_tolerance ? ".\n" : ": above the tolerance of " + fmt(100 * ev.baseline_tolerance, 3) + " %");
    if (ev.baseline_disagreement > ev.baseline_tolerance) {
      const size_t n = ev.step_search.size();
      if (n > 1) {
        // What a last refinement bought tells the step's share from the rigid model's (one
        // restitution per contact), which no step removes.
        out << " after " << n - 1 << " refinements (the last took it from " << fmt(100 * ev.step_search[n - 2].disagreement, 3)
            << " % to " << fmt(100 * ev.step_search[n - 1].disagreement, 3)
            << " %; what does not shrink with the step is the rigid model's).";
        // A coarser step that agreed better says the disagreement does not fall with h: the
        // finest step stays (its deformable run is the more accurate), but the reader is told.
        size_t least = n - 1;
        for (size_t i = 0; i < n; ++i) {
          if (ev.step_search[i].disagreement < ev.step_search[least].disagreement) least = i;
        }
        if (least != n - 1) {
          out << " A coarser step strayed less (" << fmt(100 * ev.step_search[least].disagreement, 3) << " % at h = "
              << fmt(ev.step_search[least].time_step)
              << " s): here the disagreement does not fall with the step; the finest step is kept, its "
                 "deformable run being the more accurate.";
        }
        out << "\n";
      } else {
        out << ": the comparison may measure the time step more than the object; try --time_step=auto or a "
               "smaller --time_step.\n";
      }
    }
    if (!ev.deformable_soft.time.empty()) {
      out << "Control: the reference shape in uniform material at the softest allowed Y = " << fmt(ev.soft_Y)
          << " Pa (same moments) ends " << fmt(ev.soft_vs_deformable.position_gap)
          << " m from the baseline, its velocity at T "
          << fmt(ev.soft_vs_deformable.velocity_angle_deg)
          << " deg from the baseline's; the attacked object's gap is "
          << fmt(ev.soft_vs_deformable.position_gap > 0
                     ? ev.deformable_vs_deformable.position_gap / ev.soft_vs_deformable.position_gap
                     : INFINITY, 3)
          << " x that (above 1 the optimisation adds to what softness alone does; below 1 it does not).\n";
    }
    out << "\nEach deformable run against a rigid twin calibrated to its own rebounds (its own moments, "
           "each plane's (each body's against it), mesh's and pair's restitution fitted to its own first contact with it): what remains is what no "
           "rigid simulator with a tuned restitution explains.\n\n"
        << "| run | fitted restitutions | gap at T (m) | max gap (m) | max gap / path | velocity angle at T (deg) |\n"
        << "|---|---|---|---|---|---|\n";
    auto own_row = [&](const std::string& name, const OwnTwin& t) {
      out << "| " << name << " | ";
      for (const auto& c : t.calibrations) out << c.name << ": " << fmt(c.restitution, 4) << (c.calibrated ? "" : " (not fitted)") << " ";
      out << "| " << fmt(t.gap.position_gap) << " | " << fmt(t.gap.max_position_gap) << " | "
          << fmt(100 * t.unexplained, 3) << " % | " << fmt(t.gap.velocity_angle_deg) << " |\n";
    };
    own_row("reference (stiff baseline)", ev.reference_own_twin);
    own_row("adversarial", ev.adversarial_own_twin);
    if (!ev.deformable_soft.time.empty()) own_row("soft uniform control", ev.soft_own_twin);
    out << "\n";
    out << "As rigid bodies the two objects are " << (ev.rigid_vs_rigid.max_position_gap <= 1e-9 ? "" : "NOT ")
        << "identical (max gap " << fmt(ev.rigid_vs_rigid.max_position_gap) << " m, bar 1e-9 m).";
    out << " The rigid simulator's own sensitivity: the rigid reference with its mass and principal "
           "moments (and its copies') scaled by 1 + "
        << fmt(ev.rigid_perturbation) << " (the largest relative difference between the two objects' "
           "rigid inputs before the twins round them to a grid of 2^-24), its centre of mass moved as "
           "far as theirs differ and its principal axes turned by "
        << fmt(ev.rigid_axes_turn) << " rad (as theirs are) strays up to "
        << fmt(ev.rigid_sensitivity.max_position_gap) << " m from itself (the twins' gap without the rounding)"
        << (ev.rigid_vs_rigid.max_position_gap > 1e-9 &&
                    ev.rigid_vs_rigid.max_position_gap <= 10 * ev.rigid_sensitivity.max_position_gap
                ? ": the twins' gap is of that order, Bullet amplifying round-off in its inputs, "
                  "not a difference of the objects"
                : "")
        << ".\n\n";
    if (ev.step_search.size() > 1) {
      out << "Steps tried for the baseline (the last is used):\n\n| step (s) | strays (% of path) | wall time (s) |\n"
          << "|---|---|---|\n";
      for (const auto& t : ev.step_search) {
        out << "| " << fmt(t.time_step) << " | " << fmt(100 * t.disagreement, 3) << " | " << fmt(t.seconds) << " |\n";
      }
      out << "\n";
    }
    out << "| run | wall time (s) | CSV |\n|---|---|---|\n";
    for (const RunTrace* t : runs) out << "| " << t->name << " | " << fmt(t->seconds) << " | " << file_name(*t) << " |\n";
    if (!png.empty()) out << "\n![paths](paths.png)\n";
    if (!poses_png.empty())
      out << "\nEvery body at the end of each run (side view):\n\n![final poses](final_poses.png)\n";
    if (!materials_png.empty()) {
      out << "\nThe adversarial object's Young's modulus, density and occupancy on the three coordinate planes "
             "through its centre of mass:\n\n![materials](adversarial_materials.png)\n";
    }
  });
}

}  // namespace rbaa
