#include "rbaa/contact/tangent_frame.hpp"

#include <ceres/jet.h>

#include <Eigen/Geometry>
#include <cmath>

// One template per frame, evaluated in double for the frame and in ceres::Jet<double, 12> (value
// plus the 12 partial derivatives) for its Jacobian, so that the two never disagree.

namespace rbaa::contact {
namespace {

using Jet = ceres::Jet<double, 12>;
template <typename S>
using Vec3 = Eigen::Matrix<S, 3, 1>;
template <typename S>
using Mat32 = Eigen::Matrix<S, 3, 2>;

double value_of(double s) { return s; }
double value_of(const Jet& s) { return s.a; }

template <typename S>
Vec3<S> normalised(const Vec3<S>& v) {
  using std::sqrt;
  return v / sqrt(v.dot(v));
}

template <typename S>
Mat32<S> point_point_basis(const Vec3<S>& p, const Vec3<S>& q) {
  const Vec3<S> n = p - q;
  const Vec3<S> x = Vec3<S>(S(1.0), S(0.0), S(0.0)).cross(n);
  const Vec3<S> y = Vec3<S>(S(0.0), S(1.0), S(0.0)).cross(n);
  double xx = 0, yy = 0;
  for (int i = 0; i < 3; ++i) {
    xx += value_of(x[i]) * value_of(x[i]);
    yy += value_of(y[i]) * value_of(y[i]);
  }
  const Vec3<S> t0 = normalised<S>(xx > yy ? x : y);
  Mat32<S> T;
  T.col(0) = t0;
  T.col(1) = normalised<S>(n.cross(t0));
  return T;
}

template <typename S>
Mat32<S> point_edge_basis(const Vec3<S>& p, const Vec3<S>& e0, const Vec3<S>& e1) {
  const Vec3<S> e = e1 - e0;
  Mat32<S> T;
  T.col(0) = normalised<S>(e);
  T.col(1) = normalised<S>(e.cross(p - e0));
  return T;
}

template <typename S>
Mat32<S> point_triangle_basis(const Vec3<S>& t0, const Vec3<S>& t1, const Vec3<S>& t2) {
  const Vec3<S> e0 = t1 - t0;
  const Vec3<S> n = e0.cross(t2 - t0);
  Mat32<S> T;
  T.col(0) = normalised<S>(e0);
  T.col(1) = normalised<S>(n.cross(e0));
  return T;
}

template <typename S>
Mat32<S> edge_edge_basis(const Vec3<S>& ea0, const Vec3<S>& ea1, const Vec3<S>& eb0,
                         const Vec3<S>& eb1) {
  const Vec3<S> a = ea1 - ea0;
  const Vec3<S> n = a.cross(eb1 - eb0);
  Mat32<S> T;
  T.col(0) = normalised<S>(a);
  T.col(1) = normalised<S>(n.cross(a));
  return T;
}

// Parameter of the projection of p onto the line e0 + alpha (e1 - e0).
template <typename S>
S line_parameter(const Vec3<S>& p, const Vec3<S>& e0, const Vec3<S>& e1) {
  const Vec3<S> e = e1 - e0;
  return (p - e0).dot(e) / e.dot(e);
}

template <typename S>
struct Frame {
  S gamma[4];
  Mat32<S> basis;
};

// Point indices: p = 0, t0 = 1, t1 = 2, t2 = 3.
template <typename S>
Frame<S> point_triangle_frame(const Vec3<S> x[4], PointTriangleDistanceType type) {
  using T = PointTriangleDistanceType;
  Frame<S> f;
  for (S& g : f.gamma) g = S(0.0);
  f.gamma[0] = S(1.0);
  switch (type) {
    case T::P_T0:
    case T::P_T1:
    case T::P_T2: {
      const int c = 1 + static_cast<int>(type) - static_cast<int>(T::P_T0);
      f.gamma[c] = S(-1.0);
      f.basis = point_point_basis<S>(x[0], x[c]);
      return f;
    }
    case T::P_E0:
    case T::P_E1:
    case T::P_E2: {
      const int e = static_cast<int>(type) - static_cast<int>(T::P_E0);  // E0 = t0t1, ...
      const int a = 1 + e, b = 1 + (e + 1) % 3;
      const S alpha = line_parameter<S>(x[0], x[a], x[b]);
      f.gamma[a] = alpha - S(1.0);
      f.gamma[b] = -alpha;
      f.basis = point_edge_basis<S>(x[0], x[a], x[b]);
      return f;
    }
    case T::P_T:
      break;
  }
  // Barycentric (b1, b2) of p's projection: [e1.e1 e1.e2; e1.e2 e2.e2] b = [e1.w; e2.w].
  const Vec3<S> e1 = x[2] - x[1], e2 = x[3] - x[1], w = x[0] - x[1];
  const S a11 = e1.dot(e1), a12 = e1.dot(e2), a22 = e2.dot(e2);
  const S r1 = e1.dot(w), r2 = e2.dot(w);
  const S det = a11 * a22 - a12 * a12;
  const S b1 = (a22 * r1 - a12 * r2) / det, b2 = (a11 * r2 - a12 * r1) / det;
  f.gamma[1] = b1 + b2 - S(1.0);
  f.gamma[2] = -b1;
  f.gamma[3] = -b2;
  f.basis = point_triangle_basis<S>(x[1], x[2], x[3]);
  return f;
}

// Point indices: ea0 = 0, ea1 = 1, eb0 = 2, eb1 = 3; r = (ea0 + s a) - (eb0 + t b).
template <typename S>
Frame<S> edge_edge_frame(const Vec3<S> x[4], EdgeEdgeDistanceType type) {
  using T = EdgeEdgeDistanceType;
  Frame<S> f;
  for (S& g : f.gamma) g = S(0.0);
  auto endpoints = [&](int i, int j) {  // ea_i against eb_j
    f.gamma[i] = S(1.0);
    f.gamma[2 + j] = S(-1.0);
    f.basis = point_point_basis<S>(x[i], x[2 + j]);
  };
  auto point_on_a = [&](int j) {  // eb_j against the line of a
    const S s = line_parameter<S>(x[2 + j], x[0], x[1]);
    f.gamma[0] = S(1.0) - s;
    f.gamma[1] = s;
    f.gamma[2 + j] = S(-1.0);
    f.basis = point_edge_basis<S>(x[2 + j], x[0], x[1]);
  };
  auto point_on_b = [&](int i) {  // ea_i against the line of b
    const S t = line_parameter<S>(x[i], x[2], x[3]);
    f.gamma[i] = S(1.0);
    f.gamma[2] = t - S(1.0);
    f.gamma[3] = -t;
    f.basis = point_edge_basis<S>(x[i], x[2], x[3]);
  };
  switch (type) {
    case T::EA0_EB0:
      endpoints(0, 0);
      return f;
    case T::EA0_EB1:
      endpoints(0, 1);
      return f;
    case T::EA1_EB0:
      endpoints(1, 0);
      return f;
    case T::EA1_EB1:
      endpoints(1, 1);
      return f;
    case T::EA_EB0:
      point_on_a(0);
      return f;
    case T::EA_EB1:
      point_on_a(1);
      return f;
    case T::EA0_EB:
      point_on_b(0);
      return f;
    case T::EA1_EB:
      point_on_b(1);
      return f;
    case T::EA_EB:
      break;
  }
  // Minimiser of |w + s a - t b|^2, w = ea0 - eb0: [a.a -a.b; -a.b b.b] (s, t) = (-a.w, b.w).
  const Vec3<S> a = x[1] - x[0], b = x[3] - x[2], w = x[0] - x[2];
  const S aa = a.dot(a), ab = a.dot(b), bb = b.dot(b), aw = a.dot(w), bw = b.dot(w);
  const S det = aa * bb - ab * ab;
  const S s = (ab * bw - bb * aw) / det, t = (aa * bw - ab * aw) / det;
  f.gamma[0] = S(1.0) - s;
  f.gamma[1] = s;
  f.gamma[2] = t - S(1.0);
  f.gamma[3] = -t;
  f.basis = edge_edge_basis<S>(x[0], x[1], x[2], x[3]);
  return f;
}

TangentFrame to_frame(const Frame<double>& f) {
  TangentFrame out;
  for (int i = 0; i < 4; ++i) out.gamma[i] = f.gamma[i];
  out.basis = f.basis;
  return out;
}

TangentFrameJacobian to_jacobian(const Frame<Jet>& f) {
  TangentFrameJacobian J;
  for (int i = 0; i < 4; ++i) J.gamma.row(i) = f.gamma[i].v.transpose();
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 3; ++i) J.basis.row(3 * j + i) = f.basis(i, j).v.transpose();
  return J;
}

// The pair's points as Jets seeded with the identity: point i coordinate c is variable 3 i + c.
void seeded(const Eigen::Vector3d* in[4], Vec3<Jet> out[4]) {
  for (int i = 0; i < 4; ++i)
    for (int c = 0; c < 3; ++c) out[i][c] = Jet((*in[i])[c], 3 * i + c);
}

}  // namespace

TangentFrame point_triangle_tangent_frame(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                                          const Eigen::Vector3d& t1, const Eigen::Vector3d& t2,
                                          PointTriangleDistanceType type) {
  const Eigen::Vector3d x[4] = {p, t0, t1, t2};
  return to_frame(point_triangle_frame<double>(x, type));
}

TangentFrame edge_edge_tangent_frame(const Eigen::Vector3d& ea0, const Eigen::Vector3d& ea1,
                                     const Eigen::Vector3d& eb0, const Eigen::Vector3d& eb1,
                                     EdgeEdgeDistanceType type) {
  const Eigen::Vector3d x[4] = {ea0, ea1, eb0, eb1};
  return to_frame(edge_edge_frame<double>(x, type));
}

TangentFrameJacobian point_triangle_tangent_frame_jacobian(const Eigen::Vector3d& p,
                                                           const Eigen::Vector3d& t0,
                                                           const Eigen::Vector3d& t1,
                                                           const Eigen::Vector3d& t2,
                                                           PointTriangleDistanceType type) {
  const Eigen::Vector3d* in[4] = {&p, &t0, &t1, &t2};
  Vec3<Jet> x[4];
  seeded(in, x);
  return to_jacobian(point_triangle_frame<Jet>(x, type));
}

TangentFrameJacobian edge_edge_tangent_frame_jacobian(const Eigen::Vector3d& ea0,
                                                      const Eigen::Vector3d& ea1,
                                                      const Eigen::Vector3d& eb0,
                                                      const Eigen::Vector3d& eb1,
                                                      EdgeEdgeDistanceType type) {
  const Eigen::Vector3d* in[4] = {&ea0, &ea1, &eb0, &eb1};
  Vec3<Jet> x[4];
  seeded(in, x);
  return to_jacobian(edge_edge_frame<Jet>(x, type));
}

}  // namespace rbaa::contact
