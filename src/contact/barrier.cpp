#include "rbaa/contact/barrier.hpp"

#include <cmath>
#include <limits>

namespace rbaa::contact {

double Barrier::value(double d) const {
  if (d <= 0) return std::numeric_limits<double>::infinity();
  if (d >= d_hat_) return 0.0;
  const double e = d - d_hat_;
  return -e * e * std::log(d / d_hat_);
}

double Barrier::first_derivative(double d) const {
  if (d >= d_hat_) return 0.0;
  const double e = d - d_hat_;
  return -2.0 * e * std::log(d / d_hat_) - e * e / d;
}

double Barrier::difference(double d0, double delta) const {
  const double d1 = d0 + delta;
  if (d1 <= 0) return std::numeric_limits<double>::infinity();
  if (d0 >= d_hat_ || d1 >= d_hat_) return value(d1) - value(d0);  // one side is exactly 0
  const double e0 = d0 - d_hat_, e1 = d1 - d_hat_;
  return -(delta * (2.0 * e0 + delta) * std::log(d0 / d_hat_) + e1 * e1 * std::log1p(delta / d0));
}

double Barrier::second_derivative(double d) const {
  if (d >= d_hat_) return 0.0;
  const double e = d - d_hat_;
  return -2.0 * std::log(d / d_hat_) - 4.0 * e / d + e * e / (d * d);
}

}  // namespace rbaa::contact
