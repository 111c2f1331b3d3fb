#include "rbaa/rigid/rigid_body.hpp"

#include <LinearMath/btConvexHullComputer.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <string>

#include "rbaa/error.hpp"
#include "rbaa/mesh/topology.hpp"

namespace rbaa {

namespace {

// Unit vector with the sign that makes its largest component positive: eigen-solvers return v or
// -v at random, and two objects with equal inertia must get the same frame.
Eigen::Vector3d canonical_sign(Eigen::Vector3d v) {
  Eigen::Index i = 0;
  v.cwiseAbs().maxCoeff(&i);
  return v[i] < 0 ? Eigen::Vector3d(-v) : v;
}

// x rounded to a multiple of 2^(ilogb(scale) - bits): a power of two, so that the rounding is
// exact; 0 bits leave x as it is.
double round_to_grid(double x, double scale, int bits) {
  if (bits <= 0 || !(scale > 0) || !std::isfinite(scale)) return x;
  const double cell = std::ldexp(1.0, std::ilogb(scale) - bits);
  return std::round(x / cell) * cell;
}

}  // namespace

RigidMassProperties rigid_mass_properties(const Moments& moments, double degenerate_tolerance,
                                          int grid_bits) {
  RigidMassProperties p;
  p.mass = moments.m0;
  p.centre = moments.centre_of_mass();
  const Eigen::Matrix3d I = moments.inertia_about_centre();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(I);
  const Eigen::Vector3d lambda = eig.eigenvalues();
  const double tol = degenerate_tolerance * lambda.cwiseAbs().maxCoeff();
  const bool low_pair = lambda[1] - lambda[0] <= tol, high_pair = lambda[2] - lambda[1] <= tol;
  // Within a set of equal principal moments any orthonormal basis is principal, and the solver's
  // pick follows round-off: the reference and an adversarial object with the same inertia would get
  // frames rotated against each other, and Bullet's contact generation breaks ties between
  // symmetric support points (the star's tip edges lie flat on the floor) differently in different
  // frames. So equal moments get a canonical basis built from the mesh axes.
  Eigen::Matrix3d A;
  if (low_pair && high_pair) {
    A.setIdentity();
  } else if (low_pair || high_pair) {
    const Eigen::Vector3d axis = canonical_sign(eig.eigenvectors().col(low_pair ? 2 : 0));
    Eigen::Index m = 0;
    axis.cwiseAbs().minCoeff(&m);
    const Eigen::Vector3d e = Eigen::Vector3d::Unit(m);
    const Eigen::Vector3d u = (e - e.dot(axis) * axis).normalized();
    const Eigen::Vector3d w = axis.cross(u);
    if (low_pair)
      A << u, w, axis;
    else
      A << axis, u, w;
  } else {
    for (int k = 0; k < 3; ++k) A.col(k) = canonical_sign(eig.eigenvectors().col(k));
  }
  if (A.determinant() < 0) A.col(2) *= -1.0;
  // Two objects with the same moments up to round-off (an attack's object and its reference, or
  // their copies in a stack) must hand Bullet the same numbers: a resting stack of cubes turns a
  // 1e-16 m difference in one copy's centre into 0.5 m at the end of the cube stack demo (its
  // calibrated twins). So every value is rounded to a power-of-two grid 2^-grid_bits of its own
  // scale (the radius of gyration for the centre), and the rounded axes made orthonormal again;
  // values a grid apart stay apart, which is what rbaa evaluate's sensitivity run measures.
  if (grid_bits > 0) {
    p.mass = round_to_grid(p.mass, std::abs(p.mass), grid_bits);
    const double gyration = std::sqrt(lambda.cwiseAbs().maxCoeff() / std::abs(p.mass));
    for (int k = 0; k < 3; ++k) p.centre[k] = round_to_grid(p.centre[k], gyration, grid_bits);
    for (int k = 0; k < 3; ++k) {
      for (int i = 0; i < 3; ++i) A(i, k) = round_to_grid(A(i, k), 1.0, grid_bits);
    }
    A.col(0).normalize();
    A.col(1) = (A.col(1) - A.col(0).dot(A.col(1)) * A.col(0)).normalized();
    A.col(2) = A.col(0).cross(A.col(1));
  }
  p.principal_axes = A;
  // The principal moments in that basis (off-diagonals are round-off when the moments are equal).
  p.principal_moments = (A.transpose() * I * A).diagonal();
  for (int k = 0; k < 3; ++k) {
    p.principal_moments[k] =
        round_to_grid(p.principal_moments[k], std::abs(p.principal_moments[k]), grid_bits);
  }
  return p;
}

std::string RigidShape::describe() const {
  std::ostringstream out;
  switch (kind) {
    case RigidShapeKind::kSphere:
      out << "analytic sphere, radius " << radius << " m";
      break;
    case RigidShapeKind::kBox:
      out << "analytic box, half extents (" << half_extents.transpose() << ") m";
      break;
    case RigidShapeKind::kConvexHull:
      out << "convex hull of " << points.rows() << " extreme surface vertices";
      break;
  }
  return out.str();
}

namespace {

// The extreme points of the surface: the vertices of the convex hull of the boundary vertices,
// sorted. An adversarial object with void elements removed has cavity surfaces too, which lie
// inside the hull and must not reach the collision shape (a cavity vertex made the attacked
// ball's sphere fit fail, so it became a hull while the reference was a sphere: 5 cm apart in
// Bullet). Sorting makes the hull's point order, and so Bullet's tie-breaking between equal
// support points, independent of how the mesh numbers its vertices.
//
// Two objects with the same surface up to round-off (a reference and an attack's object placed
// by another sequence of turns and moves) must get bit-identical points: btConvexHullComputer
// works on integers, each coordinate truncated to 1/10216 of the points' extent from the middle
// of their bounding box, and the extreme points sit exactly on a cell boundary there, so the last
// bits decide their cell. Its output vertices are those integers scaled back (up to half a cell
// off the surface: 2.4e-5 m on the hoop's ball) and points in one cell merge, so one flipped cell
// moved the sphere fitted through them by 1e-7 m and put the hoop's twins 1e-6 m apart; a turned
// cube's hull got 41 vertices in place of 37 (an attack's turned twin and the reference 2 m
// apart at the backboard). So the surface vertices are first rounded to a grid of about 6e-8 of
// their extent (a power of two: the rounding is exact), which makes round-off twins equal unless
// a coordinate lies within its round-off of a half cell, and the hull's vertices are taken from
// those rounded points by index, not from the integers. Bullet still quantises the hull when it
// builds its polyhedral features (initializePolyhedralFeatures), but now of equal inputs.
Vertices hull_vertices(const TetMesh& mesh) {
  const std::vector<int> surface = boundary_vertices(mesh);
  if (surface.empty()) throw InputError("rigid shape: the mesh has no surface");
  Vertices S(static_cast<Eigen::Index>(surface.size()), 3);
  for (size_t i = 0; i < surface.size(); ++i)
    S.row(static_cast<Eigen::Index>(i)) = mesh.V.row(surface[i]);
  const Eigen::RowVector3d lo = S.colwise().minCoeff(), hi = S.colwise().maxCoeff();
  const double extent = (hi - lo).norm();
  if (!(extent > 0) || !std::isfinite(extent)) {
    throw InputError("rigid shape: the surface's bounding box has no finite positive diagonal (" +
                     std::to_string(extent) + " m)");
  }
  const double cell = std::ldexp(1.0, std::ilogb(extent) - 24);
  std::vector<std::array<double, 3>> rounded;
  rounded.reserve(surface.size());
  for (Eigen::Index i = 0; i < S.rows(); ++i) {
    rounded.push_back({std::round(S(i, 0) / cell) * cell, std::round(S(i, 1) / cell) * cell,
                       std::round(S(i, 2) / cell) * cell});
  }
  // Sorted and without repeats, so that the hull computer's input depends on the point set only.
  std::sort(rounded.begin(), rounded.end());
  rounded.erase(std::unique(rounded.begin(), rounded.end()), rounded.end());
  btConvexHullComputer hull;
  hull.compute(rounded.data()->data(), 3 * static_cast<int>(sizeof(double)),
               static_cast<int>(rounded.size()), 0.0, 0.0);
  std::vector<std::array<double, 3>> points;
  for (int i = 0; i < hull.original_vertex_index.size(); ++i) {
    points.push_back(rounded.at(static_cast<size_t>(hull.original_vertex_index[i])));
  }
  std::sort(points.begin(), points.end());
  points.erase(std::unique(points.begin(), points.end()), points.end());
  Vertices P(static_cast<Eigen::Index>(points.size()), 3);
  for (size_t i = 0; i < points.size(); ++i)
    P.row(static_cast<Eigen::Index>(i)) << points[i][0], points[i][1], points[i][2];
  return P;
}

}  // namespace

RigidShape rigid_shape_from_surface(const TetMesh& mesh, double sphere_tolerance,
                                    double box_tolerance) {
  const Vertices P = hull_vertices(mesh);
  const Eigen::RowVector3d lo = P.colwise().minCoeff(), hi = P.colwise().maxCoeff();
  const double size = (hi - lo).norm();
  RigidShape shape;

  const Eigen::RowVector3d mid = (lo + hi) / 2;
  const double tol = box_tolerance * size;
  // Box: every surface vertex on a face of its bounding box, and the box's corners present.
  bool on_faces = true;
  for (Eigen::Index i = 0; i < P.rows() && on_faces; ++i) {
    const Eigen::RowVector3d d = (P.row(i) - lo).cwiseAbs().cwiseMin((P.row(i) - hi).cwiseAbs());
    on_faces = d.minCoeff() <= tol;
  }
  int corners = 0;
  for (int c = 0; c < 8 && on_faces; ++c) {
    const Eigen::RowVector3d corner((c & 1) ? hi[0] : lo[0], (c & 2) ? hi[1] : lo[1],
                                    (c & 4) ? hi[2] : lo[2]);
    corners += ((P.rowwise() - corner).rowwise().norm().minCoeff() <= tol);
  }
  if (on_faces && corners == 8) {
    shape.kind = RigidShapeKind::kBox;
    shape.centre = mid.transpose();
    shape.half_extents = ((hi - lo) / 2).transpose();
    return shape;
  }
  // Sphere: the least-squares sphere |x|^2 = 2 c.x + k through the surface vertices, accepted
  // when every vertex lies on it.
  Eigen::MatrixXd A(P.rows(), 4);
  A << 2 * P, Eigen::VectorXd::Ones(P.rows());
  const Eigen::VectorXd b = P.rowwise().squaredNorm();
  const Eigen::Vector4d fit = A.colPivHouseholderQr().solve(b);
  const Eigen::RowVector3d centre = fit.head<3>().transpose();
  const double radius2 = fit[3] + centre.squaredNorm();
  // A few points always lie on some sphere (a cube's eight corners do): a round surface has many.
  if (radius2 > 0 && P.rows() >= 50) {
    const Eigen::VectorXd r = (P.rowwise() - centre).rowwise().norm();
    if (r.maxCoeff() - r.minCoeff() <= sphere_tolerance * size) {
      shape.kind = RigidShapeKind::kSphere;
      shape.centre = centre.transpose();
      shape.radius = r.mean();
      return shape;
    }
  }
  shape.kind = RigidShapeKind::kConvexHull;
  shape.points = P;
  return shape;
}

std::vector<RigidBody> rigid_bodies(const TetMesh& stacked, const std::vector<Body>& bodies,
                                    const Eigen::VectorXd& density) {
  if (density.size() != stacked.num_tets()) {
    throw InputError("rigid bodies: " + std::to_string(density.size()) + " densities for " +
                     std::to_string(stacked.num_tets()) + " elements");
  }
  std::vector<RigidBody> out;
  for (const Body& b : bodies) {
    if (b.vertex_begin < 0 || b.vertex_end > stacked.num_vertices() || b.num_vertices() <= 0 ||
        b.element_begin < 0 || b.element_end > stacked.num_tets() || b.num_elements() <= 0) {
      throw InputError("rigid bodies: " + b.name + "'s vertex or element range is not in the mesh");
    }
    TetMesh mesh;
    mesh.V = stacked.V.middleRows(b.vertex_begin, b.num_vertices());
    mesh.T = stacked.T.middleRows(b.element_begin, b.num_elements()).array() - b.vertex_begin;
    if (mesh.T.minCoeff() < 0 || mesh.T.maxCoeff() >= mesh.num_vertices()) {
      throw InputError("rigid bodies: " + b.name + "'s elements use vertices of another body");
    }
    RigidBody r;
    r.name = b.name;
    r.mass = rigid_mass_properties(
        compute_moments(mesh, Eigen::VectorXd(density.segment(b.element_begin, b.num_elements()))));
    r.shape = rigid_shape_from_surface(mesh);
    r.velocity = b.velocity;
    r.angular_velocity = b.angular_velocity;
    // A driven body's driven vertices carry it rigidly in the twin: a kinematic body on the same
    // prescribed motion.
    if (b.is_driven()) {
      r.kinematic = true;
      r.drive = b.drive;
      r.velocity = b.drive.point_velocity(r.mass.centre, 0.0);
      r.angular_velocity = b.drive.angular_speed(0.0) * b.drive.axis;
    }
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace rbaa
