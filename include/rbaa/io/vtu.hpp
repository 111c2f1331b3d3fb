#pragma once
// ParaView output: a tet mesh with per-vertex and per-element fields as a VTK XML unstructured
// grid (.vtu, ASCII, Float64), and a .pvd collection that strings .vtu files into a time series.

#include <Eigen/Core>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "rbaa/mesh/tet_mesh.hpp"

namespace rbaa {

/// Named fields for write_vtu: each matrix has one row per vertex (point data) or per tet (cell
/// data) and one column per component (1 for scalars, 3 for vectors such as displacement).
using VtuFields = std::map<std::string, Eigen::MatrixXd>;

/// Writes vertices V (#V by 3) and tets T (#T by 4) as a .vtu, atomically, with `point_data`
/// (each #V by k) and `cell_data` (each #T by k). Throws InputError naming the file and the
/// field whose row count is wrong or whose name is empty.
void write_vtu(const std::string& path, const Vertices& V, const Tets& T,
               const VtuFields& point_data = {}, const VtuFields& cell_data = {});

/// Same for a TetMesh.
void write_vtu(const std::string& path, const TetMesh& mesh, const VtuFields& point_data = {},
               const VtuFields& cell_data = {});

/// Writes a ParaView collection (.pvd) listing (time in seconds, .vtu file name relative to the
/// .pvd's directory) pairs in the given order, atomically.
void write_pvd(const std::string& path, const std::vector<std::pair<double, std::string>>& frames);

}  // namespace rbaa
