#include "rbaa/io/materials_io.hpp"

#include <cmath>
#include <filesystem>

#include "rbaa/error.hpp"
#include "rbaa/io/csv.hpp"
#include "rbaa/io/msh.hpp"
#include "rbaa/io/number_text.hpp"

namespace rbaa {

namespace {

std::string where(const std::string& path, int line) {
  return path + ":" + std::to_string(line) + ": ";
}

MaterialField read_materials_csv(const std::string& path, int num_tets) {
  const CsvTable table = read_csv(path);
  const int rows = static_cast<int>(table.values.rows());
  auto column = [&](const char* name, bool required) {
    const int c = table.column(name);
    if (c < 0 && required) {
      std::string found;
      for (const std::string& h : table.header) found += (found.empty() ? "" : ", ") + h;
      throw InputError(where(path, table.header_line) + "missing column '" + name +
                       "' (the header names: " + found + ")");
    }
    return c;
  };
  const int cy = column("Y", true);
  const int cnu = column("nu", true);
  const int crho = column("rho", true);
  const int calpha = column("alpha", false);
  if (rows != num_tets) {
    const int line = rows > num_tets ? table.row_lines[num_tets]
                                     : (rows > 0 ? table.row_lines.back() : table.header_line);
    throw InputError(where(path, line) + "the file has " + std::to_string(rows) +
                     " rows of materials but the mesh has " + std::to_string(num_tets) +
                     " tetrahedra");
  }
  for (int r = 0; r < rows; ++r) {
    for (int c : {cy, cnu, crho, calpha}) {
      if (c >= 0 && !std::isfinite(table.values(r, c))) {
        throw InputError(where(path, table.row_lines[r]) + "column '" + table.header[c] + "' is " +
                         format_double(table.values(r, c)));
      }
    }
  }
  MaterialField field;
  field.Y = table.values.col(cy);
  field.nu = table.values.col(cnu);
  field.rho = table.values.col(crho);
  field.alpha =
      calpha >= 0 ? Eigen::VectorXd(table.values.col(calpha)) : Eigen::VectorXd::Ones(rows);
  return field;
}

MaterialField read_materials_msh(const std::string& path, int num_tets, const Tets* tets) {
  const TetMeshFile file = read_msh(path);
  const int file_tets = file.mesh.num_tets();
  if (file_tets != num_tets) {
    throw InputError(path + ": the file's mesh has " + std::to_string(file_tets) +
                     " tetrahedra but the mesh has " + std::to_string(num_tets));
  }
  for (int e = 0; tets && e < num_tets; ++e) {
    if (file.mesh.T.row(e) != tets->row(e)) {
      auto four = [](const auto& row) {
        return "(" + std::to_string(row(0)) + ", " + std::to_string(row(1)) + ", " +
               std::to_string(row(2)) + ", " + std::to_string(row(3)) + ")";
      };
      throw InputError(path + ": the file's mesh is not the mesh: its tet " + std::to_string(e) +
                       " has vertices " + four(file.mesh.T.row(e)) + ", the mesh's " +
                       four(tets->row(e)));
    }
  }
  auto field_named = [&](const char* name, bool required) -> Eigen::VectorXd {
    const auto it = file.element_data.find(name);
    if (it != file.element_data.end()) return it->second;
    if (!required) return Eigen::VectorXd::Ones(num_tets);
    std::string found;
    for (const auto& [n, v] : file.element_data) found += (found.empty() ? "" : ", ") + n;
    throw InputError(path + ": no element data named '" + name +
                     "' (the file has: " + (found.empty() ? std::string("none") : found) + ")");
  };
  MaterialField field;
  field.Y = field_named("Y", true);
  field.nu = field_named("nu", true);
  field.rho = field_named("rho", true);
  field.alpha = field_named("alpha", false);
  return field;
}

MaterialField read_materials_file(const std::string& path, int num_tets, const Tets* tets) {
  const std::string ext = std::filesystem::path(path).extension().string();
  MaterialField field;
  if (ext == ".csv") {
    field = read_materials_csv(path, num_tets);
  } else if (ext == ".msh") {
    field = read_materials_msh(path, num_tets, tets);
  } else {
    throw InputError(path + ": unknown materials file extension '" + ext +
                     "' (expected .csv or .msh)");
  }
  validate_material_field(field, num_tets, path);
  return field;
}

}  // namespace

MaterialField read_materials(const std::string& path, int num_tets) {
  return read_materials_file(path, num_tets, nullptr);
}

MaterialField read_materials(const std::string& path, const TetMesh& mesh) {
  return read_materials_file(path, mesh.num_tets(), &mesh.T);
}

void write_materials_csv(const std::string& path, const MaterialField& field) {
  const Eigen::Index n = field.Y.size();
  if (field.nu.size() != n || field.rho.size() != n || field.alpha.size() != n) {
    throw InputError("cannot write " + path + ": the material arrays have different lengths");
  }
  Eigen::MatrixXd rows(n, 4);
  rows.col(0) = field.Y;
  rows.col(1) = field.nu;
  rows.col(2) = field.rho;
  rows.col(3) = field.alpha;
  write_csv(path, {"Y", "nu", "rho", "alpha"}, rows);
}

ElementData material_element_data(const MaterialField& field) {
  return {{"Y", field.Y}, {"nu", field.nu}, {"rho", field.rho}, {"alpha", field.alpha}};
}

}  // namespace rbaa
