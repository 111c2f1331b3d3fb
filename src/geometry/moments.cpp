#include "rbaa/geometry/moments.hpp"

#include <Eigen/Dense>

#include <cmath>

namespace rbaa {

MomentVector Moments::as_vector() const {
  MomentVector v;
  v << m0, m1, m2;
  return v;
}

Moments Moments::from_vector(const MomentVector& v) {
  Moments m;
  m.m0 = v[0];
  m.m1 = v.segment<3>(1);
  m.m2 = v.segment<6>(4);
  return m;
}

Eigen::Matrix3d Moments::inertia_about_origin() const {
  Eigen::Matrix3d I;
  I << m2[0], m2[3], m2[4],  //
      m2[3], m2[1], m2[5],   //
      m2[4], m2[5], m2[2];
  return I;
}

Eigen::Matrix3d Moments::inertia_about_centre() const {
  // Parallel axis: I_origin = I_centre + m0 (|c|^2 I - c c^T).
  const Eigen::Vector3d c = centre_of_mass();
  return inertia_about_origin() -
         m0 * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
}

Eigen::Matrix<double, 10, Eigen::Dynamic> moment_operator(const TetMesh& mesh) {
  const int nt = mesh.num_tets();
  Eigen::Matrix<double, 10, Eigen::Dynamic> S(10, nt);
  for (int e = 0; e < nt; ++e) {
    Eigen::Vector3d p[4];
    for (int k = 0; k < 4; ++k) p[k] = mesh.V.row(mesh.T(e, k)).transpose();
    const double vol = signed_tet_volume(p[0], p[1], p[2], p[3]);
    const Eigen::Vector3d s = p[0] + p[1] + p[2] + p[3];
    // Exact for linear tets: int x dV = V s / 4, int x x^T dV = V/20 (sum p p^T + s s^T).
    Eigen::Matrix3d xx = s * s.transpose();
    for (int k = 0; k < 4; ++k) xx += p[k] * p[k].transpose();
    xx *= vol / 20.0;
    const double tr = xx.trace();
    S(0, e) = vol;
    S.block<3, 1>(1, e) = vol * s / 4.0;
    S(4, e) = tr - xx(0, 0);
    S(5, e) = tr - xx(1, 1);
    S(6, e) = tr - xx(2, 2);
    S(7, e) = -xx(0, 1);
    S(8, e) = -xx(0, 2);
    S(9, e) = -xx(1, 2);
  }
  return S;
}

Moments compute_moments(const TetMesh& mesh, const Eigen::VectorXd& density) {
  // Sum in element order (the matrix-vector product is sequential), so results are reproducible.
  const MomentVector v = moment_operator(mesh) * density;
  return Moments::from_vector(v);
}

Moments compute_moments(const TetMesh& mesh, double density) {
  return compute_moments(mesh, Eigen::VectorXd::Constant(mesh.num_tets(), density));
}

double radius_of_gyration(const Moments& m) {
  return std::sqrt(m.inertia_about_centre().trace() / (2.0 * m.m0));
}

MomentVector moment_normalisation(const Moments& reference) {
  const double L = radius_of_gyration(reference);
  MomentVector scale;
  scale[0] = reference.m0;
  scale.segment<3>(1).setConstant(reference.m0 * L);
  scale.segment<6>(4).setConstant(reference.m0 * L * L);
  return scale;
}

}  // namespace rbaa
