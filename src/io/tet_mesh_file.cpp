#include "rbaa/io/tet_mesh_file.hpp"

#include <filesystem>
#include <vector>

#include "rbaa/error.hpp"
#include "rbaa/io/medit.hpp"
#include "rbaa/io/msh.hpp"
#include "rbaa/io/tetgen.hpp"

namespace rbaa {

namespace {

enum class MeshFormat { kMsh, kMedit, kTetgen };

std::string extension_of(const std::string& path) {
  return std::filesystem::path(path).extension().string();
}

MeshFormat format_for_reading(const std::string& path) {
  const std::string ext = extension_of(path);
  if (ext == ".msh") return MeshFormat::kMsh;
  if (ext == ".mesh") return MeshFormat::kMedit;
  if (ext == ".node" || ext == ".ele") return MeshFormat::kTetgen;
  // TetGen names its output "name.1.node"; a base name such as "name.1" is accepted when the
  // pair exists, since that is how TetGen itself is told which mesh to read (-r).
  std::error_code ec;
  if (std::filesystem::exists(path + ".node", ec) && std::filesystem::exists(path + ".ele", ec)) {
    return MeshFormat::kTetgen;
  }
  if (!std::filesystem::exists(path, ec)) {
    throw InputError(path + ": cannot read: No such file or directory");
  }
  throw InputError(path + ": unknown mesh file extension '" + ext +
                   "' (expected .msh, .mesh, or .node/.ele)");
}

}  // namespace

TetMeshFile read_tet_mesh(const std::string& path) {
  TetMeshFile file;
  switch (format_for_reading(path)) {
    case MeshFormat::kMsh:
      file = read_msh(path);
      break;
    case MeshFormat::kMedit:
      file.mesh = read_medit(path);
      break;
    case MeshFormat::kTetgen:
      file.mesh = read_tetgen(path);
      break;
  }
  validate_tet_mesh(file.mesh, path);
  return file;
}

void write_tet_mesh(const std::string& path, const TetMesh& mesh, const ElementData& element_data) {
  const std::string ext = extension_of(path);
  if (ext == ".msh") {
    write_msh(path, mesh, element_data);
    return;
  }
  if (ext != ".mesh" && ext != ".node" && ext != ".ele") {
    throw InputError("cannot write " + path + ": unknown mesh file extension '" + ext +
                     "' (expected .msh, .mesh, or .node/.ele)");
  }
  if (!element_data.empty()) {
    throw InputError("cannot write " + path + ": only .msh files hold element data ('" +
                     element_data.begin()->first + "', ...); write a .msh instead");
  }
  if (ext == ".mesh") {
    write_medit(path, mesh);
  } else {
    write_tetgen(path, mesh);
  }
}

int remove_unreferenced_vertices(TetMesh& mesh) { return remove_unreferenced_vertices(mesh.V, mesh.T); }

}  // namespace rbaa
