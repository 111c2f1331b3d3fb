#include "rbaa/opt/occupancy_penalty.hpp"

#include <algorithm>
#include <sstream>
#include <vector>

#include "rbaa/error.hpp"
#include "rbaa/mesh/topology.hpp"
#include "rbaa/opt/occupancy.hpp"

namespace rbaa {

double occupancy_penalty_ramp(const OccupancyPenaltyOptions& options, int iteration,
                              int iterations) {
  if (iterations <= 0) return 0.0;
  const double f = static_cast<double>(iteration) / iterations;
  if (f >= options.ramp_end) return 1.0;
  if (f <= options.ramp_start) return 0.0;
  return (f - options.ramp_start) / (options.ramp_end - options.ramp_start);
}

OccupancyPenalty::OccupancyPenalty(const TetMesh& mesh, const DesignSpace& design, double threshold,
                                   const OccupancyPenaltyOptions& options)
    : design_(design), options_(options), threshold_(threshold) {
  const double alpha_min = design.options().alpha_min;
  if (!(threshold > alpha_min && threshold < 1.0)) {
    std::ostringstream msg;
    msg << "occupancy penalty: the rounding threshold " << threshold
        << " must lie between alpha_min (" << alpha_min << ") and 1";
    throw InputError(msg.str());
  }
  if (mesh.num_tets() != design.num_tets()) {
    std::ostringstream msg;
    msg << "occupancy penalty: the mesh has " << mesh.num_tets() << " elements, the design space "
        << design.num_tets();
    throw InputError(msg.str());
  }
  if (!design.optimises(DesignField::kAlpha) || design.num_interior() == 0) return;
  mesh_ = mesh;
  adjacency_ = face_adjacency(mesh);
  const Eigen::VectorXd volume = tet_volumes(mesh);
  weights_.resize(design.num_interior());
  for (int i = 0; i < design.num_interior(); ++i) weights_[i] = volume[design.interior()[i]];
  weights_ /= weights_.sum();
}

double OccupancyPenalty::greyness(double alpha, double* derivative) const {
  // s maps [alpha_min, t] onto [0, 1/2] and [t, 1] onto [1/2, 1]; p = 4 s (1 - s).
  const double alpha_min = design_.options().alpha_min;
  const bool low = alpha <= threshold_;
  const double ds = low ? 0.5 / (threshold_ - alpha_min) : 0.5 / (1.0 - threshold_);
  const double s = low ? (alpha - alpha_min) * ds : 1.0 - (1.0 - alpha) * ds;
  if (derivative) *derivative = 4.0 * (1.0 - 2.0 * s) * ds;
  return 4.0 * s * (1.0 - s);
}

double OccupancyPenalty::value(const Eigen::VectorXd& theta, Eigen::VectorXd* gradient) const {
  if (theta.size() != design_.size())
    throw InputError("occupancy penalty: design vector of wrong size");
  if (gradient) gradient->setZero(design_.size());
  if (weights_.size() == 0) return 0.0;
  const int o = design_.offset(DesignField::kAlpha);
  const TanhBoxMap& map = design_.map(DesignField::kAlpha);
  double P = 0;
  for (int i = 0; i < design_.num_interior(); ++i) {
    double dp = 0;
    P += weights_[i] * greyness(map.value(theta[o + i]), gradient ? &dp : nullptr);
    if (gradient) (*gradient)[o + i] = weights_[i] * dp * map.derivative(theta[o + i]);
  }
  return P;
}

double OccupancyPenalty::repair_share(const Eigen::VectorXd& theta, Eigen::VectorXd* gradient,
                                      int* components) const {
  if (theta.size() != design_.size())
    throw InputError("occupancy penalty: design vector of wrong size");
  if (gradient) gradient->setZero(design_.size());
  if (components) *components = 1;
  if (weights_.size() == 0) return 0.0;
  // The post-processing's own rounding and repair (post_process.cpp): F is what it fills.
  const MaterialField m = design_.to_material(theta);
  const std::vector<char>& held = design_.boundary();
  const Eigen::VectorXd rounded = round_occupancy(m.alpha, held, threshold_);
  Eigen::VectorXd repaired = rounded;
  const ConnectivityReport report = repair_connectivity(mesh_, held, repaired);
  if (components) *components = report.components_before;
  if (report.elements_added == 0) return 0.0;
  const double alpha_min = design_.options().alpha_min;
  const int o = design_.offset(DesignField::kAlpha);
  const TanhBoxMap& map = design_.map(DesignField::kAlpha);
  double R = 0;
  for (int i = 0; i < design_.num_interior(); ++i) {
    const int e = design_.interior()[i];
    if (repaired[e] == rounded[e]) continue;
    R += weights_[i] * (1.0 - m.alpha[e]) / (1.0 - alpha_min);
    if (gradient)
      (*gradient)[o + i] = -weights_[i] * map.derivative(theta[o + i]) / (1.0 - alpha_min);
  }
  return R;
}

int OccupancyPenalty::components(const Eigen::VectorXd& theta) const {
  if (theta.size() != design_.size())
    throw InputError("occupancy penalty: design vector of wrong size");
  if (weights_.size() == 0) return 1;
  const MaterialField m = design_.to_material(theta);
  const Eigen::VectorXd rounded = round_occupancy(m.alpha, design_.boundary(), threshold_);
  std::vector<char> occupied(design_.num_tets(), 0);
  for (int e = 0; e < design_.num_tets(); ++e) occupied[e] = rounded[e] == 1.0;
  std::vector<int> label;
  return label_components(adjacency_, occupied, label);
}

int OccupancyPenalty::fill_repair_paths(Eigen::VectorXd& theta) const {
  if (theta.size() != design_.size())
    throw InputError("occupancy penalty: design vector of wrong size");
  if (weights_.size() == 0) return 0;
  const MaterialField m = design_.to_material(theta);
  const std::vector<char>& held = design_.boundary();
  const Eigen::VectorXd rounded = round_occupancy(m.alpha, held, threshold_);
  Eigen::VectorXd repaired = rounded;
  if (repair_connectivity(mesh_, held, repaired).elements_added == 0) return 0;
  const int o = design_.offset(DesignField::kAlpha);
  const double theta_fill =
      design_.map(DesignField::kAlpha).inverse(0.5 * (1.0 + threshold_), "filled alpha");
  int filled = 0;
  for (int i = 0; i < design_.num_interior(); ++i) {
    const int e = design_.interior()[i];
    if (repaired[e] == rounded[e]) continue;
    theta[o + i] = theta_fill;
    ++filled;
  }
  return filled;
}

double OccupancyPenalty::grey_fraction(const Eigen::VectorXd& theta) const {
  if (theta.size() != design_.size())
    throw InputError("occupancy penalty: design vector of wrong size");
  if (weights_.size() == 0) return 0.0;
  const int o = design_.offset(DesignField::kAlpha);
  const TanhBoxMap& map = design_.map(DesignField::kAlpha);
  double grey = 0;
  for (int i = 0; i < design_.num_interior(); ++i) {
    const double alpha = map.value(theta[o + i]);
    if (alpha > 0.05 && alpha < 0.95) grey += weights_[i];
  }
  return grey;
}

}  // namespace rbaa
