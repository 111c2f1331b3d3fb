#pragma once
// The IPC log barrier on an unsigned distance d (SPEC section 2):
//
//   b(d) = -(d - d_hat)^2 ln(d / d_hat)  for 0 < d < d_hat,  0 for d >= d_hat,
//
// C2 at d_hat and infinite at d = 0. Applied to distances, not squared distances.

namespace rbaa::contact {

class Barrier {
 public:
  explicit Barrier(double d_hat) : d_hat_(d_hat) {}

  double d_hat() const { return d_hat_; }
  /// b(d); +infinity for d <= 0.
  double value(double d) const;
  /// b'(d) = -2 (d - d_hat) ln(d / d_hat) - (d - d_hat)^2 / d.
  double first_derivative(double d) const;
  /// b(d0 + delta) - b(d0) without subtracting two nearly equal values (a Newton step near
  /// convergence changes b in its 15th digit):
  /// -[delta (2 (d0 - d_hat) + delta) ln(d0 / d_hat) + (d0 + delta - d_hat)^2 log1p(delta / d0)].
  double difference(double d0, double delta) const;
  /// b''(d) = -2 ln(d / d_hat) - 4 (d - d_hat) / d + (d - d_hat)^2 / d^2 (positive below d_hat).
  double second_derivative(double d) const;

 private:
  double d_hat_;
};

}  // namespace rbaa::contact
