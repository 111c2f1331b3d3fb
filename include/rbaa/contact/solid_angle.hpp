#pragma once
// Solid angle of a triangle surface seen from a point, for inside tests: a closed surface with
// outward normals subtends 4 pi at a point inside it and 0 at a point outside (the winding number
// times 4 pi), robustly enough to tell the two apart by comparing |omega| with 2 pi.

#include <Eigen/Core>

#include "rbaa/contact/broad_phase.hpp"

namespace rbaa::contact {

/// Signed solid angle (sr) of triangle (a, b, c) seen from p (Van Oosterom and Strackee 1983).
double solid_angle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                   const Eigen::Vector3d& c);

/// Sum of the solid angles of triangles F (#F by 3, rows of V, #V by 3) seen from p.
double surface_solid_angle(const Eigen::Vector3d& p, const Eigen::Ref<const Positions>& V,
                           const Eigen::Ref<const Triangles>& F);

}  // namespace rbaa::contact
