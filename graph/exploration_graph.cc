#include "graph/exploration_graph.h"

#include <boost/graph/dijkstra_shortest_paths.hpp>

#include <algorithm>
#include <cassert>
#include <limits>

namespace splam::graph {

Vertex ExplorationGraph::AddNode(const kernel::Pose2& q) {
  NodeData data;
  data.configuration = q;
  return boost::add_vertex(std::move(data), graph_);
}

double ExplorationGraph::EdgeLength(Vertex a, Vertex b,
                                    const std::vector<Eigen::Vector2d>& path) const {
  if (path.size() < 2)
    return (graph_[a].configuration.translation() - graph_[b].configuration.translation()).norm();
  double length = 0.0;
  for (std::size_t k = 1; k < path.size(); ++k) length += (path[k] - path[k - 1]).norm();
  return length;
}

void ExplorationGraph::AddEdge(Vertex a, Vertex b, std::vector<Eigen::Vector2d> path) {
  const double length = EdgeLength(a, b, path);
  if (a > b) std::reverse(path.begin(), path.end());
  boost::add_edge(a, b, EdgeData{std::move(path), length}, graph_);
}

const EdgeData* ExplorationGraph::Edge(Vertex a, Vertex b) const {
  if (a >= num_nodes() || b >= num_nodes()) return nullptr;
  const auto [edge, exists] = boost::edge(a, b, graph_);
  return exists ? &graph_[edge] : nullptr;
}

std::vector<EdgeRef> ExplorationGraph::Edges() const {
  std::vector<EdgeRef> edges;
  edges.reserve(num_edges());
  for (auto [e, end] = boost::edges(graph_); e != end; ++e) {
    const Vertex s = boost::source(*e, graph_), t = boost::target(*e, graph_);
    edges.push_back({std::min(s, t), std::max(s, t), &graph_[*e]});
  }
  return edges;
}

void ExplorationGraph::MoveNodes(const std::vector<kernel::Pose2>& poses) {
  if (poses.empty() || poses.size() != num_nodes()) return;
  std::vector<kernel::Pose2> corrections;  // moved_T_world of every node
  bool moved = false;
  for (Vertex v = 0; v < poses.size(); ++v) {
    corrections.push_back(poses[v] * graph_[v].configuration.Inverse());
    moved = moved || corrections.back().translation().norm() > 1e-9 ||
            std::abs(corrections.back().theta()) > 1e-12;
  }
  if (!moved) return;
  for (Vertex v = 0; v < poses.size(); ++v) {
    NodeData& node = graph_[v];
    node.configuration = poses[v];
    node.lsr = node.lsr.Transformed(corrections[v]);
    for (auto& arc : node.frontiers) arc = arc.Turned(corrections[v].theta());
    for (auto& given_up : node.given_up) given_up.arc = given_up.arc.Turned(corrections[v].theta());
  }
  for (auto [e, end] = boost::edges(graph_); e != end; ++e) {
    EdgeData& edge = graph_[*e];
    const Vertex s = boost::source(*e, graph_), t = boost::target(*e, graph_);
    const Vertex a = std::min(s, t), b = std::max(s, t);
    std::vector<double> along{0.0};
    for (std::size_t i = 1; i < edge.path.size(); ++i)
      along.push_back(along.back() + (edge.path[i] - edge.path[i - 1]).norm());
    for (std::size_t i = 0; i < edge.path.size(); ++i) {
      const double f = along.back() > 0 ? along[i] / along.back() : 0.0;
      const Eigen::Vector2d p = edge.path[i];
      edge.path[i] = (1.0 - f) * (corrections[a] * p) + f * (corrections[b] * p);
    }
    edge.length_m = EdgeLength(a, b, edge.path);
  }
}

std::vector<Eigen::Vector2d> ExplorationGraph::Waypoints(
    const std::vector<Vertex>& vertices) const {
  std::vector<Eigen::Vector2d> waypoints;
  for (std::size_t k = 1; k < vertices.size(); ++k) {
    const Vertex from = vertices[k - 1], to = vertices[k];
    const EdgeData* edge = Edge(from, to);
    assert(edge != nullptr);
    std::vector<Eigen::Vector2d> path = edge->path;
    if (path.size() < 2) {
      path = {graph_[from].configuration.translation(), graph_[to].configuration.translation()};
    } else if (from > to) {
      std::reverse(path.begin(), path.end());
    }
    waypoints.insert(waypoints.end(), path.begin() + 1, path.end());
  }
  return waypoints;
}

std::vector<double> ExplorationGraph::DistancesFrom(Vertex source,
                                                    std::vector<Vertex>* previous) const {
  std::vector<double> distance(num_nodes());
  previous->assign(num_nodes(), 0);
  boost::dijkstra_shortest_paths(graph_, source,
                                 boost::predecessor_map(previous->data())
                                     .distance_map(distance.data())
                                     .weight_map(boost::get(&EdgeData::length_m, graph_)));
  for (Vertex v = 0; v < num_nodes(); ++v)
    if (v != source && (*previous)[v] == v) distance[v] = std::numeric_limits<double>::infinity();
  return distance;
}

}  // namespace splam::graph
