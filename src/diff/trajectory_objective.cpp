#include "rbaa/diff/trajectory_objective.hpp"

#include <cmath>

#include "rbaa/error.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/sim/mass_matrix.hpp"
#include "rbaa/sim/sparse_hessian.hpp"

namespace rbaa {

namespace {

void add_vector(Eigen::VectorXd& to, double scale, const Eigen::VectorXd& from) {
  if (from.size() == 0) return;
  if (to.size() == 0) {
    to = scale * from;
  } else {
    to += scale * from;
  }
}

}  // namespace

void add_scaled(TrajectorySeed& to, double scale, const TrajectorySeed& from) {
  if (to.dq.size() < from.dq.size()) to.dq.resize(from.dq.size());
  for (std::size_t k = 0; k < from.dq.size(); ++k) add_vector(to.dq[k], scale, from.dq[k]);
  add_vector(to.direct.Y, scale, from.direct.Y);
  add_vector(to.direct.nu, scale, from.direct.nu);
  add_vector(to.direct.rho, scale, from.direct.rho);
  add_vector(to.direct.alpha, scale, from.direct.alpha);
}

UndirectedTrajectoryObjective::UndirectedTrajectoryObjective(Eigen::SparseMatrix<double> reference_mass,
                                                             Eigen::VectorXd reference_final,
                                                             double m0_ref, double L)
    : M_(std::move(reference_mass)), q_ref_(std::move(reference_final)), m0_(m0_ref), L_(L) {
  if (M_.rows() != q_ref_.size() || M_.cols() != q_ref_.size()) {
    throw InputError("trajectory objective: the reference mass matrix does not fit its positions");
  }
  if (!(m0_ > 0) || !(L_ > 0)) {
    throw InputError("trajectory objective: the reference mass and radius of gyration must be positive");
  }
}

std::shared_ptr<UndirectedTrajectoryObjective> UndirectedTrajectoryObjective::from_reference(
    const TetMesh& rest, double reference_rho, const Eigen::VectorXd& reference_final) {
  SparseHessian pattern(rest.T, rest.num_vertices());
  const Eigen::VectorXd density = Eigen::VectorXd::Constant(rest.num_tets(), reference_rho);
  Eigen::SparseMatrix<double> M = mass_matrix(rest, density, MassModel::kConsistent, pattern);
  const Moments m = compute_moments(rest, reference_rho);
  return std::make_shared<UndirectedTrajectoryObjective>(std::move(M), reference_final, m.m0,
                                                         radius_of_gyration(m));
}

std::shared_ptr<UndirectedTrajectoryObjective> UndirectedTrajectoryObjective::from_reference(
    const TetMesh& rest, double reference_rho, const Eigen::VectorXd& reference_final,
    const Body& body) {
  if (body.element_begin == 0 && body.element_end == rest.num_tets() && body.vertex_begin == 0 &&
      body.vertex_end == rest.num_vertices()) {
    return from_reference(rest, reference_rho, reference_final);
  }
  if (body.element_begin < 0 || body.element_end > rest.num_tets() ||
      body.element_begin >= body.element_end) {
    throw InputError("trajectory objective: body " + body.name + " has no elements in the mesh");
  }
  // The other bodies' elements weigh nothing: Mref and the moments are the body's alone.
  Eigen::VectorXd density = Eigen::VectorXd::Zero(rest.num_tets());
  density.segment(body.element_begin, body.num_elements()).setConstant(reference_rho);
  SparseHessian pattern(rest.T, rest.num_vertices());
  Eigen::SparseMatrix<double> M = mass_matrix(rest, density, MassModel::kConsistent, pattern);
  const Moments m = compute_moments(rest, density);
  return std::make_shared<UndirectedTrajectoryObjective>(std::move(M), reference_final, m.m0,
                                                         radius_of_gyration(m));
}

double UndirectedTrajectoryObjective::evaluate(const Trajectory& trajectory, const MaterialField&,
                                               TrajectorySeed* seed) const {
  const int N = trajectory.num_steps();
  const Eigen::VectorXd& q = trajectory.q.back();
  if (q.size() != q_ref_.size()) {
    throw InputError("trajectory objective: the trajectory and the reference differ in size");
  }
  const Eigen::VectorXd d = q - q_ref_;
  const Eigen::VectorXd Md = M_.selfadjointView<Eigen::Lower>() * d;
  const double scale = 1.0 / (m0_ * L_ * L_);
  if (seed != nullptr) {
    *seed = TrajectorySeed::empty(N);
    seed->dq[N] = (-2.0 * scale) * Md;
  }
  return -scale * d.dot(Md);
}

double UndirectedTrajectoryObjective::gap(const Eigen::VectorXd& q_final) const {
  const Eigen::VectorXd d = q_final - q_ref_;
  return std::sqrt(std::max(0.0, d.dot(M_.selfadjointView<Eigen::Lower>() * d)) / m0_);
}

CentreOfMassObservable::CentreOfMassObservable(const TetMesh& rest,
                                               const Eigen::Vector3d& direction, int step)
    : tets_(rest.T),
      volumes_(tet_volumes(rest)),
      num_vertices_(rest.num_vertices()),
      num_tets_(rest.num_tets()),
      element_begin_(0),
      element_end_(rest.num_tets()),
      vertex_begin_(0),
      vertex_end_(rest.num_vertices()),
      direction_(direction),
      step_(step) {}

CentreOfMassObservable::CentreOfMassObservable(const TetMesh& rest, const Body& body,
                                               const Eigen::Vector3d& direction, int step)
    : CentreOfMassObservable(rest, direction, step) {
  if (body.element_begin < 0 || body.element_end > num_tets_ ||
      body.element_begin >= body.element_end || body.vertex_begin < 0 ||
      body.vertex_end > num_vertices_ || body.vertex_begin >= body.vertex_end) {
    throw InputError("centre-of-mass observable: body " + body.name +
                     " is not a range of the mesh");
  }
  element_begin_ = body.element_begin;
  element_end_ = body.element_end;
  vertex_begin_ = body.vertex_begin;
  vertex_end_ = body.vertex_end;
}

double CentreOfMassObservable::evaluate(const Trajectory& trajectory, const MaterialField& materials,
                                        TrajectorySeed* gradient) const {
  const int N = trajectory.num_steps();
  const int k = step_ < 0 ? N + 1 + step_ : step_;
  if (k < 0 || k > N) throw InputError("centre-of-mass observable: step out of range");
  const Eigen::VectorXd& q = trajectory.q[k];
  const int nt = num_tets_;
  // Vertex masses m_i = sum_e rho_e alpha_e V_e / 4 (the row sums of either mass matrix), of the
  // body's elements (whose vertices are the body's).
  Eigen::VectorXd mv = Eigen::VectorXd::Zero(num_vertices_);
  double total = 0;
  for (int e = element_begin_; e < element_end_; ++e) {
    const double me = materials.rho[e] * materials.alpha[e] * volumes_[e];
    total += me;
    for (int a = 0; a < 4; ++a) mv[tets_(e, a)] += me / 4.0;
  }
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  for (int i = vertex_begin_; i < vertex_end_; ++i) com += mv[i] * q.segment<3>(3 * i);
  com /= total;
  const double value = direction_.dot(com);
  if (gradient != nullptr) {
    *gradient = TrajectorySeed::empty(N);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(3 * num_vertices_);
    for (int i = vertex_begin_; i < vertex_end_; ++i) {
      g.segment<3>(3 * i) = (mv[i] / total) * direction_;
    }
    gradient->dq[k] = g;
    // d value / d m_e = direction . (mean of e's vertices - com) / total.
    gradient->direct.rho = Eigen::VectorXd::Zero(nt);
    gradient->direct.alpha = Eigen::VectorXd::Zero(nt);
    for (int e = element_begin_; e < element_end_; ++e) {
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (int a = 0; a < 4; ++a) mean += q.segment<3>(3 * tets_(e, a)) / 4.0;
      const double dm = direction_.dot(mean - com) / total;
      gradient->direct.rho[e] = dm * materials.alpha[e] * volumes_[e];
      gradient->direct.alpha[e] = dm * materials.rho[e] * volumes_[e];
    }
  }
  return value;
}

double DirectedObjective::evaluate(const Trajectory& trajectory, const MaterialField& materials,
                                   TrajectorySeed* seed) const {
  double value = 0;
  if (seed != nullptr) *seed = TrajectorySeed::empty(trajectory.num_steps());
  for (const Term& t : terms_) {
    TrajectorySeed g;
    const double o = t.observable->evaluate(trajectory, materials, seed != nullptr ? &g : nullptr);
    value += t.weight * (o - t.target) * (o - t.target);
    if (seed != nullptr) add_scaled(*seed, 2.0 * t.weight * (o - t.target), g);
  }
  return value;
}

}  // namespace rbaa
