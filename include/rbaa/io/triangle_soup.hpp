#pragma once
// Triangles from a surface file, open or closed, without the checks tetrahedralisation needs
// (read_surface in mesh/surface.hpp adds those: closed, manifold, not self-intersecting). For
// static obstacles: a backboard may be one rectangle.
//
// OBJ and OFF are parsed here line by line, so that a malformed file is one error naming file, line
// and value ("rim.obj:12: expected vertex z (a number), found 'x'"); STL and PLY (often binary)
// go through CGAL's polygon-soup reader like read_surface, whose errors name the file only.
// Polygons with more than three corners are fanned from their first corner, as read_surface does.

#include <string>

#include "rbaa/mesh/surface.hpp"

namespace rbaa {

/// Reads OBJ (v and f records; f corners "i", "i/t", "i//n", "i/t/n", negative indices relative),
/// OFF, STL or PLY. Checks: readable, at least one triangle, finite coordinates, indices in range,
/// no triangle with a repeated corner or zero area. V is #V by 3, F is #F by 3. Throws
/// rbaa::InputError "FILE[:LINE]: what is wrong".
SurfaceMesh read_triangle_soup(const std::string& path);

}  // namespace rbaa
