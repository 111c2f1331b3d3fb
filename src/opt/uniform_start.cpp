#include "rbaa/opt/uniform_start.hpp"

#include <sstream>

#include "rbaa/error.hpp"

namespace rbaa {

std::vector<double> uniform_candidate_values(double lo, double hi) {
  const double inside = 1e-6 * (hi - lo);
  return {lo + inside, TanhBoxMap(lo, hi, "candidate range").mid(), hi - inside};
}

MaterialField uniform_start_material(const AttackProblem& problem, double Y0, double nu0) {
  DesignSpaceOptions o = problem.body_design->options();
  o.Y0 = Y0;
  o.nu0 = nu0;
  const DesignSpace design(problem.body_mesh, o);
  return design.to_material(design.initial_theta(false));
}

UniformStart find_best_uniform_start(
    const AttackProblem& problem,
    const std::function<void(const UniformCandidate&)>& on_candidate) {
  const DesignSpaceOptions& o = problem.body_design->options();
  UniformStart start;
  for (double Y : uniform_candidate_values(o.Y_min, o.Y_max)) {
    for (double nu : uniform_candidate_values(o.nu_min, o.nu_max)) {
      UniformCandidate c;
      c.Y = Y;
      c.nu = nu;
      try {
        const BodyRun run = problem.simulate(uniform_start_material(problem, Y, nu));
        c.objective = run.objective;
        c.gap = run.state.gap;
      } catch (const SolverError& e) {
        std::ostringstream what;
        what.precision(6);
        what << "uniform start candidate Y = " << Y << " Pa, nu = " << nu << ": " << e.what();
        throw SolverError(what.str());
      }
      start.candidates.push_back(c);
      if (start.chosen < 0 || c.objective < start.best().objective) {
        start.chosen = static_cast<int>(start.candidates.size()) - 1;
      }
      if (on_candidate) on_candidate(c);
    }
  }
  return start;
}

}  // namespace rbaa
