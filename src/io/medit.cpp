#include "rbaa/io/medit.hpp"

#include <algorithm>
#include <cctype>
#include <vector>

#include "rbaa/error.hpp"
#include "rbaa/io/atomic_file.hpp"
#include "rbaa/io/number_text.hpp"
#include "rbaa/io/tet_mesh_file.hpp"
#include "rbaa/io/text_reader.hpp"

namespace rbaa {

namespace {

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

// Keywords whose entries are skipped, with the number of words per entry (indices plus a
// reference, or vector components).
int skipped_entry_size(const std::string& keyword) {
  static const std::pair<const char*, int> kSkipped[] = {{"edges", 3},
                                                         {"triangles", 4},
                                                         {"quadrilaterals", 5},
                                                         {"corners", 1},
                                                         {"ridges", 1},
                                                         {"requiredvertices", 1},
                                                         {"requirededges", 1},
                                                         {"requiredtriangles", 1},
                                                         {"requiredquadrilaterals", 1},
                                                         {"normals", 3},
                                                         {"tangents", 3},
                                                         {"normalatvertices", 2},
                                                         {"tangentatvertices", 2},
                                                         {"normalattrianglevertices", 3},
                                                         {"tangentatedges", 3},
                                                         {"normalatquadrilateralvertices", 3},
                                                         {"requiredtetrahedra", 1},
                                                         {"edgesp2", 4},
                                                         {"trianglesp2", 7}};
  for (const auto& [name, size] : kSkipped) {
    if (keyword == name) return size;
  }
  return 0;
}

bool is_unsupported_volume(const std::string& keyword) {
  return keyword == "hexahedra" || keyword == "prisms" || keyword == "pyramids" ||
         keyword == "tetrahedrap2" || keyword == "hexahedraq2";
}

}  // namespace

TetMesh read_medit(const std::string& path) {
  TextReader reader(path);
  reader.set_comment_char('#');
  std::vector<double> coords;
  std::vector<int> tets;
  std::vector<int> tet_lines;
  bool have_vertices = false;
  bool have_tets = false;
  bool have_version = false;
  while (true) {
    // A file may end without the End keyword.
    while (!reader.has_word()) {
      if (!reader.next_line()) break;
    }
    if (!reader.has_word()) break;
    const std::string word(reader.read_word("a keyword"));
    const std::string keyword = lower(word);
    if (keyword == "end") {
      // Nothing may follow End: a second mesh or a cut-and-paste would be silently dropped.
      do {
        if (reader.has_word()) reader.fail("text after End");
      } while (reader.next_line());
      break;
    }
    if (keyword == "meshversionformatted") {
      reader.read_int_anywhere("the mesh version");
      have_version = true;
    } else if (keyword == "dimension") {
      const long long dim = reader.read_int_anywhere("the dimension");
      if (dim != 3) {
        reader.fail("Dimension " + std::to_string(dim) + ": rbaa reads 3-dimensional meshes only");
      }
    } else if (keyword == "vertices") {
      if (have_vertices) reader.fail("second Vertices section");
      const long long n = reader.read_int_anywhere("the number of vertices");
      if (n < 0 || n > 2000000000LL) reader.fail("bad number of vertices " + std::to_string(n));
      coords.reserve(3 * announced_capacity(n));
      for (long long i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c)
          coords.push_back(reader.read_double_anywhere("a vertex coordinate"));
        reader.read_int_anywhere("a vertex reference");
      }
      have_vertices = true;
    } else if (keyword == "tetrahedra") {
      if (have_tets) reader.fail("second Tetrahedra section");
      const long long n = reader.read_int_anywhere("the number of tetrahedra");
      if (n < 0 || n > 2000000000LL) reader.fail("bad number of tetrahedra " + std::to_string(n));
      for (long long e = 0; e < n; ++e) {
        for (int k = 0; k < 4; ++k) {
          const long long v = reader.read_int_anywhere("a tetrahedron's vertex index");
          if (v < 1 || v > 2000000000LL) {
            reader.fail("vertex index " + std::to_string(v) + " (indices start at 1)");
          }
          tets.push_back(static_cast<int>(v - 1));
        }
        tet_lines.push_back(reader.line());
        reader.read_int_anywhere("a tetrahedron reference");
      }
      have_tets = true;
    } else if (const int size = skipped_entry_size(keyword); size > 0) {
      const long long n = reader.read_int_anywhere("the number of " + word);
      if (n < 0 || n > 2000000000LL) reader.fail("bad count " + std::to_string(n) + " for " + word);
      for (long long i = 0; i < n * size; ++i) reader.read_double_anywhere("a value of " + word);
    } else if (is_unsupported_volume(keyword)) {
      reader.fail(word + " are not supported; rbaa reads linear tetrahedra");
    } else {
      reader.fail("unknown keyword " + TextReader::quote(word) + " (not an ASCII MEDIT .mesh?)");
    }
  }
  if (!have_version && !have_vertices)
    reader.fail("no MeshVersionFormatted or Vertices: not a MEDIT .mesh");
  if (!have_vertices) reader.fail("the file has no Vertices section");
  if (!have_tets) reader.fail("the file has no Tetrahedra section");
  TetMesh mesh;
  const int nv = static_cast<int>(coords.size() / 3);
  const int nt = static_cast<int>(tets.size() / 4);
  mesh.V = Eigen::Map<const Vertices>(coords.data(), nv, 3);
  mesh.T = Eigen::Map<const Tets>(tets.data(), nt, 4);
  for (int e = 0; e < nt; ++e) {
    for (int k = 0; k < 4; ++k) {
      if (mesh.T(e, k) >= nv) {
        reader.fail_at(tet_lines[e], "tetrahedron " + std::to_string(e + 1) + " refers to vertex " +
                                         std::to_string(mesh.T(e, k) + 1) + ", but there are " +
                                         std::to_string(nv) + " vertices");
      }
    }
  }
  remove_unreferenced_vertices(mesh);
  return mesh;
}

void write_medit(const std::string& path, const TetMesh& mesh) {
  write_file_atomically(path, [&](std::ostream& os) {
    os << "MeshVersionFormatted 2\nDimension 3\nVertices\n" << mesh.num_vertices() << '\n';
    for (int i = 0; i < mesh.num_vertices(); ++i) {
      for (int c = 0; c < 3; ++c) os << exact(mesh.V(i, c)) << ' ';
      os << "0\n";
    }
    os << "Tetrahedra\n" << mesh.num_tets() << '\n';
    for (int e = 0; e < mesh.num_tets(); ++e) {
      for (int k = 0; k < 4; ++k) os << mesh.T(e, k) + 1 << ' ';
      os << "1\n";
    }
    os << "End\n";
  });
}

}  // namespace rbaa
