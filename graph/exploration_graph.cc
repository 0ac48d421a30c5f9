#include "graph/exploration_graph.h"

#include <algorithm>
#include <cassert>

namespace splam::graph {

Vertex AddNode(ExplorationGraph* graph, const kernel::Pose2& q) {
  NodeData data;
  data.configuration = q;
  return boost::add_vertex(std::move(data), *graph);
}

void AddEdge(ExplorationGraph* graph, Vertex a, Vertex b, std::vector<Eigen::Vector2d> path) {
  double length = 0.0;
  if (path.size() < 2) {
    length =
        ((*graph)[a].configuration.translation() - (*graph)[b].configuration.translation()).norm();
  } else {
    for (std::size_t k = 1; k < path.size(); ++k) length += (path[k] - path[k - 1]).norm();
  }
  if (a > b) std::reverse(path.begin(), path.end());
  boost::add_edge(a, b, EdgeData{std::move(path), length}, *graph);
}

bool HasEdge(const ExplorationGraph& graph, Vertex a, Vertex b) {
  return boost::edge(a, b, graph).second;
}

std::vector<Eigen::Vector2d> Waypoints(const ExplorationGraph& graph,
                                       const std::vector<Vertex>& vertices) {
  std::vector<Eigen::Vector2d> waypoints;
  for (std::size_t k = 1; k < vertices.size(); ++k) {
    const Vertex from = vertices[k - 1], to = vertices[k];
    const auto [edge, exists] = boost::edge(from, to, graph);
    assert(exists);
    std::vector<Eigen::Vector2d> path = graph[edge].path;
    if (path.size() < 2) {
      path = {graph[from].configuration.translation(), graph[to].configuration.translation()};
    } else if (from > to) {
      std::reverse(path.begin(), path.end());
    }
    waypoints.insert(waypoints.end(), path.begin() + 1, path.end());
  }
  return waypoints;
}

}  // namespace splam::graph
