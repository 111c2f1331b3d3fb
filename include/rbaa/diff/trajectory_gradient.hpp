#pragma once
// The trajectory term of an attack as a function of the design vector, with its gradient from the
// adjoint (SPEC section 4):
//
//   theta -> DesignSpace::to_material -> forward simulation -> objective -> adjoint -> material
//   gradient -> DesignSpace::chain_gradient -> dC/dtheta.
//
// It is a ceres::FirstOrderFunction (for Ceres' GradientProblemSolver) and offers the same call
// as a throwing member (for the Adam loop: opt/adam.hpp's ValueAndGradient is
// [&f](const Eigen::VectorXd& x, Eigen::VectorXd* g) { return f.evaluate(x, g); }), plus a
// material-space version for gradient checks. Holds its own simulator; not thread-safe.

#include <ceres/first_order_function.h>

#include <Eigen/Core>

#include <memory>
#include <string>

#include "rbaa/diff/adjoint.hpp"
#include "rbaa/diff/trajectory_objective.hpp"
#include "rbaa/material/design_space.hpp"
#include "rbaa/sim/simulator.hpp"

namespace rbaa {

/// What one evaluation computed (kept for progress reports and checkpoints).
struct TrajectoryEvaluation {
  double value = 0;
  MaterialField materials;
  Trajectory trajectory;
  AdjointStats adjoint;  ///< zeros when no gradient was asked for
  double forward_seconds = 0;
  double objective_seconds = 0;
  double adjoint_seconds = 0;
  std::size_t stored_factor_bytes = 0;
};

class TrajectoryGradientFunction : public ceres::FirstOrderFunction {
 public:
  /// `rest`: the placed mesh (rest shape and initial positions' mesh); q0, v0: initial positions
  /// and per-dof velocities (3 #V); `design`: the map theta -> materials.
  TrajectoryGradientFunction(const TetMesh& rest, const SimulationSettings& settings,
                             Eigen::VectorXd q0, Eigen::VectorXd v0, DesignSpace design,
                             std::shared_ptr<const TrajectoryObjective> objective,
                             FactorStorage storage = FactorStorage::kStore);
  ~TrajectoryGradientFunction() override;

  /// C(theta) and, with gradient != nullptr, dC/dtheta (design().size()). Throws
  /// rbaa::SolverError when a step fails.
  double evaluate(const Eigen::VectorXd& theta, Eigen::VectorXd* gradient);
  /// C(materials) and, with gradient != nullptr, dC/d(material) (#T per field).
  double evaluate_materials(const MaterialField& materials, MaterialGradient* gradient);

  /// ceres::FirstOrderFunction: returns false (and keeps the message in last_error()) when the
  /// simulation fails, which Ceres' line searches treat as an infeasible point.
  bool Evaluate(const double* parameters, double* cost, double* gradient) const override;
  int NumParameters() const override { return design_.size(); }

  const DesignSpace& design() const { return design_; }
  const TrajectoryObjective& objective() const { return *objective_; }
  const TrajectoryEvaluation& last() const { return last_; }
  const std::string& last_error() const { return last_error_; }
  Simulator& simulator() { return *sim_; }
  DifferentiableSimulator& differentiable() { return *diff_; }

 private:
  DesignSpace design_;
  std::shared_ptr<const TrajectoryObjective> objective_;
  Eigen::VectorXd q0_, v0_;
  std::unique_ptr<Simulator> sim_;
  std::unique_ptr<DifferentiableSimulator> diff_;
  TrajectoryEvaluation last_;
  mutable std::string last_error_;
};

}  // namespace rbaa
