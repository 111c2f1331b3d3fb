#include "rbaa/sim/trajectory.hpp"

#include "rbaa/sim/newton_solver.hpp"

namespace rbaa {

void StepStats::add(const NewtonResult& solve) {
  newton_iterations += solve.iterations;
  exact_factor = solve.exact_factor;
  roundoff_limited = solve.roundoff_limited;
  floor_velocity = solve.floor_velocity;
  projected_fallbacks += solve.projected_fallbacks;
  extrapolations += solve.extrapolations;
  chord_steps += solve.chord_steps;
  line_search_probes += solve.line_search_probes;
  symbolic_analyses += solve.symbolic_analyses;
  gradient_seconds += solve.gradient_seconds;
  assembly_seconds += solve.assembly_seconds;
  factorization_seconds += solve.factorization_seconds;
  solve_seconds += solve.solve_seconds;
  line_search_seconds += solve.line_search_seconds;
}

StepStats& StepStats::operator+=(const StepStats& other) {
  newton_iterations += other.newton_iterations;
  projected_fallbacks += other.projected_fallbacks;
  extrapolations += other.extrapolations;
  chord_steps += other.chord_steps;
  line_search_probes += other.line_search_probes;
  symbolic_analyses += other.symbolic_analyses;
  ccd_caps += other.ccd_caps;
  friction_relags += other.friction_relags;
  seconds += other.seconds;
  gradient_seconds += other.gradient_seconds;
  assembly_seconds += other.assembly_seconds;
  factorization_seconds += other.factorization_seconds;
  solve_seconds += other.solve_seconds;
  line_search_seconds += other.line_search_seconds;
  return *this;
}

std::vector<int> Trajectory::grid_frames() const {
  if (!grid.empty()) return grid;
  std::vector<int> all(q.size());
  for (std::size_t k = 0; k < q.size(); ++k) all[k] = static_cast<int>(k);
  return all;
}

BdfStepRule Trajectory::rule(int k) const {
  return bdf_step_rule(integrator, step_size(k), step_size(k - 1));
}

BdfPredictor Trajectory::predictor(int k) const {
  return bdf_predictor(integrator, rule(k), rule(k - 1), rule(k - 2), step_size(k));
}

Eigen::VectorXd Trajectory::velocity(int k) const {
  return bdf_velocity(integrator, rule(k - 1), step_size(k - 1), position(k), position(k - 1),
                      position(k - 2));
}

}  // namespace rbaa
