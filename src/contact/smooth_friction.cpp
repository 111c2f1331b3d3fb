#include "rbaa/contact/smooth_friction.hpp"

namespace rbaa::contact {

double smooth_friction_f0(double y, double eps) {
  return y < eps ? -y * y * y / (3 * eps * eps) + y * y / eps + eps / 3 : y;
}

double smooth_friction_f1_over_y(double y, double eps) {
  return y < eps ? 2.0 / eps - y / (eps * eps) : 1.0 / y;
}

double smooth_friction_c1(double y, double eps) {
  if (y < eps) return y > 0 ? -1.0 / (eps * eps * y) : 0.0;
  return -1.0 / (y * y * y);
}

double smooth_friction_f0_difference(double y0, double y1, double dy, double eps) {
  if (y0 >= eps && y1 >= eps) return dy;
  // f0(y1) - f0(y0) = (y1 - y0) [(y0 + y1) / eps - (y0^2 + y0 y1 + y1^2) / (3 eps^2)].
  if (y0 < eps && y1 < eps) {
    return dy * ((y0 + y1) / eps - (y0 * y0 + y0 * y1 + y1 * y1) / (3 * eps * eps));
  }
  return smooth_friction_f0(y1, eps) - smooth_friction_f0(y0, eps);
}

}  // namespace rbaa::contact
