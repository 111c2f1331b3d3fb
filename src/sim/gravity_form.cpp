#include "rbaa/sim/gravity_form.hpp"

#include "rbaa/sim/parallel.hpp"

namespace rbaa {

GravityForm::GravityForm(const Eigen::VectorXd& vertex_masses, const Eigen::Vector3d& gravity,
                         UnitElementMass unit)
    : unit_(std::move(unit)) {
  const int nv = static_cast<int>(vertex_masses.size());
  force_.resize(3 * nv);
  gravity_.resize(3 * nv);
  for (int v = 0; v < nv; ++v) {
    force_.segment<3>(3 * v) = vertex_masses[v] * gravity;
    gravity_.segment<3>(3 * v) = gravity;
  }
}

void GravityForm::add_material_adjoint(const Eigen::VectorXd& x, const Eigen::VectorXd& a,
                                       double scale, const MaterialField& materials,
                                       MaterialGradient& g) const {
  const int nt = unit_.num_elements();
#pragma omp parallel for schedule(static) if (nt > kParallelCheapElements)
  for (int e = 0; e < nt; ++e) {
    unit_.add_mass_gradient(e, scale * unit_.product(e, a, gravity_), materials, g);
  }
}

void GravityForm::add_material_tangent(const Eigen::VectorXd& x, const MaterialGradient& direction,
                                       double scale, const MaterialField& materials,
                                       Eigen::VectorXd& out) const {
  if (direction.rho.size() == 0 && direction.alpha.size() == 0) return;
  for (int e = 0; e < unit_.num_elements(); ++e) {
    const double dm = unit_.mass_change(e, materials, direction);
    if (dm != 0.0) unit_.add_times(e, -scale * dm, gravity_, out);
  }
}

}  // namespace rbaa
