#pragma once
// The paper's reference shapes as closed triangle surfaces (SPEC section 7), centred so that
// CGAL can tetrahedralise them. All lengths in metres.

#include <string>
#include <utility>
#include <vector>

#include "rbaa/mesh/surface.hpp"

namespace rbaa {

/// Icosphere of the given radius centred at the origin (20 * 4^subdivisions triangles).
SurfaceMesh sphere_surface(double radius, int subdivisions = 5);

/// Axis-aligned cube of side `side` centred at the origin.
SurfaceMesh cube_surface(double side);

/// Prism over a `points`-pointed star in the yz-plane (outer radius, inner radius; one tip on +z),
/// extruded `thickness` along x and centred at the origin.
SurfaceMesh star_surface(double outer_radius = 1.0, double inner_radius = 0.4,
                         double thickness = 0.3, int points = 5);

/// Surface of revolution about +z of a profile of (z, r) points (z increasing, r > 0), closed by
/// flat caps at the first and last z, with `segments` facets around.
SurfaceMesh lathe_surface(const std::vector<std::pair<double, double>>& profile, int segments);

/// The bat's lathe profile (z, r) of SPEC section 7: knob at the origin, barrel towards +z.
std::vector<std::pair<double, double>> bat_profile();

}  // namespace rbaa
