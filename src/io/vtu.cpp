#include "rbaa/io/vtu.hpp"

#include "rbaa/error.hpp"
#include "rbaa/io/atomic_file.hpp"
#include "rbaa/io/number_text.hpp"

namespace rbaa {

namespace {

// XML attribute values: field and file names are user-chosen and may hold any of these.
std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

void check_fields(const std::string& path, const VtuFields& fields, Eigen::Index rows,
                  const char* kind) {
  for (const auto& [name, values] : fields) {
    if (name.empty())
      throw InputError("cannot write " + path + ": a " + kind + " field has no name");
    if (values.rows() != rows || values.cols() < 1) {
      throw InputError("cannot write " + path + ": " + kind + " field '" + name + "' is " +
                       std::to_string(values.rows()) + " by " + std::to_string(values.cols()) +
                       ", expected " + std::to_string(rows) + " rows and at least 1 column");
    }
  }
}

void write_field(std::ostream& os, const std::string& name, const Eigen::MatrixXd& values) {
  os << "        <DataArray type=\"Float64\" Name=\"" << xml_escape(name)
     << "\" NumberOfComponents=\"" << values.cols() << "\" format=\"ascii\">\n";
  for (Eigen::Index r = 0; r < values.rows(); ++r) {
    os << "         ";
    for (Eigen::Index c = 0; c < values.cols(); ++c) os << ' ' << exact(values(r, c));
    os << '\n';
  }
  os << "        </DataArray>\n";
}

void write_fields(std::ostream& os, const char* tag, const VtuFields& fields) {
  if (fields.empty()) return;
  os << "      <" << tag << ">\n";
  for (const auto& [name, values] : fields) write_field(os, name, values);
  os << "      </" << tag << ">\n";
}

}  // namespace

void write_vtu(const std::string& path, const Vertices& V, const Tets& T,
               const VtuFields& point_data, const VtuFields& cell_data) {
  check_fields(path, point_data, V.rows(), "point");
  check_fields(path, cell_data, T.rows(), "cell");
  for (Eigen::Index e = 0; e < T.rows(); ++e) {
    for (int k = 0; k < 4; ++k) {
      if (T(e, k) < 0 || T(e, k) >= V.rows()) {
        throw InputError("cannot write " + path + ": tet " + std::to_string(e) +
                         " refers to vertex " + std::to_string(T(e, k)) + " of " +
                         std::to_string(V.rows()));
      }
    }
  }
  write_file_atomically(path, [&](std::ostream& os) {
    os << "<?xml version=\"1.0\"?>\n"
       << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
          "header_type=\"UInt64\">\n"
       << "  <UnstructuredGrid>\n"
       << "    <Piece NumberOfPoints=\"" << V.rows() << "\" NumberOfCells=\"" << T.rows()
       << "\">\n";
    write_fields(os, "PointData", point_data);
    write_fields(os, "CellData", cell_data);
    os << "      <Points>\n"
       << "        <DataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\" "
          "format=\"ascii\">\n";
    for (Eigen::Index i = 0; i < V.rows(); ++i) {
      os << "         ";
      for (int c = 0; c < 3; ++c) os << ' ' << exact(V(i, c));
      os << '\n';
    }
    os << "        </DataArray>\n      </Points>\n      <Cells>\n"
       << "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
    for (Eigen::Index e = 0; e < T.rows(); ++e) {
      os << "         ";
      for (int k = 0; k < 4; ++k) os << ' ' << T(e, k);
      os << '\n';
    }
    os << "        </DataArray>\n"
       << "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    for (Eigen::Index e = 0; e < T.rows(); ++e) os << "          " << 4 * (e + 1) << '\n';
    // 10 is VTK_TETRA.
    os << "        </DataArray>\n"
       << "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    for (Eigen::Index e = 0; e < T.rows(); ++e) os << "          10\n";
    os << "        </DataArray>\n      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n"
       << "</VTKFile>\n";
  });
}

void write_vtu(const std::string& path, const TetMesh& mesh, const VtuFields& point_data,
               const VtuFields& cell_data) {
  write_vtu(path, mesh.V, mesh.T, point_data, cell_data);
}

void write_pvd(const std::string& path, const std::vector<std::pair<double, std::string>>& frames) {
  write_file_atomically(path, [&](std::ostream& os) {
    os << "<?xml version=\"1.0\"?>\n"
       << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
       << "  <Collection>\n";
    for (const auto& [time, file] : frames) {
      os << "    <DataSet timestep=\"" << exact(time) << "\" group=\"\" part=\"0\" file=\""
         << xml_escape(file) << "\"/>\n";
    }
    os << "  </Collection>\n</VTKFile>\n";
  });
}

}  // namespace rbaa
