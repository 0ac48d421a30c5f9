#include "graph/exploration_graph.h"

namespace splam::graph {

Vertex AddNode(ExplorationGraph* graph, const kernel::Pose2& q) {
  return boost::add_vertex(NodeData{q}, *graph);
}

void AddEdge(ExplorationGraph* graph, Vertex a, Vertex b, std::vector<Eigen::Vector2d> path) {
  double length = 0.0;
  if (path.size() < 2) {
    length =
        ((*graph)[a].configuration.translation() - (*graph)[b].configuration.translation()).norm();
  } else {
    for (std::size_t k = 1; k < path.size(); ++k) length += (path[k] - path[k - 1]).norm();
  }
  boost::add_edge(a, b, EdgeData{std::move(path), length}, *graph);
}

}  // namespace splam::graph
