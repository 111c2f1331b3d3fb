#pragma once
// Contact potential kappa B(q) = kappa sum over active pairs b(d_pair(q)) (barrier.hpp). kappa is a
// physical energy scale in J per unit of b (barrier_stiffness.hpp); the integrator multiplies the
// whole form by its h^2 weight like every other potential.

#include <Eigen/Core>

#include "rbaa/contact/barrier.hpp"
#include "rbaa/sim/contact_set.hpp"
#include "rbaa/sim/form.hpp"

namespace rbaa {

class ContactForm : public Form {
 public:
  ContactForm(ContactSet candidates, double kappa)
      : set_(std::move(candidates)), barrier_(set_.d_hat()), kappa_(kappa) {}

  const char* name() const override { return "contact"; }
  double value(const Eigen::VectorXd& q) const override;
  double value_difference(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const override;
  void add_gradient(const Eigen::VectorXd& q, double scale, Eigen::VectorXd& grad) const override;
  /// Vertex-plane blocks kappa b''(d) n n^T are PSD already (b'' > 0 below d_hat; d is linear).
  void add_hessian(const Eigen::VectorXd& q, double scale, HessianKind kind,
                   SparseHessian& hessian) const override;
  /// CCD: no vertex may close more than 90 % of its gap to a plane in one step.
  double max_step_size(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const override {
    return set_.max_step_size(q0, q1);
  }
  /// Every candidate strictly on the free side of every plane.
  bool is_step_valid(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const override {
    return set_.min_distance(q1) > 0;
  }

  /// Number of pairs closer than d_hat at q.
  int num_active_pairs(const Eigen::VectorXd& q) const;
  /// Smallest distance over every candidate pair at q.
  double min_distance(const Eigen::VectorXd& q) const { return set_.min_distance(q); }

  double kappa() const { return kappa_; }
  const ContactSet& contact_set() const { return set_; }
  const contact::Barrier& barrier() const { return barrier_; }

 private:
  // Active pairs at q, rebuilt per call: cheap for planes and keeps the form a pure function of q.
  mutable ContactSet set_;
  contact::Barrier barrier_;
  double kappa_;
};

}  // namespace rbaa
