#include "rbaa/scene/scene_mesh.hpp"

#include <Eigen/Geometry>

#include <sstream>

#include "rbaa/error.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/io/tet_mesh_file.hpp"
#include "rbaa/mesh/tetrahedralize.hpp"

namespace rbaa {

TetMesh make_source_mesh(const MeshSource& source, const std::string& scene_source) {
  if (!source.mesh_file.empty()) return read_tet_mesh(source.mesh_file).mesh;
  if (!source.surface_file.empty()) {
    const int target = source.target_tets > 0 ? source.target_tets : 5000;
    return mesh_surface_file(source.surface_file, target, source.volume);
  }
  if (source.shape.empty()) throw InputError(scene_source + ": the scene names no mesh");
  ShapeParameters params;
  params.radius = source.radius;
  params.side = source.side;
  return mesh_shape(source.shape, source.target_tets, params);
}

TetMesh make_scene_mesh(const Scene& scene) {
  TetMesh mesh = make_source_mesh(scene.mesh, scene.source);
  const Eigen::Vector3d centre = compute_moments(mesh, 1.0).centre_of_mass();
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(scene.rotation_angle_deg * M_PI / 180.0, scene.rotation_axis).toRotationMatrix();
  for (int i = 0; i < mesh.num_vertices(); ++i) {
    const Eigen::Vector3d x = mesh.V.row(i).transpose() - centre;
    mesh.V.row(i) = (R * x + scene.position).transpose();
  }
  for (size_t p = 0; p < scene.planes.size(); ++p) {
    const Plane& plane = scene.planes[p];
    const Eigen::VectorXd d = mesh.V * plane.normal - Eigen::VectorXd::Constant(mesh.num_vertices(), plane.offset);
    Eigen::Index worst = 0;
    const double d_min = d.minCoeff(&worst);
    if (d_min <= scene.d_hat) {
      std::ostringstream msg;
      msg << scene.source << ": the object starts " << (d_min <= 0 ? "intersecting" : "touching")
          << " obstacles.planes[" << p << "] (vertex " << worst << " at distance " << d_min
          << " m; it must start farther than d_hat = " << scene.d_hat << " m)";
      throw InputError(msg.str());
    }
  }
  return mesh;
}

}  // namespace rbaa
