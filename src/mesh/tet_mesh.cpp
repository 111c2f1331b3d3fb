#include "rbaa/mesh/tet_mesh.hpp"

#include <Eigen/Dense>

#include <cmath>
#include <sstream>

#include "rbaa/error.hpp"
#include "rbaa/mesh/topology.hpp"

namespace rbaa {

double signed_tet_volume(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                         const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
  return (b - a).cross(c - a).dot(d - a) / 6.0;
}

Eigen::VectorXd tet_volumes(const TetMesh& mesh) {
  Eigen::VectorXd vol(mesh.num_tets());
  for (int e = 0; e < mesh.num_tets(); ++e) {
    vol[e] = signed_tet_volume(mesh.V.row(mesh.T(e, 0)), mesh.V.row(mesh.T(e, 1)),
                               mesh.V.row(mesh.T(e, 2)), mesh.V.row(mesh.T(e, 3)));
  }
  return vol;
}

void validate_tet_mesh(const TetMesh& mesh, const std::string& source,
                       double relative_volume_tolerance) {
  const int nv = mesh.num_vertices();
  if (mesh.num_tets() == 0) throw InputError(source + ": mesh has no tetrahedra");
  for (int i = 0; i < nv; ++i) {
    if (!mesh.V.row(i).allFinite()) {
      std::ostringstream msg;
      msg << source << ": vertex " << i << " has a non-finite coordinate";
      throw InputError(msg.str());
    }
  }
  std::vector<char> used(nv, 0);
  for (int e = 0; e < mesh.num_tets(); ++e) {
    for (int k = 0; k < 4; ++k) {
      const int v = mesh.T(e, k);
      if (v < 0 || v >= nv) {
        std::ostringstream msg;
        msg << source << ": tet " << e << " refers to vertex " << v << " but the mesh has " << nv
            << " vertices";
        throw InputError(msg.str());
      }
      used[v] = 1;
    }
  }
  for (int i = 0; i < nv; ++i) {
    if (!used[i]) {
      std::ostringstream msg;
      msg << source << ": vertex " << i << " belongs to no tetrahedron";
      throw InputError(msg.str());
    }
  }
  const Eigen::VectorXd vol = tet_volumes(mesh);
  const double mean_abs = vol.cwiseAbs().mean();
  for (int e = 0; e < mesh.num_tets(); ++e) {
    if (!(std::abs(vol[e]) > relative_volume_tolerance * mean_abs)) {
      std::ostringstream msg;
      msg << source << ": tet " << e << " is degenerate (volume " << vol[e] << " m^3)";
      throw InputError(msg.str());
    }
    if (vol[e] < 0) {
      std::ostringstream msg;
      msg << source << ": tet " << e << " is inverted (volume " << vol[e] << " m^3)";
      throw InputError(msg.str());
    }
  }
  validate_tet_faces(mesh, source);
}

int orient_tets_positively(TetMesh& mesh) {
  const Eigen::VectorXd vol = tet_volumes(mesh);
  int flipped = 0;
  for (int e = 0; e < mesh.num_tets(); ++e) {
    if (vol[e] < 0) {
      std::swap(mesh.T(e, 2), mesh.T(e, 3));
      ++flipped;
    }
  }
  return flipped;
}

double bounding_box_diagonal(const TetMesh& mesh) {
  if (mesh.num_vertices() == 0) return 0.0;
  return (mesh.V.colwise().maxCoeff() - mesh.V.colwise().minCoeff()).norm();
}

Eigen::RowVector3d box_middle(const TetMesh& mesh) {
  return 0.5 * (mesh.V.colwise().minCoeff() + mesh.V.colwise().maxCoeff());
}

RestShape compute_rest_shape(const TetMesh& mesh, const std::string& source) {
  RestShape rest;
  const int nt = mesh.num_tets();
  rest.Dm_inv.resize(nt);
  rest.volume.resize(nt);
  for (int e = 0; e < nt; ++e) {
    const Eigen::Vector3d a = mesh.V.row(mesh.T(e, 0));
    Eigen::Matrix3d Dm;
    for (int k = 0; k < 3; ++k) Dm.col(k) = mesh.V.row(mesh.T(e, k + 1)).transpose() - a;
    const double det = Dm.determinant();
    if (!(det > 0)) {
      std::ostringstream msg;
      msg << source << ": tet " << e << " is " << (det < 0 ? "inverted" : "degenerate") << " (volume "
          << det / 6.0 << " m^3)";
      throw InputError(msg.str());
    }
    rest.volume[e] = det / 6.0;
    rest.Dm_inv[e] = Dm.inverse();
  }
  return rest;
}

}  // namespace rbaa
