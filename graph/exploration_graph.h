#ifndef SPLAM_GRAPH_EXPLORATION_GRAPH_H_
#define SPLAM_GRAPH_EXPLORATION_GRAPH_H_

#include <Eigen/Core>
#include <boost/graph/adjacency_list.hpp>
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

// Undirected, vertices in a vector (stable indices: exploration never removes nodes).
using ExplorationGraph =
    boost::adjacency_list<boost::vecS, boost::vecS, boost::undirectedS, NodeData, EdgeData>;
using Vertex = boost::graph_traits<ExplorationGraph>::vertex_descriptor;

// Adds a node at configuration q; returns its vertex.
Vertex AddNode(ExplorationGraph* graph, const kernel::Pose2& q);
// Adds an edge along `path` from a to b (its ends should be the two configurations; it is stored
// from the lower to the higher vertex); its length is the polyline's length, or the straight-line
// distance when the path is empty.
void AddEdge(ExplorationGraph* graph, Vertex a, Vertex b, std::vector<Eigen::Vector2d> path = {});
// Moves the nodes to `poses` (one per vertex, in order; nothing when the sizes differ), as when a
// pose graph revises where the nodes were: each node's configuration, LSR and frontiers (open and
// given up) by its own rigid correction, and every point of a stored path by the blend of its two
// ends' corrections in proportion to its arc length along the path, so the path joins the moved
// nodes; edge lengths follow.
void MoveNodes(ExplorationGraph* graph, const std::vector<kernel::Pose2>& poses);
// True when a and b are joined by an edge.
bool HasEdge(const ExplorationGraph& graph, Vertex a, Vertex b);
// The waypoints that lead along the vertex path `vertices` (consecutive vertices must be joined):
// every edge's path oriented in the direction of travel, without the starting configuration;
// straight lines for edges without a path.
std::vector<Eigen::Vector2d> Waypoints(const ExplorationGraph& graph,
                                       const std::vector<Vertex>& vertices);

}  // namespace splam::graph

#endif  // SPLAM_GRAPH_EXPLORATION_GRAPH_H_
