#include "rbaa/io/tetgen.hpp"

#include <array>
#include <vector>

#include "rbaa/error.hpp"
#include "rbaa/io/atomic_file.hpp"
#include "rbaa/io/number_text.hpp"
#include "rbaa/io/tet_mesh_file.hpp"
#include "rbaa/io/text_reader.hpp"

namespace rbaa {

namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

struct NodeFile {
  std::vector<double> coords;
  int base = 0;
};

NodeFile read_node_file(const std::string& path) {
  TextReader reader(path);
  reader.set_comment_char('#');
  reader.expect_next_line("the .node header (#points, dimension, #attributes, #markers)");
  const int header_line = reader.line();
  const int n = reader.read_count("the number of points");
  const long long dim = reader.has_word() ? reader.read_int("the dimension") : 3;
  const int num_attributes =
      reader.has_word() ? reader.read_count("the number of attributes", 1000) : 0;
  const long long markers = reader.has_word() ? reader.read_int("the boundary marker flag") : 0;
  reader.expect_line_end("the .node header");
  if (dim != 3) reader.fail("dimension " + std::to_string(dim) + ": rbaa reads 3D meshes only");
  if (markers != 0 && markers != 1) reader.fail("the boundary marker flag must be 0 or 1");
  NodeFile file;
  file.coords.reserve(3 * announced_capacity(n));
  for (int i = 0; i < n; ++i) {
    if (!reader.next_line()) {
      reader.fail_end_of_file("point " + std::to_string(i + 1) + " of the " + std::to_string(n) +
                              " announced on line " + std::to_string(header_line));
    }
    const long long index = reader.read_int("a point index");
    if (i == 0) {
      if (index != 0 && index != 1) {
        reader.fail("the first point index is " + std::to_string(index) + "; it must be 0 or 1");
      }
      file.base = static_cast<int>(index);
    } else if (index != file.base + i) {
      reader.fail("point index " + std::to_string(index) + " where " +
                  std::to_string(file.base + i) + " was expected (indices must be consecutive)");
    }
    for (int c = 0; c < 3; ++c) file.coords.push_back(reader.read_double("a point coordinate"));
    for (int a = 0; a < num_attributes; ++a) reader.read_double("a point attribute");
    if (markers) reader.read_int("a boundary marker");
    reader.expect_line_end("the point's values (the header announces " +
                           std::to_string(num_attributes) + " attributes and " +
                           std::to_string(markers) + " markers)");
  }
  if (reader.next_line()) {
    reader.fail("more points than the " + std::to_string(n) + " announced on line " +
                std::to_string(header_line));
  }
  return file;
}

}  // namespace

std::string tetgen_base_name(const std::string& path) {
  if (ends_with(path, ".node")) return path.substr(0, path.size() - 5);
  if (ends_with(path, ".ele")) return path.substr(0, path.size() - 4);
  return path;
}

TetMesh read_tetgen(const std::string& path) {
  const std::string base = tetgen_base_name(path);
  const NodeFile nodes = read_node_file(base + ".node");
  const int nv = static_cast<int>(nodes.coords.size() / 3);

  TextReader reader(base + ".ele");
  reader.set_comment_char('#');
  reader.expect_next_line("the .ele header (#tetrahedra, nodes per tetrahedron, #attributes)");
  const int header_line = reader.line();
  const int nt = reader.read_count("the number of tetrahedra");
  const long long nodes_per_tet =
      reader.has_word() ? reader.read_int("the nodes per tetrahedron") : 4;
  const int num_attributes =
      reader.has_word() ? reader.read_count("the number of attributes", 1000) : 0;
  reader.expect_line_end("the .ele header");
  if (nodes_per_tet != 4 && nodes_per_tet != 10) {
    reader.fail(std::to_string(nodes_per_tet) + " nodes per tetrahedron; expected 4 or 10");
  }
  TetMesh mesh;
  mesh.V = Eigen::Map<const Vertices>(nodes.coords.data(), nv, 3);
  std::vector<std::array<int, 4>> tets;
  tets.reserve(announced_capacity(nt));
  for (int e = 0; e < nt; ++e) {
    tets.emplace_back();
    if (!reader.next_line()) {
      reader.fail_end_of_file("tetrahedron " + std::to_string(e + 1) + " of the " +
                              std::to_string(nt) + " announced on line " +
                              std::to_string(header_line));
    }
    reader.read_int("a tetrahedron index");
    for (int k = 0; k < nodes_per_tet; ++k) {
      const long long v = reader.read_int("a node index") - nodes.base;
      if (v < 0 || v >= nv) {
        reader.fail("node index " + std::to_string(v + nodes.base) + " is outside " +
                    std::to_string(nodes.base) + ".." + std::to_string(nv - 1 + nodes.base) +
                    " (the points of " + base + ".node)");
      }
      // Of quadratic tets, the first four nodes are the corners.
      if (k < 4) tets.back()[k] = static_cast<int>(v);
    }
    for (int a = 0; a < num_attributes; ++a) reader.read_double("a tetrahedron attribute");
    reader.expect_line_end("the tetrahedron's values (the header announces " +
                           std::to_string(nodes_per_tet) + " nodes and " +
                           std::to_string(num_attributes) + " attributes)");
  }
  if (reader.next_line()) {
    reader.fail("more tetrahedra than the " + std::to_string(nt) + " announced on line " +
                std::to_string(header_line));
  }
  mesh.T.resize(nt, 4);
  for (int e = 0; e < nt; ++e) {
    for (int k = 0; k < 4; ++k) mesh.T(e, k) = tets[e][k];
  }
  // Tools writing .ele disagree on the sign convention; a consistently negative mesh is a
  // convention, a mixed one is an error left for validate_tet_mesh to report.
  if (nt > 0 && (tet_volumes(mesh).array() < 0).all()) mesh.T.col(2).swap(mesh.T.col(3));
  remove_unreferenced_vertices(mesh);
  return mesh;
}

void write_tetgen(const std::string& path, const TetMesh& mesh) {
  const std::string base = tetgen_base_name(path);
  write_file_atomically(base + ".node", [&](std::ostream& os) {
    os << "# " << mesh.num_vertices() << " points, 3D, no attributes, no markers (rbaa)\n";
    os << mesh.num_vertices() << " 3 0 0\n";
    for (int i = 0; i < mesh.num_vertices(); ++i) {
      os << i + 1;
      for (int c = 0; c < 3; ++c) os << ' ' << exact(mesh.V(i, c));
      os << '\n';
    }
  });
  write_file_atomically(base + ".ele", [&](std::ostream& os) {
    os << mesh.num_tets() << " 4 0\n";
    for (int e = 0; e < mesh.num_tets(); ++e) {
      os << e + 1;
      for (int k = 0; k < 4; ++k) os << ' ' << mesh.T(e, k) + 1;
      os << '\n';
    }
  });
}

}  // namespace rbaa
