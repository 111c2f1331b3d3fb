#pragma once
// The tanh box map that keeps a design variable inside its physical range (SPEC section 4):
// x = 1/2 tanh(theta) (x_max - x_min) + 1/2 (x_max + x_min), so every theta maps into the open
// interval (x_min, x_max) and the optimiser works unconstrained in theta.

#include <string>

namespace rbaa {

class TanhBoxMap {
 public:
  TanhBoxMap() = default;
  /// Throws rbaa::InputError naming `name` unless lo < hi are finite.
  TanhBoxMap(double lo, double hi, const std::string& name = "range");

  double lo() const { return lo_; }
  double hi() const { return hi_; }
  double mid() const { return 0.5 * (lo_ + hi_); }

  /// x(theta) = 1/2 tanh(theta) (hi - lo) + 1/2 (hi + lo).
  double value(double theta) const;
  /// dx/dtheta = 1/2 (1 - tanh(theta)^2) (hi - lo).
  double derivative(double theta) const;
  /// theta(x) = atanh((2 x - hi - lo) / (hi - lo)); throws rbaa::InputError naming `what` unless
  /// lo < x < hi (the ends would need theta = +-infinity).
  double inverse(double x, const std::string& what = "value") const;

 private:
  double lo_ = -1.0, hi_ = 1.0;
  std::string name_ = "range";
};

}  // namespace rbaa
