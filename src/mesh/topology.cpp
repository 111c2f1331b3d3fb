#include "rbaa/mesh/topology.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

#include "rbaa/error.hpp"

namespace rbaa {
namespace {

// Outward-oriented faces of a positively oriented tet, indexed by the opposite local vertex.
constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

struct FaceRecord {
  std::array<int, 3> key;  // sorted vertex indices
  int element;
  int local;  // opposite local vertex
  bool operator<(const FaceRecord& o) const {
    return std::tie(key, element, local) < std::tie(o.key, o.element, o.local);
  }
};

std::vector<FaceRecord> sorted_faces(const TetMesh& mesh) {
  std::vector<FaceRecord> faces;
  faces.reserve(4 * static_cast<size_t>(mesh.num_tets()));
  for (int e = 0; e < mesh.num_tets(); ++e) {
    for (int k = 0; k < 4; ++k) {
      std::array<int, 3> key = {mesh.T(e, kFace[k][0]), mesh.T(e, kFace[k][1]),
                                mesh.T(e, kFace[k][2])};
      std::sort(key.begin(), key.end());
      faces.push_back({key, e, k});
    }
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

// Calls group(i, j) for each run faces[i, j) of one face (the same sorted vertices); refuses a
// face shared by more than two tets, naming `source` (or "non-manifold tet mesh") first.
template <typename Group>
void for_each_face(const std::vector<FaceRecord>& faces, const std::string& source, Group group) {
  for (size_t i = 0; i < faces.size();) {
    size_t j = i + 1;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    if (j - i > 2) {
      std::ostringstream msg;
      msg << (source.empty() ? "non-manifold tet mesh" : source) << ": face (" << faces[i].key[0]
          << ", " << faces[i].key[1] << ", " << faces[i].key[2] << ") is shared by " << (j - i)
          << " tetrahedra (tets " << faces[i].element << ", " << faces[i + 1].element << ", "
          << faces[i + 2].element << (j - i > 3 ? ", ..." : "") << ")";
      throw InputError(msg.str());
    }
    group(i, j);
    i = j;
  }
}

}  // namespace

Tets face_adjacency(const TetMesh& mesh) {
  Tets adj = Tets::Constant(mesh.num_tets(), 4, -1);
  const std::vector<FaceRecord> faces = sorted_faces(mesh);
  for_each_face(faces, "", [&](size_t i, size_t j) {
    if (j - i == 2) {
      adj(faces[i].element, faces[i].local) = faces[i + 1].element;
      adj(faces[i + 1].element, faces[i + 1].local) = faces[i].element;
    }
  });
  return adj;
}

void validate_tet_faces(const TetMesh& mesh, const std::string& source) {
  const std::vector<FaceRecord> faces = sorted_faces(mesh);
  auto oriented = [&](const FaceRecord& f) {
    return std::array<int, 3>{mesh.T(f.element, kFace[f.local][0]),
                              mesh.T(f.element, kFace[f.local][1]),
                              mesh.T(f.element, kFace[f.local][2])};
  };
  for_each_face(faces, source, [&](size_t i, size_t j) {
    if (j - i != 2) return;
    // Outward from both tets: the two copies run in opposite senses when the tets lie on
    // opposite sides. The same sense puts both on one side: they overlap (or repeat).
    const std::array<int, 3> a = oriented(faces[i]), b = oriented(faces[i + 1]);
    const int r = static_cast<int>(std::find(b.begin(), b.end(), a[0]) - b.begin());
    if (b[(r + 1) % 3] == a[1]) {
      std::ostringstream msg;
      msg << source << ": face (" << faces[i].key[0] << ", " << faces[i].key[1] << ", "
          << faces[i].key[2] << ") has tets " << faces[i].element << " and "
          << faces[i + 1].element << " on the same side: they overlap";
      throw InputError(msg.str());
    }
  });
}

Faces boundary_faces(const TetMesh& mesh) {
  const Tets adj = face_adjacency(mesh);
  std::vector<std::array<int, 3>> out;
  for (int e = 0; e < mesh.num_tets(); ++e) {
    for (int k = 0; k < 4; ++k) {
      if (adj(e, k) < 0) {
        out.push_back({mesh.T(e, kFace[k][0]), mesh.T(e, kFace[k][1]), mesh.T(e, kFace[k][2])});
      }
    }
  }
  Faces F(static_cast<Eigen::Index>(out.size()), 3);
  for (size_t i = 0; i < out.size(); ++i) {
    for (int c = 0; c < 3; ++c) F(static_cast<Eigen::Index>(i), c) = out[i][c];
  }
  return F;
}

std::string surface_mismatch(const TetMesh& reference, const TetMesh& adversarial,
                             const std::string& what) {
  const double size = bounding_box_diagonal(reference);
  const double tol = 1e-9 * size;
  const Eigen::RowVector3d dlo =
      reference.V.colwise().minCoeff() - adversarial.V.colwise().minCoeff();
  const Eigen::RowVector3d dhi =
      reference.V.colwise().maxCoeff() - adversarial.V.colwise().maxCoeff();
  const double off = std::max(dlo.cwiseAbs().maxCoeff(), dhi.cwiseAbs().maxCoeff());
  if (off > tol) {
    std::ostringstream msg;
    msg << what << ": the adversarial object's bounding box differs from the scene's reference "
        << "object's by up to " << off << " m (is it placed at the scene's initial pose, from "
        << "the same scene?)";
    return msg.str();
  }
  std::vector<std::array<double, 3>> adv(adversarial.num_vertices());
  for (int i = 0; i < adversarial.num_vertices(); ++i) {
    adv[i] = {adversarial.V(i, 0), adversarial.V(i, 1), adversarial.V(i, 2)};
  }
  std::sort(adv.begin(), adv.end());
  for (int v : boundary_vertices(reference)) {
    const std::array<double, 3> p = {reference.V(v, 0), reference.V(v, 1), reference.V(v, 2)};
    auto it = std::lower_bound(adv.begin(), adv.end(),
                               std::array<double, 3>{p[0] - tol, -INFINITY, -INFINITY});
    bool found = false;
    for (; it != adv.end() && (*it)[0] <= p[0] + tol && !found; ++it) {
      found = std::abs((*it)[1] - p[1]) <= tol && std::abs((*it)[2] - p[2]) <= tol;
    }
    if (!found) {
      std::ostringstream msg;
      msg << what << ": the adversarial object's surface is not the reference's (reference "
          << "surface vertex " << v << " at (" << p[0] << ", " << p[1] << ", " << p[2]
          << ") is missing)";
      return msg.str();
    }
  }
  return "";
}

std::vector<int> boundary_vertices(const TetMesh& mesh) {
  const Faces F = boundary_faces(mesh);
  std::vector<char> on(mesh.num_vertices(), 0);
  for (Eigen::Index i = 0; i < F.size(); ++i) on[F.data()[i]] = 1;
  std::vector<int> out;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (on[v]) out.push_back(v);
  }
  return out;
}

std::vector<char> boundary_elements(const TetMesh& mesh, bool by_vertex) {
  std::vector<char> flags(mesh.num_tets(), 0);
  if (by_vertex) {
    std::vector<char> on(mesh.num_vertices(), 0);
    for (int v : boundary_vertices(mesh)) on[v] = 1;
    for (int e = 0; e < mesh.num_tets(); ++e) {
      for (int k = 0; k < 4; ++k) flags[e] |= on[mesh.T(e, k)];
    }
  } else {
    const Tets adj = face_adjacency(mesh);
    for (int e = 0; e < mesh.num_tets(); ++e) {
      for (int k = 0; k < 4; ++k) flags[e] |= (adj(e, k) < 0);
    }
  }
  return flags;
}

int label_components(const Tets& adj, const std::vector<char>& flags, std::vector<int>& label) {
  const int nt = static_cast<int>(adj.rows());
  label.assign(nt, -1);
  std::vector<int> stack;
  int count = 0;
  for (int s = 0; s < nt; ++s) {
    if (!flags[s] || label[s] >= 0) continue;
    label[s] = count;
    stack.push_back(s);
    while (!stack.empty()) {
      const int e = stack.back();
      stack.pop_back();
      for (int k = 0; k < 4; ++k) {
        const int n = adj(e, k);
        if (n >= 0 && flags[n] && label[n] < 0) {
          label[n] = count;
          stack.push_back(n);
        }
      }
    }
    ++count;
  }
  return count;
}

int count_components(const TetMesh& mesh, const std::vector<char>& flags) {
  std::vector<int> label;
  return label_components(face_adjacency(mesh), flags.empty() ? std::vector<char>(mesh.num_tets(), 1) : flags,
                          label);
}

}  // namespace rbaa
