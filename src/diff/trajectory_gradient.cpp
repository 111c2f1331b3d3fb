#include "rbaa/diff/trajectory_gradient.hpp"

#include <chrono>

#include "rbaa/error.hpp"

namespace rbaa {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

TrajectoryGradientFunction::TrajectoryGradientFunction(
    const TetMesh& rest, const SimulationSettings& settings, Eigen::VectorXd q0,
    Eigen::VectorXd v0, DesignSpace design, std::shared_ptr<const TrajectoryObjective> objective,
    FactorStorage storage)
    : design_(std::move(design)), objective_(std::move(objective)), q0_(std::move(q0)),
      v0_(std::move(v0)) {
  if (!objective_) throw InputError("trajectory gradient: no objective");
  if (design_.num_tets() != rest.num_tets()) {
    throw InputError("trajectory gradient: the design space and the mesh differ in element count");
  }
  sim_ = std::make_unique<Simulator>(rest, design_.initial_material(), settings);
  diff_ = std::make_unique<DifferentiableSimulator>(*sim_, storage);
}

TrajectoryGradientFunction::~TrajectoryGradientFunction() = default;

double TrajectoryGradientFunction::evaluate_materials(const MaterialField& materials,
                                                      MaterialGradient* gradient) {
  last_ = TrajectoryEvaluation{};
  last_.materials = materials;
  const auto t0 = std::chrono::steady_clock::now();
  last_.trajectory = diff_->forward(materials, q0_, v0_);
  last_.forward_seconds = seconds_since(t0);
  last_.stored_factor_bytes = diff_->stored_factor_bytes();

  const auto t1 = std::chrono::steady_clock::now();
  TrajectorySeed seed;
  last_.value = objective_->evaluate(last_.trajectory, materials, gradient ? &seed : nullptr);
  last_.objective_seconds = seconds_since(t1);
  if (gradient != nullptr) {
    const auto t2 = std::chrono::steady_clock::now();
    AdjointResult r = diff_->backward(last_.trajectory, seed);
    last_.adjoint = r.stats;
    *gradient = std::move(r.materials);
    last_.adjoint_seconds = seconds_since(t2);
  }
  return last_.value;
}

double TrajectoryGradientFunction::evaluate(const Eigen::VectorXd& theta, Eigen::VectorXd* gradient) {
  const MaterialField materials = design_.to_material(theta);
  MaterialGradient g;
  const double value = evaluate_materials(materials, gradient ? &g : nullptr);
  if (gradient != nullptr) *gradient = design_.chain_gradient(theta, g);
  return value;
}

bool TrajectoryGradientFunction::Evaluate(const double* parameters, double* cost,
                                          double* gradient) const {
  // Ceres' interface is const; the simulator's state is a cache of the last evaluation.
  auto* self = const_cast<TrajectoryGradientFunction*>(this);
  const Eigen::Map<const Eigen::VectorXd> theta(parameters, design_.size());
  try {
    Eigen::VectorXd g;
    *cost = self->evaluate(theta, gradient != nullptr ? &g : nullptr);
    if (gradient != nullptr) Eigen::Map<Eigen::VectorXd>(gradient, design_.size()) = g;
    last_error_.clear();
    return true;
  } catch (const SolverError& e) {
    last_error_ = e.what();
    return false;
  }
}

}  // namespace rbaa
