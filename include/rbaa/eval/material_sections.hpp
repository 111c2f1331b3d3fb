#pragma once
// Pictures of an object's materials: cross-sections of its tet mesh through a point (its centre
// of mass) along the three coordinate planes, each element's cut filled with its Young's modulus
// (log10), density or occupancy, with a colour bar per panel. gnuplot draws the PNG from a script
// and one data file that stay beside it (as path_plot does), so a person can restyle it.

#include <Eigen/Core>

#include <string>
#include <vector>

#include "rbaa/material/material_field.hpp"
#include "rbaa/mesh/tet_mesh.hpp"

namespace rbaa {

/// One element's cut by a coordinate plane: a triangle or a quadrilateral, corners in order around
/// it, in the plane's two remaining coordinates (increasing axis order: x = c gives (y, z)).
struct SectionPolygon {
  int element = -1;
  std::vector<Eigen::Vector2d> corners;
};

/// The cuts of every element by the plane x_axis = offset. A vertex on the plane counts as lying
/// on its positive side, so every cut has 3 or 4 corners and the cuts tile the section.
std::vector<SectionPolygon> section_polygons(const TetMesh& mesh, int axis, double offset);

/// Writes `stem`.gp, `stem`.dat and, if gnuplot is installed, renders `stem`.png: three rows
/// (log10 Y in Pa, rho alpha in kg/m^3, occupancy alpha) by three columns (the planes x, y, z
/// through `centre`). Returns the PNG path, or "" when gnuplot is missing or fails.
std::string write_material_sections(const std::string& stem, const std::string& title,
                                    const TetMesh& mesh, const MaterialField& materials,
                                    const Eigen::Vector3d& centre);

}  // namespace rbaa
