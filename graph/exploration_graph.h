#ifndef SPLAM_GRAPH_EXPLORATION_GRAPH_H_
#define SPLAM_GRAPH_EXPLORATION_GRAPH_H_

#include <Eigen/Core>
#include <boost/graph/adjacency_list.hpp>
#include <cstddef>
#include <string>
#include <vector>

#include "kernel/local_safe_region.h"
#include "kernel/pose2.h"

// The graph that exploration builds (paper 003 §3.1, SPEC §9): a node per configuration where
// the robot sensed, an edge per collision-free path between two of them.
namespace splam::graph {

// A frontier the explorer gave up at a node, and why: a free arc, or (shadow_edge >= 0) the
// space hidden behind that boundary edge of the node's LSR (kernel::OcclusionEdges).
struct GivenUpArc {
  kernel::FrontierArc arc;
  std::string reason;
  int shadow_edge = -1;
};

struct NodeData {
  kernel::Pose2 configuration;                 // world frame
  kernel::LocalSafeRegion lsr;                 // perceived at the configuration
  std::vector<kernel::FrontierArc> frontiers;  // free frontiers of the LSR not yet explored
  std::vector<std::size_t> shadows;  // occlusion edges of the LSR whose hidden side is unseen
  std::vector<GivenUpArc> given_up;  // frontiers of the LSR given up
};

struct EdgeData {
  // The collision-free path between the two nodes (world frame, from the lower to the higher
  // vertex index) and its length, metres. Lengths are never shorter than the straight line
  // between the two configurations, which keeps the A* heuristics admissible.
  std::vector<Eigen::Vector2d> path;
  double length_m = 0.0;
};

// A node's index: nodes are numbered 0, 1, ... in the order they were added and never removed.
using Vertex = std::size_t;

// An edge as ExplorationGraph::Edges lists it: its ends, a < b, and its data.
struct EdgeRef {
  Vertex a = 0, b = 0;
  const EdgeData* data = nullptr;
};

// Undirected; Boost.Graph's adjacency list inside (vertices in a vector: stable indices).
class ExplorationGraph {
 public:
  std::size_t num_nodes() const { return boost::num_vertices(graph_); }
  std::size_t num_edges() const { return boost::num_edges(graph_); }
  NodeData& operator[](Vertex v) { return graph_[v]; }
  const NodeData& operator[](Vertex v) const { return graph_[v]; }

  // Adds a node at configuration q; returns its vertex.
  Vertex AddNode(const kernel::Pose2& q);
  // Adds an edge along `path` from a to b (its ends should be the two configurations; it is
  // stored from the lower to the higher vertex); its length is the polyline's length, or the
  // straight-line distance when the path is empty.
  void AddEdge(Vertex a, Vertex b, std::vector<Eigen::Vector2d> path = {});
  // True when a and b are joined by an edge.
  bool HasEdge(Vertex a, Vertex b) const { return Edge(a, b) != nullptr; }
  // The edge joining a and b, or null.
  const EdgeData* Edge(Vertex a, Vertex b) const;
  // Every edge once.
  std::vector<EdgeRef> Edges() const;
  // Calls visit(w, edge) for every neighbour w of v and the edge that joins them.
  template <class Visit>
  void ForEachNeighbour(Vertex v, Visit visit) const {
    for (auto [e, end] = boost::out_edges(v, graph_); e != end; ++e)
      visit(static_cast<Vertex>(boost::target(*e, graph_)), graph_[*e]);
  }

  // Moves the nodes to `poses` (one per vertex, in order; nothing when the sizes differ), as when
  // a pose graph revises where the nodes were: each node's configuration, LSR and frontiers (open
  // and given up) by its own rigid correction, and every point of a stored path by the blend of
  // its two ends' corrections in proportion to its arc length along the path, so the path joins
  // the moved nodes; edge lengths follow.
  void MoveNodes(const std::vector<kernel::Pose2>& poses);
  // The waypoints that lead along the vertex path `vertices` (consecutive vertices must be
  // joined): every edge's path oriented in the direction of travel, without the starting
  // configuration; straight lines for edges without a path.
  std::vector<Eigen::Vector2d> Waypoints(const std::vector<Vertex>& vertices) const;
  // Dijkstra from `source` by edge length (Boost.Graph): the graph distance of every vertex
  // (infinity when unreachable), and in *previous each vertex's predecessor on its shortest
  // path (itself for the source and the unreachable).
  std::vector<double> DistancesFrom(Vertex source, std::vector<Vertex>* previous) const;

 private:
  using Graph =
      boost::adjacency_list<boost::vecS, boost::vecS, boost::undirectedS, NodeData, EdgeData>;
  // The length of `path`, or the straight-line distance between a and b without one.
  double EdgeLength(Vertex a, Vertex b, const std::vector<Eigen::Vector2d>& path) const;

  Graph graph_;
};

}  // namespace splam::graph

#endif  // SPLAM_GRAPH_EXPLORATION_GRAPH_H_
