#include "rbaa/sim/gravity_form.hpp"

namespace rbaa {

GravityForm::GravityForm(const Eigen::VectorXd& vertex_masses, const Eigen::Vector3d& gravity) {
  const int nv = static_cast<int>(vertex_masses.size());
  force_.resize(3 * nv);
  for (int v = 0; v < nv; ++v) force_.segment<3>(3 * v) = vertex_masses[v] * gravity;
}

}  // namespace rbaa
