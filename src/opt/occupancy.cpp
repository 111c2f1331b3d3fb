#include "rbaa/opt/occupancy.hpp"

#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/dijkstra_shortest_paths.hpp>
#include <boost/property_map/function_property_map.hpp>

#include <functional>
#include <limits>
#include <sstream>

#include "rbaa/error.hpp"
#include "rbaa/mesh/topology.hpp"

namespace rbaa {

Eigen::VectorXd round_occupancy(const Eigen::VectorXd& alpha, const std::vector<char>& boundary,
                                double threshold) {
  if (!(threshold > 0.0 && threshold < 1.0)) {
    std::ostringstream msg;
    msg << "occupancy rounding threshold = " << threshold << " must lie in (0, 1)";
    throw InputError(msg.str());
  }
  if (static_cast<size_t>(alpha.size()) != boundary.size()) {
    throw InputError("round_occupancy: alpha and the boundary flags differ in size");
  }
  Eigen::VectorXd out(alpha.size());
  for (Eigen::Index e = 0; e < alpha.size(); ++e) {
    out[e] = (boundary[e] || alpha[e] >= threshold) ? 1.0 : 0.0;
  }
  return out;
}

ConnectivityReport repair_connectivity(const TetMesh& mesh, const std::vector<char>& boundary,
                                       Eigen::VectorXd& alpha) {
  const int nt = mesh.num_tets();
  if (alpha.size() != nt || static_cast<int>(boundary.size()) != nt) {
    throw InputError("repair_connectivity: alpha or boundary flags do not have one entry per element");
  }
  std::vector<char> occupied(nt, 0);
  for (int e = 0; e < nt; ++e) {
    if (alpha[e] != 0.0 && alpha[e] != 1.0) {
      std::ostringstream msg;
      msg << "repair_connectivity: alpha of element " << e << " is " << alpha[e]
          << "; round the occupancy to {0, 1} first";
      throw InputError(msg.str());
    }
    if (boundary[e] && alpha[e] != 1.0) {
      throw InputError("repair_connectivity: boundary element " + std::to_string(e) + " is void");
    }
    occupied[e] = alpha[e] == 1.0;
  }
  const Tets adj = face_adjacency(mesh);
  if (count_components(mesh) != 1) {
    throw InputError("repair_connectivity: the tet mesh itself is not face-connected");
  }
  const Eigen::VectorXd volume = tet_volumes(mesh);

  // The dual graph, one arc per direction of each interior face; an arc's weight is the cost of
  // entering its target, which changes as void elements are filled (read through a function map).
  using Graph = boost::adjacency_list<boost::vecS, boost::vecS, boost::directedS>;
  using Edge = boost::graph_traits<Graph>::edge_descriptor;
  Graph graph(nt);
  for (int e = 0; e < nt; ++e) {
    for (int k = 0; k < 4; ++k) {
      if (adj(e, k) >= 0) boost::add_edge(e, adj(e, k), graph);
    }
  }
  const auto weight = boost::make_function_property_map<Edge, double>(
      [&](const Edge& arc) {
        const int t = static_cast<int>(boost::target(arc, graph));
        return occupied[t] ? 0.0 : volume[t];
      });

  ConnectivityReport report;
  std::vector<int> label;
  report.components_before = label_components(adj, occupied, label);
  int components = report.components_before;

  std::vector<double> distance(nt);
  std::vector<Graph::vertex_descriptor> predecessor(nt);
  std::vector<int> sources;
  const double inf = std::numeric_limits<double>::infinity();
  while (components > 1) {
    // The tree: the component with the most boundary elements (lowest label on ties).
    std::vector<int> boundary_count(components, 0);
    for (int e = 0; e < nt; ++e) {
      if (boundary[e] && label[e] >= 0) ++boundary_count[label[e]];
    }
    int root = 0;
    for (int c = 1; c < components; ++c) {
      if (boundary_count[c] > boundary_count[root]) root = c;
    }
    sources.clear();
    for (int e = 0; e < nt; ++e) {
      if (label[e] == root) sources.push_back(e);
    }
    boost::dijkstra_shortest_paths(
        graph, sources.begin(), sources.end(),
        boost::make_iterator_property_map(predecessor.begin(), boost::get(boost::vertex_index, graph)),
        boost::make_iterator_property_map(distance.begin(), boost::get(boost::vertex_index, graph)),
        weight, boost::get(boost::vertex_index, graph), std::less<double>(),
        boost::closed_plus<double>(inf), inf, 0.0, boost::default_dijkstra_visitor());
    // The nearest element of another component (lowest index on ties).
    int target = -1;
    for (int e = 0; e < nt; ++e) {
      if (label[e] >= 0 && label[e] != root && (target < 0 || distance[e] < distance[target])) {
        target = e;
      }
    }
    if (target < 0 || !(distance[target] < inf)) {
      throw SolverError("repair_connectivity: no path between occupied components");
    }
    // Fill the void elements along the path back to the tree.
    for (int e = static_cast<int>(predecessor[target]); label[e] != root;
         e = static_cast<int>(predecessor[e])) {
      if (!occupied[e]) {
        occupied[e] = 1;
        alpha[e] = 1.0;
        ++report.elements_added;
        report.volume_added += volume[e];
      }
    }
    const int before = components;
    components = label_components(adj, occupied, label);
    if (components >= before) throw SolverError("repair_connectivity: a path joined nothing");
  }
  report.components_after = components;
  return report;
}

}  // namespace rbaa
