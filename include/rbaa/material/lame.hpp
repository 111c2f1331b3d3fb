#pragma once
// Lame parameters for the stable Neo-Hookean energy.

namespace rbaa {

struct LameParameters {
  double mu;      ///< shear modulus (Pa)
  double lambda;  ///< the stable Neo-Hookean's lambda (Pa), see lame_from_young_poisson
};

/// mu = Y / (2 (1 + nu)), lambda_L = Y nu / ((1 + nu)(1 - 2 nu)). The stable Neo-Hookean energy
/// mu/2 (I2 - 3) - mu (J - 1) + lambda/2 (J - 1)^2 linearises to mu |eps|^2 + (lambda - mu)/2 tr(eps)^2,
/// so lambda = lambda_L + mu reproduces (Y, nu) at small strain (SPEC section 2).
inline LameParameters lame_from_young_poisson(double Y, double nu) {
  const double mu = Y / (2.0 * (1.0 + nu));
  const double lambda_L = Y * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
  return {mu, lambda_L + mu};
}

/// d mu / dY, d mu / dnu, d lambda / dY, d lambda / dnu for the map above.
struct LameDerivatives {
  double dmu_dY, dmu_dnu, dlambda_dY, dlambda_dnu;
};

inline LameDerivatives lame_derivatives(double Y, double nu) {
  const double a = 1.0 + nu, b = 1.0 - 2.0 * nu;
  const double dmu_dY = 1.0 / (2.0 * a);
  const double dmu_dnu = -Y / (2.0 * a * a);
  // lambda_L = Y nu / (a b); d/dnu [nu / (a b)] = (a b - nu (b - 2 a)) / (a b)^2 = (1 + 2 nu^2) / (a b)^2
  const double dlamL_dY = nu / (a * b);
  const double dlamL_dnu = Y * (1.0 + 2.0 * nu * nu) / (a * a * b * b);
  return {dmu_dY, dmu_dnu, dlamL_dY + dmu_dY, dlamL_dnu + dmu_dnu};
}

}  // namespace rbaa
