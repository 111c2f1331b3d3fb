#include "rbaa/sim/trajectory.hpp"

namespace rbaa {

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
