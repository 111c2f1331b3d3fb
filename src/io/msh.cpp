#include "rbaa/io/msh.hpp"

#include <array>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "rbaa/error.hpp"
#include "rbaa/io/atomic_file.hpp"
#include "rbaa/io/number_text.hpp"
#include "rbaa/io/text_reader.hpp"

namespace rbaa {

namespace {

enum class ElementKind { kLinearTet, kSkipped, kUnsupportedVolume };

// Gmsh element type numbers (Gmsh's GmshDefines.h). Lower-dimensional elements are boundary or
// geometry annotations and are skipped; other volume elements would leave holes in the solid, so
// they are refused rather than dropped.
ElementKind classify_element(long long type, std::string* description) {
  switch (type) {
    case 4:
      return ElementKind::kLinearTet;
    case 11:
    case 29:
    case 30:
    case 31:
      *description = "higher-order tetrahedron";
      return ElementKind::kUnsupportedVolume;
    case 5:
    case 12:
    case 17:
    case 92:
    case 93:
      *description = "hexahedron";
      return ElementKind::kUnsupportedVolume;
    case 6:
    case 13:
    case 18:
    case 90:
    case 91:
      *description = "prism";
      return ElementKind::kUnsupportedVolume;
    case 7:
    case 14:
    case 19:
    case 118:
    case 119:
      *description = "pyramid";
      return ElementKind::kUnsupportedVolume;
    default:
      break;
  }
  // Points, lines, triangles, quadrangles and polygons of any order (GmshDefines.h: 1-3, 8-10,
  // 15, 16, 20-28, 34, 36-70, 84-86) are skipped; anything else is a volume element (tetrahedra
  // of order 5 and up are 71-75 and 79-83, hexahedra, prisms and pyramids of higher orders follow)
  // or no Gmsh type at all, and dropping it could leave holes in the solid.
  const bool lower_dimensional = (type >= 1 && type <= 3) || (type >= 8 && type <= 10) ||
                                 type == 15 || type == 16 || (type >= 20 && type <= 28) ||
                                 type == 34 || (type >= 36 && type <= 70) ||
                                 (type >= 84 && type <= 86);
  if (lower_dimensional) return ElementKind::kSkipped;
  *description = "a volume element or no Gmsh type rbaa reads";
  return ElementKind::kUnsupportedVolume;
}

std::string unquote(std::string_view s) {
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = s.substr(1, s.size() - 2);
  return std::string(s);
}

struct RawElementData {
  std::string name;
  int line = 0;
  std::vector<long long> element_tags;
  std::vector<double> values;
  std::vector<int> lines;
};

// How far a counted list has got: what the file ending inside it reports.
struct ListProgress {
  const char* section;  // "$Elements"
  std::string unit;     // "elements"
  long long expected;
  long long read;
};

class MshParser {
 public:
  explicit MshParser(const std::string& path) : reader_(path) {}

  TetMeshFile parse() {
    read_mesh_format();
    while (reader_.next_line()) {
      const std::string section(reader_.rest_of_line());
      if (section.empty() || section[0] != '$') {
        reader_.fail("expected a section header such as $Nodes, found " +
                     TextReader::quote(section));
      }
      if (section == "$Nodes") {
        if (have_nodes_) reader_.fail("second $Nodes section");
        major_ == 2 ? read_nodes_v2() : read_nodes_v4();
        have_nodes_ = true;
      } else if (section == "$Elements") {
        if (have_elements_) reader_.fail("second $Elements section");
        major_ == 2 ? read_elements_v2() : read_elements_v4();
        have_elements_ = true;
      } else if (section == "$ElementData") {
        read_element_data();
      } else if (section == "$MeshFormat") {
        reader_.fail("second $MeshFormat section");
      } else if (section.rfind("$End", 0) == 0) {
        reader_.fail(TextReader::quote(section) + " without a matching section start");
      } else {
        skip_section(section);
      }
    }
    if (!have_nodes_) reader_.fail("the file has no $Nodes section");
    if (!have_elements_) reader_.fail("the file has no $Elements section");
    return assemble();
  }

 private:
  void read_mesh_format() {
    if (!reader_.next_line()) reader_.fail("empty file, expected $MeshFormat");
    const std::string first(reader_.rest_of_line());
    if (first != "$MeshFormat") {
      reader_.fail("expected $MeshFormat on the first line, found " + TextReader::quote(first) +
                   " (not a Gmsh .msh file?)");
    }
    reader_.expect_next_line("the mesh format line");
    const std::string version(reader_.read_word("the format version"));
    const long long file_type = reader_.read_int("the file type (0 = ASCII)");
    reader_.read_int("the data size");
    reader_.expect_line_end("the data size");
    if (file_type != 0) {
      reader_.fail(
          "binary .msh files are not supported; save as ASCII (Gmsh option "
          "Mesh.Binary = 0)");
    }
    if (version == "2" || version == "2.0" || version == "2.1" || version == "2.2") {
      major_ = 2;
    } else if (version == "4.1") {
      major_ = 4;
    } else {
      reader_.fail("unsupported .msh version " + TextReader::quote(version) +
                   "; rbaa reads ASCII versions 2.2 and 4.1");
    }
    expect_section_end("$EndMeshFormat", "the mesh format line");
  }

  // `after` says what was read last, for the message when the count before it was wrong.
  void expect_section_end(const std::string& end, const std::string& after) {
    reader_.expect_next_line(end);
    const std::string_view found = reader_.rest_of_line();
    if (found != end) {
      reader_.fail("expected " + end + " after " + after + ", found " + TextReader::quote(found) +
                   " (wrong count?)");
    }
  }

  void skip_section(const std::string& section) {
    const std::string end = "$End" + section.substr(1);
    while (true) {
      reader_.expect_next_line(end);
      if (reader_.rest_of_line() == end) return;
    }
  }

  void add_node(long long tag, double x, double y, double z) {
    if (!node_index_.emplace(tag, static_cast<int>(node_tags_.size())).second) {
      reader_.fail("node tag " + std::to_string(tag) + " appears twice");
    }
    node_tags_.push_back(tag);
    coords_.insert(coords_.end(), {x, y, z});
  }

  void read_nodes_v2() {
    reader_.expect_next_line("the number of nodes");
    const int count_line = reader_.line();
    const int n = reader_.read_count("the number of nodes");
    reader_.expect_line_end("the number of nodes");
    for (int i = 0; i < n; ++i) {
      expect_entry_line("node", i, n, count_line, {"$Nodes", "nodes", n, i});
      const long long tag = reader_.read_int("a node tag");
      const double x = reader_.read_double("the node's x coordinate");
      const double y = reader_.read_double("the node's y coordinate");
      const double z = reader_.read_double("the node's z coordinate");
      reader_.expect_line_end("the node's z coordinate");
      add_node(tag, x, y, z);
    }
    expect_section_end("$EndNodes", std::to_string(n) + " nodes");
  }

  void read_nodes_v4() {
    reader_.expect_next_line("the $Nodes header");
    const int count_line = reader_.line();
    const int num_blocks = reader_.read_count("the number of node blocks");
    const int n = reader_.read_count("the number of nodes");
    reader_.read_int("the minimum node tag");
    reader_.read_int("the maximum node tag");
    reader_.expect_line_end("the maximum node tag");
    long long done = 0;
    for (int b = 0; b < num_blocks; ++b) {
      expect_entry_line("node block", b, num_blocks, count_line, {"$Nodes", "nodes", n, done});
      const long long dim = reader_.read_int("the entity dimension");
      reader_.read_int("the entity tag");
      const long long parametric = reader_.read_int("the parametric flag");
      const int block_line = reader_.line();
      const int k = reader_.read_count("the number of nodes in the block");
      reader_.expect_line_end("the number of nodes in the block");
      if (dim < 0 || dim > 3)
        reader_.fail("entity dimension " + std::to_string(dim) + " is not 0-3");
      if (parametric != 0 && parametric != 1) reader_.fail("parametric flag must be 0 or 1");
      if (done + k > n) {
        reader_.fail("node blocks hold more nodes than the " + std::to_string(n) +
                     " announced on line " + std::to_string(count_line));
      }
      std::vector<long long> tags;
      tags.reserve(announced_capacity(k));
      for (int i = 0; i < k; ++i) {
        expect_entry_line("node tag", i, k, block_line, {"$Nodes", "nodes", n, done});
        tags.push_back(reader_.read_int("a node tag"));
        reader_.expect_line_end("the node tag");
      }
      // Parametric nodes carry their coordinates on the entity (u; u v; u v w) after x y z.
      const int extra = parametric ? static_cast<int>(dim) : 0;
      for (int i = 0; i < k; ++i) {
        expect_entry_line("node coordinate line", i, k, block_line,
                          {"$Nodes", "nodes", n, done + i});
        const double x = reader_.read_double("the node's x coordinate");
        const double y = reader_.read_double("the node's y coordinate");
        const double z = reader_.read_double("the node's z coordinate");
        for (int p = 0; p < extra; ++p) reader_.read_double("a parametric coordinate");
        reader_.expect_line_end("the node's coordinates");
        add_node(tags[i], x, y, z);
      }
      done += k;
    }
    if (done != n) {
      reader_.fail_at(count_line, "the $Nodes header announces " + std::to_string(n) +
                                      " nodes, but its blocks hold " + std::to_string(done));
    }
    expect_section_end("$EndNodes", std::to_string(n) + " nodes");
  }

  void add_element(long long tag) {
    if (!element_tags_.insert(tag).second) {
      reader_.fail("element tag " + std::to_string(tag) + " appears twice");
    }
  }

  void read_tet_nodes(long long tag) {
    add_element(tag);
    std::array<long long, 4> nodes;
    for (auto& node : nodes) node = reader_.read_int("a node tag of the tetrahedron");
    reader_.expect_line_end("the tetrahedron's 4 node tags");
    tet_tags_.push_back(tag);
    tet_nodes_.push_back(nodes);
    tet_lines_.push_back(reader_.line());
  }

  void refuse_element_type(long long type, const std::string& description) {
    reader_.fail("element type " + std::to_string(type) + " (" + description +
                 ") is not supported; rbaa reads linear tetrahedra (type 4)");
  }

  void read_elements_v2() {
    reader_.expect_next_line("the number of elements");
    const int count_line = reader_.line();
    const int m = reader_.read_count("the number of elements");
    reader_.expect_line_end("the number of elements");
    for (int i = 0; i < m; ++i) {
      expect_entry_line("element", i, m, count_line, {"$Elements", "elements", m, i});
      const long long tag = reader_.read_int("an element tag");
      const long long type = reader_.read_int("the element type");
      const int num_tags = reader_.read_count("the number of element tags", 1000);
      for (int t = 0; t < num_tags; ++t) reader_.read_int("an element tag (physical/entity)");
      std::string description;
      switch (classify_element(type, &description)) {
        case ElementKind::kLinearTet:
          read_tet_nodes(tag);
          break;
        case ElementKind::kSkipped:
          add_element(tag);
          reader_.rest_of_line();
          break;
        case ElementKind::kUnsupportedVolume:
          refuse_element_type(type, description);
      }
    }
    expect_section_end("$EndElements", std::to_string(m) + " elements");
  }

  void read_elements_v4() {
    reader_.expect_next_line("the $Elements header");
    const int count_line = reader_.line();
    const int num_blocks = reader_.read_count("the number of element blocks");
    const int m = reader_.read_count("the number of elements");
    reader_.read_int("the minimum element tag");
    reader_.read_int("the maximum element tag");
    reader_.expect_line_end("the maximum element tag");
    long long done = 0;
    for (int b = 0; b < num_blocks; ++b) {
      expect_entry_line("element block", b, num_blocks, count_line,
                        {"$Elements", "elements", m, done});
      reader_.read_int("the entity dimension");
      reader_.read_int("the entity tag");
      const long long type = reader_.read_int("the element type");
      const int block_line = reader_.line();
      const int k = reader_.read_count("the number of elements in the block");
      reader_.expect_line_end("the number of elements in the block");
      if (done + k > m) {
        reader_.fail("element blocks hold more elements than the " + std::to_string(m) +
                     " announced on line " + std::to_string(count_line));
      }
      std::string description;
      const ElementKind kind = classify_element(type, &description);
      if (kind == ElementKind::kUnsupportedVolume) refuse_element_type(type, description);
      for (int i = 0; i < k; ++i) {
        expect_entry_line("element", i, k, block_line, {"$Elements", "elements", m, done + i});
        const long long tag = reader_.read_int("an element tag");
        if (kind == ElementKind::kLinearTet) {
          read_tet_nodes(tag);
        } else {
          add_element(tag);
          reader_.rest_of_line();
        }
      }
      done += k;
    }
    if (done != m) {
      reader_.fail_at(count_line, "the $Elements header announces " + std::to_string(m) +
                                      " elements, but its blocks hold " + std::to_string(done));
    }
    expect_section_end("$EndElements", std::to_string(m) + " elements");
  }

  void read_element_data() {
    RawElementData data;
    data.line = reader_.line();
    reader_.expect_next_line("the number of string tags");
    const int num_strings = reader_.read_count("the number of string tags", 1000);
    reader_.expect_line_end("the number of string tags");
    if (num_strings < 1) reader_.fail("element data needs a name (at least one string tag)");
    for (int s = 0; s < num_strings; ++s) {
      reader_.expect_next_line("a string tag");
      const std::string_view text = reader_.rest_of_line();
      if (text.size() >= 1 && text[0] == '$') reader_.fail("section ends inside the string tags");
      if (s == 0) data.name = unquote(text);
    }
    reader_.expect_next_line("the number of real tags");
    const int num_reals = reader_.read_count("the number of real tags", 1000);
    reader_.expect_line_end("the number of real tags");
    for (int s = 0; s < num_reals; ++s) {
      reader_.expect_next_line("a real tag");
      reader_.read_double("a real tag (time)");
      reader_.expect_line_end("the real tag");
    }
    reader_.expect_next_line("the number of integer tags");
    const int num_ints = reader_.read_count("the number of integer tags", 1000);
    reader_.expect_line_end("the number of integer tags");
    if (num_ints < 3) {
      reader_.fail("element data '" + data.name + "' has " + std::to_string(num_ints) +
                   " integer tags; it needs 3 (time step, components, number of elements)");
    }
    long long components = 0;
    int count = 0;
    int count_line = 0;
    for (int s = 0; s < num_ints; ++s) {
      reader_.expect_next_line("an integer tag");
      if (s == 2) {
        count_line = reader_.line();
        count = reader_.read_count("the number of elements with data");
      } else {
        const long long value = reader_.read_int("an integer tag");
        if (s == 1) components = value;
      }
      reader_.expect_line_end("the integer tag");
      if (s == 1 && components != 1) {
        reader_.fail("element data '" + data.name + "' has " + std::to_string(components) +
                     " components; rbaa reads scalar fields (1 component)");
      }
    }
    data.element_tags.reserve(announced_capacity(count));
    data.values.reserve(announced_capacity(count));
    for (int i = 0; i < count; ++i) {
      expect_entry_line("element data value", i, count, count_line,
                        {"$ElementData", "values of '" + data.name + "'", count, i});
      data.element_tags.push_back(reader_.read_int("an element tag"));
      data.values.push_back(reader_.read_double("the element's value"));
      reader_.expect_line_end("the element's value");
      data.lines.push_back(reader_.line());
    }
    expect_section_end("$EndElementData", std::to_string(count) + " values of '" + data.name + "'");
    data_.push_back(std::move(data));
  }

  // Starts the next line of a counted list; a section end here means the count announced on
  // `count_line` is larger than the list. The file ending here, or this line being the file's
  // last with no line break after it (a cut inside the line: "1" left of "16 ..." would read as
  // a duplicate tag 1), means the file is truncated: an entry line is always followed by at
  // least its section's end.
  void expect_entry_line(const char* what, long long done, long long announced, int count_line,
                         const ListProgress& progress) {
    if (!reader_.next_line() || reader_.on_unterminated_last_line()) {
      reader_.fail("file ends inside the " + std::string(progress.section) + " section (expected " +
                   std::to_string(progress.expected) + " " + progress.unit + ", read " +
                   std::to_string(progress.read) + "): the file is truncated");
    }
    {
      const std::string_view first = reader_.peek_word();
      if (!first.empty() && first[0] == '$') {
        reader_.fail("section ends after " + std::to_string(done) + " of the " +
                     std::to_string(announced) + " entries (" + what + ") announced on line " +
                     std::to_string(count_line));
      }
    }
  }

  TetMeshFile assemble() {
    TetMeshFile file;
    const int nv = static_cast<int>(node_tags_.size());
    const int nt = static_cast<int>(tet_tags_.size());
    file.mesh.V.resize(nv, 3);
    for (int i = 0; i < nv; ++i) {
      for (int c = 0; c < 3; ++c) file.mesh.V(i, c) = coords_[3 * i + c];
    }
    file.mesh.T.resize(nt, 4);
    for (int e = 0; e < nt; ++e) {
      for (int k = 0; k < 4; ++k) {
        const auto it = node_index_.find(tet_nodes_[e][k]);
        if (it == node_index_.end()) {
          reader_.fail_at(tet_lines_[e], "tetrahedron " + std::to_string(tet_tags_[e]) +
                                             " refers to node " + std::to_string(tet_nodes_[e][k]) +
                                             ", which is not in $Nodes");
        }
        file.mesh.T(e, k) = it->second;
      }
    }
    std::unordered_map<long long, int> tet_index;
    tet_index.reserve(nt);
    for (int e = 0; e < nt; ++e) tet_index.emplace(tet_tags_[e], e);
    for (const RawElementData& data : data_) {
      Eigen::VectorXd values(nt);
      std::vector<char> seen(nt, 0);
      int filled = 0;
      for (std::size_t i = 0; i < data.element_tags.size(); ++i) {
        const long long tag = data.element_tags[i];
        const auto it = tet_index.find(tag);
        if (it == tet_index.end()) {
          if (element_tags_.count(tag)) continue;  // data on a skipped (e.g. surface) element
          reader_.fail_at(data.lines[i], "element data '" + data.name + "' refers to element " +
                                             std::to_string(tag) + ", which is not in $Elements");
        }
        if (seen[it->second]) {
          reader_.fail_at(data.lines[i], "element data '" + data.name + "' gives element " +
                                             std::to_string(tag) + " a second value");
        }
        seen[it->second] = 1;
        values[it->second] = data.values[i];
        ++filled;
      }
      if (filled != nt) {
        reader_.fail_at(data.line, "element data '" + data.name + "' has values for " +
                                       std::to_string(filled) + " of the " + std::to_string(nt) +
                                       " tetrahedra; it needs one per tetrahedron");
      }
      if (file.element_data.count(data.name)) {
        reader_.fail_at(data.line, "element data '" + data.name +
                                       "' is given a second time (one block per name)");
      }
      file.element_data[data.name] = std::move(values);
    }
    remove_unreferenced_vertices(file.mesh);
    return file;
  }

  TextReader reader_;
  int major_ = 0;
  bool have_nodes_ = false;
  bool have_elements_ = false;
  std::vector<long long> node_tags_;
  std::vector<double> coords_;
  std::unordered_map<long long, int> node_index_;
  std::unordered_set<long long> element_tags_;
  std::vector<long long> tet_tags_;
  std::vector<std::array<long long, 4>> tet_nodes_;
  std::vector<int> tet_lines_;
  std::vector<RawElementData> data_;
};

void check_writable(const std::string& path, const TetMesh& mesh, const ElementData& data) {
  const int nv = mesh.num_vertices();
  for (int e = 0; e < mesh.num_tets(); ++e) {
    for (int k = 0; k < 4; ++k) {
      if (mesh.T(e, k) < 0 || mesh.T(e, k) >= nv) {
        throw InputError("cannot write " + path + ": tet " + std::to_string(e) +
                         " refers to vertex " + std::to_string(mesh.T(e, k)) + " of " +
                         std::to_string(nv));
      }
    }
  }
  for (const auto& [name, values] : data) {
    if (name.empty() || name.find_first_of("\"\n\r") != std::string::npos) {
      throw InputError("cannot write " + path + ": element data name '" + name +
                       "' is empty or contains a quote or line break");
    }
    if (values.size() != mesh.num_tets()) {
      throw InputError("cannot write " + path + ": element data '" + name + "' has " +
                       std::to_string(values.size()) + " values but the mesh has " +
                       std::to_string(mesh.num_tets()) + " tetrahedra");
    }
  }
}

void write_coordinates(std::ostream& os, const TetMesh& mesh, int i) {
  os << exact(mesh.V(i, 0)) << ' ' << exact(mesh.V(i, 1)) << ' ' << exact(mesh.V(i, 2));
}

void write_tet_nodes(std::ostream& os, const TetMesh& mesh, int e) {
  // Gmsh tags start at 1; vertex i is node i + 1.
  for (int k = 0; k < 4; ++k) os << ' ' << mesh.T(e, k) + 1;
}

void write_element_data(std::ostream& os, const ElementData& data) {
  // Tags: one string (the name), one real (time 0), three integers (time step 0, 1 component,
  // one value per tet). Element e is tag e + 1 in both versions.
  for (const auto& [name, values] : data) {
    os << "$ElementData\n1\n\"" << name << "\"\n1\n0\n3\n0\n1\n" << values.size() << '\n';
    for (Eigen::Index e = 0; e < values.size(); ++e) {
      os << e + 1 << ' ' << exact(values[e]) << '\n';
    }
    os << "$EndElementData\n";
  }
}

void write_v22(std::ostream& os, const TetMesh& mesh) {
  const int nv = mesh.num_vertices();
  const int nt = mesh.num_tets();
  os << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
  os << "$Nodes\n" << nv << '\n';
  for (int i = 0; i < nv; ++i) {
    os << i + 1 << ' ';
    write_coordinates(os, mesh, i);
    os << '\n';
  }
  os << "$EndNodes\n$Elements\n" << nt << '\n';
  // "4 2 1 1": type 4 (tet), two tags: physical group 1, elementary volume 1.
  for (int e = 0; e < nt; ++e) {
    os << e + 1 << " 4 2 1 1";
    write_tet_nodes(os, mesh, e);
    os << '\n';
  }
  os << "$EndElements\n";
}

void write_v41(std::ostream& os, const TetMesh& mesh) {
  const int nv = mesh.num_vertices();
  const int nt = mesh.num_tets();
  os << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  // One volume entity holding everything, with its bounding box, so Gmsh opens the file as is.
  Eigen::RowVector3d lo = Eigen::RowVector3d::Zero();
  Eigen::RowVector3d hi = Eigen::RowVector3d::Zero();
  if (nv > 0) {
    lo = mesh.V.colwise().minCoeff();
    hi = mesh.V.colwise().maxCoeff();
  }
  os << "$Entities\n0 0 0 1\n1";
  for (int c = 0; c < 3; ++c) os << ' ' << exact(lo[c]);
  for (int c = 0; c < 3; ++c) os << ' ' << exact(hi[c]);
  os << " 0 0\n$EndEntities\n";
  os << "$Nodes\n";
  if (nv == 0) {
    os << "0 0 0 0\n";
  } else {
    os << "1 " << nv << " 1 " << nv << '\n' << "3 1 0 " << nv << '\n';
    for (int i = 0; i < nv; ++i) os << i + 1 << '\n';
    for (int i = 0; i < nv; ++i) {
      write_coordinates(os, mesh, i);
      os << '\n';
    }
  }
  os << "$EndNodes\n$Elements\n";
  if (nt == 0) {
    os << "0 0 0 0\n";
  } else {
    os << "1 " << nt << " 1 " << nt << '\n' << "3 1 4 " << nt << '\n';
    for (int e = 0; e < nt; ++e) {
      os << e + 1;
      write_tet_nodes(os, mesh, e);
      os << '\n';
    }
  }
  os << "$EndElements\n";
}

}  // namespace

TetMeshFile read_msh(const std::string& path) { return MshParser(path).parse(); }

void write_msh(const std::string& path, const TetMesh& mesh, const ElementData& element_data,
               MshVersion version) {
  check_writable(path, mesh, element_data);
  write_file_atomically(path, [&](std::ostream& os) {
    if (version == MshVersion::kV22) {
      write_v22(os, mesh);
    } else {
      write_v41(os, mesh);
    }
    write_element_data(os, element_data);
  });
}

}  // namespace rbaa
