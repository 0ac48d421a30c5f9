#include "graph/exploration_graph.h"

#include <algorithm>
#include <cassert>

namespace splam::graph {

Vertex AddNode(ExplorationGraph* graph, const kernel::Pose2& q) {
  NodeData data;
  data.configuration = q;
  return boost::add_vertex(std::move(data), *graph);
}

namespace {

// The length of the edge's path, or the straight-line distance between its ends without one.
double EdgeLength(const ExplorationGraph& graph, Vertex a, Vertex b,
                  const std::vector<Eigen::Vector2d>& path) {
  if (path.size() < 2)
    return (graph[a].configuration.translation() - graph[b].configuration.translation()).norm();
  double length = 0.0;
  for (std::size_t k = 1; k < path.size(); ++k) length += (path[k] - path[k - 1]).norm();
  return length;
}

}  // namespace

void AddEdge(ExplorationGraph* graph, Vertex a, Vertex b, std::vector<Eigen::Vector2d> path) {
  const double length = EdgeLength(*graph, a, b, path);
  if (a > b) std::reverse(path.begin(), path.end());
  boost::add_edge(a, b, EdgeData{std::move(path), length}, *graph);
}

void MoveNodes(ExplorationGraph* graph, const std::vector<kernel::Pose2>& poses) {
  ExplorationGraph& g = *graph;
  if (poses.empty() || poses.size() != boost::num_vertices(g)) return;
  std::vector<kernel::Pose2> corrections;  // moved_T_world of every node
  bool moved = false;
  for (Vertex v = 0; v < poses.size(); ++v) {
    corrections.push_back(poses[v] * g[v].configuration.Inverse());
    moved = moved || corrections.back().translation().norm() > 1e-9 ||
            std::abs(corrections.back().theta()) > 1e-12;
  }
  if (!moved) return;
  for (Vertex v = 0; v < poses.size(); ++v) {
    NodeData& node = g[v];
    node.configuration = poses[v];
    node.lsr = node.lsr.Transformed(corrections[v]);
    for (auto& arc : node.frontiers) arc = arc.Turned(corrections[v].theta());
    for (auto& given_up : node.given_up) given_up.arc = given_up.arc.Turned(corrections[v].theta());
  }
  for (const auto e : boost::make_iterator_range(boost::edges(g))) {
    EdgeData& edge = g[e];
    const auto a = std::min(boost::source(e, g), boost::target(e, g));
    const auto b = std::max(boost::source(e, g), boost::target(e, g));
    std::vector<double> along{0.0};
    for (std::size_t i = 1; i < edge.path.size(); ++i)
      along.push_back(along.back() + (edge.path[i] - edge.path[i - 1]).norm());
    for (std::size_t i = 0; i < edge.path.size(); ++i) {
      const double s = along.back() > 0 ? along[i] / along.back() : 0.0;
      const Eigen::Vector2d p = edge.path[i];
      edge.path[i] = (1.0 - s) * (corrections[a] * p) + s * (corrections[b] * p);
    }
    edge.length_m = EdgeLength(g, a, b, edge.path);
  }
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
