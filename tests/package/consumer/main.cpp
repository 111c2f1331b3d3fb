// Use of the installed library from outside rbaa's tree: the moments of a unit box at density 1,
// and the attack's moment term driven through Ceres' own interface (its public header is a Ceres
// class, so the package must bring Ceres along).
#include <ceres/cost_function.h>
#include <rbaa/geometry/moments.hpp>
#include <rbaa/material/design_space.hpp>
#include <rbaa/mesh/grid_mesh.hpp>
#include <rbaa/opt/moment_cost.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>

int main() {
  const rbaa::TetMesh mesh = rbaa::box_tet_mesh({0, 0, 0}, {1, 1, 1}, 2, 2, 2);
  const rbaa::Moments m = rbaa::compute_moments(mesh, 1.0);
  std::cout << "m0 = " << m.m0 << "\n";
  if (std::abs(m.m0 - 1.0) > 1e-12) return 1;

  // The unperturbed design has the reference's uniform density: every residual is round-off.
  const rbaa::DesignSpace design(mesh, rbaa::DesignSpaceOptions{});
  const rbaa::MomentCostFunction moment_term(mesh, design, rbaa::compute_moments(mesh, 2500.0));
  const ceres::CostFunction& cost = moment_term;
  const Eigen::VectorXd theta = design.initial_theta(/*perturb=*/false);
  const double* parameters[] = {theta.data()};
  double residuals[10];
  if (cost.num_residuals() != 10 || !cost.Evaluate(parameters, residuals, nullptr)) return 2;
  double largest = 0;
  for (double r : residuals) largest = std::max(largest, std::abs(r));
  std::cout << "largest moment residual = " << largest << "\n";
  return largest < 1e-12 ? 0 : 3;
}
