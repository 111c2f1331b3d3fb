#include "rbaa/study/object_voids.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <numeric>
#include <set>
#include <utility>
#include <vector>

#include "rbaa/mesh/topology.hpp"

namespace rbaa {

std::string ObjectVoids::describe() const {
  std::string text;
  auto add = [&](int count, const std::string& one, const std::string& many) {
    if (count > 0)
      text += (text.empty() ? "" : ", ") + std::to_string(count) + " " + (count == 1 ? one : many);
  };
  add(partial_elements, "element with alpha < 1", "elements with alpha < 1");
  add(removed_elements, "element of the config's mesh removed",
      "elements of the config's mesh removed");
  add(inner_surfaces, "inner surface", "inner surfaces");
  return text;
}

bool is_part_of(const TetMesh& part, const TetMesh& whole) {
  std::map<std::array<double, 3>, int> vertex;
  for (int v = 0; v < whole.num_vertices(); ++v) {
    vertex.emplace(std::array<double, 3>{whole.V(v, 0), whole.V(v, 1), whole.V(v, 2)}, v);
  }
  auto sorted = [](std::array<int, 4> t) {
    std::sort(t.begin(), t.end());
    return t;
  };
  std::set<std::array<int, 4>> tets;
  for (int e = 0; e < whole.num_tets(); ++e) {
    tets.insert(sorted({whole.T(e, 0), whole.T(e, 1), whole.T(e, 2), whole.T(e, 3)}));
  }
  for (int e = 0; e < part.num_tets(); ++e) {
    std::array<int, 4> t;
    for (int k = 0; k < 4; ++k) {
      const int v = part.T(e, k);
      const auto it = vertex.find({part.V(v, 0), part.V(v, 1), part.V(v, 2)});
      if (it == vertex.end()) return false;
      t[k] = it->second;
    }
    if (!tets.count(sorted(t))) return false;
  }
  return true;
}

int boundary_surface_pieces(const TetMesh& mesh) {
  const Faces faces = boundary_faces(mesh);
  const int nf = static_cast<int>(faces.rows());
  std::map<std::pair<int, int>, std::vector<int>> edge_faces;
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = faces(f, k), b = faces(f, (k + 1) % 3);
      edge_faces[{std::min(a, b), std::max(a, b)}].push_back(f);
    }
  }
  std::vector<int> parent(nf);
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](int f) {
    while (parent[f] != f) f = parent[f] = parent[parent[f]];
    return f;
  };
  int pieces = nf;
  for (const auto& [edge, fs] : edge_faces) {
    if (fs.size() != 2) continue;
    const int a = root(fs[0]), b = root(fs[1]);
    if (a != b) {
      parent[a] = b;
      --pieces;
    }
  }
  return pieces;
}

ObjectVoids find_object_voids(const TetMesh& object, const MaterialField& materials,
                              const TetMesh& config_mesh) {
  ObjectVoids v;
  v.partial_elements = static_cast<int>((materials.alpha.array() < 1.0).count());
  v.part_of_config = is_part_of(object, config_mesh);
  if (v.part_of_config) v.removed_elements = config_mesh.num_tets() - object.num_tets();
  v.inner_surfaces =
      std::max(0, boundary_surface_pieces(object) - boundary_surface_pieces(config_mesh));
  return v;
}

}  // namespace rbaa
