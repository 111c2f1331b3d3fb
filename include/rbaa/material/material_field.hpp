#pragma once
// Per-element materials: Young's modulus Y (Pa), Poisson's ratio nu, density rho (kg/m^3) and
// occupancy alpha in [alpha_min, 1]. Mass scales with rho alpha, stiffness with alpha^3.

#include <Eigen/Core>

#include <string>

namespace rbaa {

struct MaterialField {
  Eigen::VectorXd Y;      ///< #T Young's moduli (Pa)
  Eigen::VectorXd nu;     ///< #T Poisson's ratios
  Eigen::VectorXd rho;    ///< #T densities (kg/m^3)
  Eigen::VectorXd alpha;  ///< #T occupancies

  int size() const { return static_cast<int>(Y.size()); }

  /// A uniform field of `num_tets` elements.
  static MaterialField uniform(int num_tets, double Y, double nu, double rho, double alpha = 1.0);

  /// Density per unit volume that the mass sees: rho alpha (#T).
  Eigen::VectorXd effective_density() const { return rho.cwiseProduct(alpha); }
};

/// Material-space gradient dC/dY, dC/dnu, dC/drho, dC/dalpha, each #T (an empty vector means zero).
/// Also a direction in material space (the tangent-linear pass).
struct MaterialGradient {
  Eigen::VectorXd Y, nu, rho, alpha;
};

/// Throws rbaa::InputError naming `source` when the field does not have `num_tets` entries in
/// every array, or holds a non-finite or physically meaningless value (Y <= 0, nu outside
/// (-1, 0.5), rho <= 0, alpha outside (0, 1]).
void validate_material_field(const MaterialField& field, int num_tets, const std::string& source);

}  // namespace rbaa
