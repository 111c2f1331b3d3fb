// Everything that instantiates CGAL lives in this one translation unit: Mesh_3 alone takes about
// a minute and several GB to compile, so keeping it here keeps rebuilds of the rest fast.

#include "rbaa/mesh/tetrahedralize.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polyhedral_mesh_domain_with_features_3.h>
#include <CGAL/Random.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/make_mesh_3.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <unordered_map>

#include "rbaa/error.hpp"
#include "rbaa/geometry/moments.hpp"
#include "rbaa/mesh/primitives.hpp"

namespace rbaa {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using CgalSurface = CGAL::Surface_mesh<Point>;
using Domain = CGAL::Polyhedral_mesh_domain_with_features_3<Kernel, CgalSurface>;
using Triangulation =
    CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using Complex = CGAL::Mesh_complex_3_in_triangulation_3<Triangulation, Domain::Corner_index,
                                                        Domain::Curve_index>;
using Criteria = CGAL::Mesh_criteria_3<Triangulation>;
namespace PMP = CGAL::Polygon_mesh_processing;

CgalSurface to_cgal(const SurfaceMesh& s) {
  std::vector<Point> points;
  points.reserve(s.V.rows());
  for (Eigen::Index i = 0; i < s.V.rows(); ++i) points.emplace_back(s.V(i, 0), s.V(i, 1), s.V(i, 2));
  std::vector<std::vector<std::size_t>> polygons(s.F.rows());
  for (Eigen::Index i = 0; i < s.F.rows(); ++i) {
    polygons[i] = {static_cast<std::size_t>(s.F(i, 0)), static_cast<std::size_t>(s.F(i, 1)),
                   static_cast<std::size_t>(s.F(i, 2))};
  }
  CgalSurface sm;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, sm);
  return sm;
}

SurfaceMesh from_cgal(const CgalSurface& sm) {
  SurfaceMesh s;
  s.V.resize(sm.number_of_vertices(), 3);
  std::map<CgalSurface::Vertex_index, int> index;
  int i = 0;
  for (auto v : sm.vertices()) {
    const Point& p = sm.point(v);
    s.V.row(i) << p.x(), p.y(), p.z();
    index[v] = i++;
  }
  s.F.resize(sm.number_of_faces(), 3);
  int f = 0;
  for (auto face : sm.faces()) {
    int c = 0;
    for (auto v : CGAL::vertices_around_face(sm.halfedge(face), sm)) s.F(f, c++) = index[v];
    ++f;
  }
  return s;
}

// Edge use counts on the raw triangle list: each undirected edge of a closed 2-manifold is used
// by exactly two triangles, once in each direction when consistently oriented.
void check_edges(const SurfaceMesh& s, const std::string& source) {
  std::map<std::pair<int, int>, int> uses;
  for (Eigen::Index f = 0; f < s.F.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int a = s.F(f, c), b = s.F(f, (c + 1) % 3);
      if (a == b) {
        throw InputError(source + ": face " + std::to_string(f) + " is degenerate (repeated vertex)");
      }
      ++uses[std::minmax(a, b)];
    }
  }
  for (const auto& [edge, count] : uses) {
    if (count == 1) {
      throw InputError(source + ": surface is not closed (edge " + std::to_string(edge.first) +
                       "-" + std::to_string(edge.second) + " borders only one face)");
    }
    if (count > 2) {
      throw InputError(source + ": surface is non-manifold (edge " + std::to_string(edge.first) +
                       "-" + std::to_string(edge.second) + " is shared by " +
                       std::to_string(count) + " faces)");
    }
  }
}

}  // namespace

void validate_surface(SurfaceMesh& surface, const std::string& source) {
  if (surface.F.rows() == 0 || surface.V.rows() < 4) throw InputError(source + ": surface is empty");
  if (!surface.V.allFinite()) throw InputError(source + ": surface has a non-finite coordinate");
  for (Eigen::Index i = 0; i < surface.F.size(); ++i) {
    if (surface.F.data()[i] < 0 || surface.F.data()[i] >= surface.V.rows()) {
      throw InputError(source + ": face refers to a missing vertex " + std::to_string(surface.F.data()[i]));
    }
  }
  // A point no face uses (files exported with stray vertices have them) is no part of the
  // surface, and CGAL's mesher crashes on one: drop it, keeping the others' order.
  if (remove_unreferenced_vertices(surface.V, surface.F) > 0 && surface.V.rows() < 4) {
    throw InputError(source + ": surface is empty");
  }
  check_edges(surface, source);

  std::vector<Point> points;
  for (Eigen::Index i = 0; i < surface.V.rows(); ++i) {
    points.emplace_back(surface.V(i, 0), surface.V(i, 1), surface.V(i, 2));
  }
  std::vector<std::vector<std::size_t>> polygons(surface.F.rows());
  for (Eigen::Index i = 0; i < surface.F.rows(); ++i) {
    polygons[i] = {static_cast<std::size_t>(surface.F(i, 0)), static_cast<std::size_t>(surface.F(i, 1)),
                   static_cast<std::size_t>(surface.F(i, 2))};
  }
  // Non-manifold vertices (two sheets touching at a point) and inconsistent orientation: the soup
  // can be oriented into a mesh only if every vertex has a single fan of faces.
  if (!PMP::is_polygon_soup_a_polygon_mesh(polygons)) {
    if (!PMP::orient_polygon_soup(points, polygons)) {
      throw InputError(source + ": surface is non-manifold (a vertex joins separate sheets)");
    }
  }
  CgalSurface sm;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, sm);
  if (!CGAL::is_closed(sm)) throw InputError(source + ": surface is not closed");
  if (PMP::does_self_intersect(sm)) throw InputError(source + ": surface intersects itself");
  if (!PMP::is_outward_oriented(sm)) PMP::reverse_face_orientations(sm);
  surface = from_cgal(sm);
}

SurfaceMesh read_surface(const std::string& path) {
  {
    std::ifstream probe(path);
    if (!probe) throw InputError(path + ": cannot open surface file");
  }
  std::vector<Point> points;
  std::vector<std::vector<std::size_t>> polygons;
  bool ok = false;
  try {
    ok = CGAL::IO::read_polygon_soup(path, points, polygons);
  } catch (const std::exception& e) {
    throw InputError(path + ": cannot read surface (" + e.what() + ")");
  }
  if (!ok || points.empty() || polygons.empty()) {
    throw InputError(path + ": cannot read surface (unsupported format or malformed file)");
  }
  SurfaceMesh s;
  s.V.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (size_t i = 0; i < points.size(); ++i) {
    s.V.row(static_cast<Eigen::Index>(i)) << points[i].x(), points[i].y(), points[i].z();
  }
  // Polygons with more than three corners are fanned into triangles.
  std::vector<std::array<int, 3>> tris;
  for (size_t f = 0; f < polygons.size(); ++f) {
    const auto& poly = polygons[f];
    if (poly.size() < 3) throw InputError(path + ": face " + std::to_string(f) + " has fewer than 3 vertices");
    for (size_t k = 1; k + 1 < poly.size(); ++k) {
      tris.push_back({static_cast<int>(poly[0]), static_cast<int>(poly[k]), static_cast<int>(poly[k + 1])});
    }
  }
  s.F.resize(static_cast<Eigen::Index>(tris.size()), 3);
  for (size_t i = 0; i < tris.size(); ++i) {
    for (int c = 0; c < 3; ++c) s.F(static_cast<Eigen::Index>(i), c) = tris[i][c];
  }
  validate_surface(s, path);
  return s;
}

double enclosed_volume(const SurfaceMesh& surface) {
  double v = 0;
  for (Eigen::Index f = 0; f < surface.F.rows(); ++f) {
    const Eigen::Vector3d a = surface.V.row(surface.F(f, 0)), b = surface.V.row(surface.F(f, 1)),
                          c = surface.V.row(surface.F(f, 2));
    v += a.dot(b.cross(c)) / 6.0;
  }
  return v;
}

TetMesh tetrahedralize_with_size(const SurfaceMesh& surface, double cell_size,
                                 const MeshingOptions& options, const std::string& source) {
  namespace params = CGAL::parameters;
  // Mesh_3 draws from CGAL's default generator; reseeding it makes every run identical.
  CGAL::get_default_random() = CGAL::Random(options.seed);
  CGAL::Random rng(options.seed);

  CgalSurface sm = to_cgal(surface);
  Domain domain(sm, &rng);
  domain.detect_features(options.feature_angle_deg);
  Criteria criteria(params::edge_size = cell_size, params::facet_angle = 25.0,
                    params::facet_size = cell_size,
                    params::facet_distance = cell_size * options.facet_distance_ratio,
                    params::cell_radius_edge_ratio = 3.0, params::cell_size = cell_size);
  Complex c3t3 = CGAL::make_mesh_3<Complex>(domain, criteria, params::no_perturb(),
                                            params::exude(params::time_limit = 0,
                                                          params::sliver_bound = 0));

  // Number vertices in order of first use by the cells, which follows the triangulation's
  // deterministic storage order.
  TetMesh mesh;
  std::unordered_map<const void*, int> index;
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 4>> tets;
  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c) {
    std::array<int, 4> tet;
    for (int k = 0; k < 4; ++k) {
      const auto v = c->vertex(k);
      auto [it, inserted] = index.emplace(&*v, static_cast<int>(points.size()));
      if (inserted) {
        const auto& p = v->point();
        points.emplace_back(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
      }
      tet[k] = it->second;
    }
    tets.push_back(tet);
  }
  mesh.V.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (size_t i = 0; i < points.size(); ++i) mesh.V.row(static_cast<Eigen::Index>(i)) = points[i];
  mesh.T.resize(static_cast<Eigen::Index>(tets.size()), 4);
  for (size_t i = 0; i < tets.size(); ++i) {
    for (int k = 0; k < 4; ++k) mesh.T(static_cast<Eigen::Index>(i), k) = tets[i][k];
  }
  if (mesh.num_tets() == 0) throw InputError(source + ": meshing produced no tetrahedra");
  orient_tets_positively(mesh);
  validate_tet_mesh(mesh, source);
  return mesh;
}

TetMesh tetrahedralize(const SurfaceMesh& surface, const MeshingOptions& options,
                       const std::string& source, MeshingOutcome* outcome) {
  if (options.target_tets < 10) {
    throw InputError(source + ": target_tets must be at least 10, got " +
                     std::to_string(options.target_tets));
  }
  const double volume = enclosed_volume(surface);
  if (!(volume > 0)) throw InputError(source + ": surface encloses no volume");
  // CGAL's meshes hold about one tet per 0.24 h^3 at cell size h (measured on the ball); the
  // count then steers h by the cube root of the ratio.
  double size = std::cbrt(volume / (0.24 * options.target_tets));
  TetMesh best;
  double best_error = std::numeric_limits<double>::infinity();
  std::string last_fault;
  MeshingOutcome record;
  record.target_tets = options.target_tets;
  record.tolerance = options.tolerance;
  for (int attempt = 0; attempt < options.max_attempts; ++attempt) {
    TetMesh mesh;
    try {
      mesh = tetrahedralize_with_size(surface, size, options, source);
    } catch (const InputError& e) {
      // Mesh_3 can leave a flat sliver at sharp features (seen on the star at 400 tets); another
      // cell size gives another mesh.
      last_fault = e.what();
      record.attempts.push_back({size, 0, last_fault});
      size *= 0.97;
      continue;
    }
    record.attempts.push_back({size, mesh.num_tets(), ""});
    const double ratio = static_cast<double>(mesh.num_tets()) / options.target_tets;
    const double error = std::abs(ratio - 1.0);
    if (error < best_error) {
      best_error = error;
      best = std::move(mesh);
    }
    if (error <= options.tolerance) break;
    size *= std::cbrt(ratio);
  }
  if (best.num_tets() == 0) throw InputError(last_fault);
  record.tets = best.num_tets();
  if (outcome) *outcome = std::move(record);
  return best;
}

const char* mesh_size_key(const std::string& shape) {
  return shape.empty() ? "volume" : shape == "sphere" ? "radius" : shape == "cube" ? "side" : "";
}

int default_tet_count(const std::string& shape) {
  static const std::map<std::string, int> counts = {
      {"sphere", 9056}, {"star", 1506}, {"bunny", 2274}, {"cube", 10164}, {"bat", 9098}};
  auto it = counts.find(shape);
  if (it == counts.end()) {
    throw InputError("unknown shape '" + shape + "' (expected sphere, cube, star, bat or bunny)");
  }
  return it->second;
}

std::string bunny_surface_path() {
  std::vector<std::string> candidates;
  if (const char* dir = std::getenv("RBAA_DATA_DIR")) candidates.push_back(std::string(dir) + "/bunny00.off");
  candidates.push_back(std::string(RBAA_CGAL_DATA_DIR) + "/bunny00.off");
  candidates.push_back("/usr/local/share/rbaa/bunny00.off");
  candidates.push_back("/usr/share/rbaa/bunny00.off");
  for (const auto& c : candidates) {
    if (std::ifstream(c)) return c;
  }
  throw InputError(
      "bunny00.off not found (looked in $RBAA_DATA_DIR, " + std::string(RBAA_CGAL_DATA_DIR) +
      ", /usr/local/share/rbaa): install libcgal-demo (scripts/install_deps.sh) and re-run cmake");
}

namespace {

// Scales the mesh about its centroid to the given volume and moves the centroid to the origin.
void normalise_volume(TetMesh& mesh, double volume) {
  const double current = tet_volumes(mesh).sum();
  const double scale = std::cbrt(volume / current);
  mesh.V *= scale;
  const Moments m = compute_moments(mesh, 1.0);
  mesh.V.rowwise() -= m.centre_of_mass().transpose();
}

}  // namespace

TetMesh mesh_surface_file(const std::string& path, int target_tets, double volume,
                          MeshingOutcome* outcome) {
  SurfaceMesh s = read_surface(path);
  MeshingOptions options;
  options.target_tets = target_tets;
  if (volume > 0) {
    // Mesh at about the wanted size so that the count target means the same thing.
    s.V *= std::cbrt(volume / enclosed_volume(s));
  }
  TetMesh mesh = tetrahedralize(s, options, path, outcome);
  if (volume > 0) normalise_volume(mesh, volume);
  return mesh;
}

TetMesh mesh_shape(const std::string& shape, int target_tets, const ShapeParameters& params,
                   MeshingOutcome* outcome) {
  if (target_tets <= 0) target_tets = default_tet_count(shape);
  else default_tet_count(shape);  // validates the name
  MeshingOptions options;
  options.target_tets = target_tets;
  if (shape == "sphere") {
    return tetrahedralize(sphere_surface(params.radius > 0 ? params.radius : 0.121), options,
                          "sphere", outcome);
  }
  if (shape == "cube") {
    return tetrahedralize(cube_surface(params.side > 0 ? params.side : 0.05), options, "cube",
                          outcome);
  }
  if (shape == "star") return tetrahedralize(star_surface(), options, "star", outcome);
  if (shape == "bat") {
    return tetrahedralize(lathe_surface(bat_profile(), 96), options, "bat", outcome);
  }
  // bunny: CGAL's bunny00.off is y-up; new (x, y, z) = old (z, x, y) stands it upright.
  const std::string path = bunny_surface_path();
  SurfaceMesh s = read_surface(path);
  for (Eigen::Index i = 0; i < s.V.rows(); ++i) {
    const Eigen::Vector3d old = s.V.row(i);
    s.V.row(i) << old.z(), old.x(), old.y();
  }
  const double volume = 1.5604;
  s.V *= std::cbrt(volume / enclosed_volume(s));
  TetMesh mesh = tetrahedralize(s, options, path, outcome);
  normalise_volume(mesh, volume);
  return mesh;
}

}  // namespace rbaa
