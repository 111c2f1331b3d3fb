#include "rbaa/opt/post_process.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace rbaa {

SolidObject remove_void_elements(const TetMesh& mesh, const MaterialField& field) {
  SolidObject out;
  std::vector<int> new_index(mesh.num_vertices(), -1);
  for (int e = 0; e < mesh.num_tets(); ++e) {
    if (field.alpha[e] > 0) {
      out.element_origin.push_back(e);
      for (int k = 0; k < 4; ++k) new_index[mesh.T(e, k)] = 0;
    }
  }
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (new_index[v] == 0) {
      new_index[v] = static_cast<int>(out.vertex_origin.size());
      out.vertex_origin.push_back(v);
    }
  }
  const int nt = static_cast<int>(out.element_origin.size());
  out.mesh.V.resize(static_cast<Eigen::Index>(out.vertex_origin.size()), 3);
  for (size_t i = 0; i < out.vertex_origin.size(); ++i) {
    out.mesh.V.row(static_cast<Eigen::Index>(i)) = mesh.V.row(out.vertex_origin[i]);
  }
  out.mesh.T.resize(nt, 4);
  out.materials = MaterialField::uniform(nt, 0, 0, 0, 0);
  for (int i = 0; i < nt; ++i) {
    const int e = out.element_origin[i];
    for (int k = 0; k < 4; ++k) out.mesh.T(i, k) = new_index[mesh.T(e, k)];
    out.materials.Y[i] = field.Y[e];
    out.materials.nu[i] = field.nu[e];
    out.materials.rho[i] = field.rho[e];
    out.materials.alpha[i] = field.alpha[e];
  }
  return out;
}

PostProcessResult post_process(const TetMesh& mesh, const DesignSpace& design,
                               const MaterialField& continuous, const Moments& reference,
                               double threshold) {
  PostProcessResult r;
  r.rounded = continuous;
  if (design.optimises(DesignField::kAlpha)) {
    // The design's held elements: boundary ones and those of its solid vertices (a driven body's
    // driven vertices), so that every driven vertex stays in the object.
    const std::vector<char>& solid = design.boundary();
    r.rounded.alpha = round_occupancy(continuous.alpha, solid, threshold);
    r.connectivity = repair_connectivity(mesh, solid, r.rounded.alpha);
  } else {
    r.connectivity.components_before = r.connectivity.components_after = 1;
  }
  const Eigen::VectorXd volume = tet_volumes(mesh);
  double void_volume = 0;
  for (int e = 0; e < mesh.num_tets(); ++e) void_volume += (r.rounded.alpha[e] == 0) ? volume[e] : 0.0;
  r.void_fraction = void_volume / volume.sum();

  const MomentVector scale = moment_normalisation(reference);
  const MomentVector before = compute_moments(mesh, r.rounded.effective_density()).as_vector();
  r.max_residual_before_refit =
      ((before - reference.as_vector()).array() / scale.array()).abs().maxCoeff();

  r.refit = refit_density(mesh, r.rounded.alpha, r.rounded.rho, reference, design.map(DesignField::kRho));
  r.rounded.rho = r.refit.rho;
  r.solid = remove_void_elements(mesh, r.rounded);
  return r;
}

}  // namespace rbaa
