// Tutorial: the exploration graph and FIND_PATH (bidirectional A* to the nearest of several
// nodes), on a small hand-made graph with a wall in it.
// Usage: example_graph
#include <cstdio>

#include "graph/bidirectional_astar.h"
#include "graph/exploration_graph.h"

int main() {
  namespace graph = splam::graph;
  using splam::kernel::Pose2;

  // 1. Nodes are configurations where the robot sensed; edges are collision-free paths between
  //    them. A wall runs along x = 2 from y = -1 to y = 3: nodes on its two sides are joined only
  //    around its top end.
  graph::ExplorationGraph g;
  const graph::Vertex start = g.AddNode(Pose2(0, 0, 0));
  const graph::Vertex up = g.AddNode(Pose2(0, 3.5, 0));
  const graph::Vertex over = g.AddNode(Pose2(4, 3.5, 0));
  const graph::Vertex behind_wall = g.AddNode(Pose2(4, 0, 0));
  const graph::Vertex left = g.AddNode(Pose2(-3, 0, 0));
  const graph::Vertex far_left = g.AddNode(Pose2(-5.5, 0, 0));
  g.AddEdge(start, up);  // straight: the path's length is the distance
  g.AddEdge(up, over, {{0, 3.5}, {2, 3.6}, {4, 3.5}});  // a path with a bend
  g.AddEdge(over, behind_wall);
  g.AddEdge(start, left);
  g.AddEdge(left, far_left);

  // 2. Two nodes still have free frontiers (the frontier-control list of REG). The one behind
  //    the wall is nearer as the crow flies (4 m) but 11 m away along the graph; the one far to
  //    the left is 5.5 m away. FIND_PATH searches from the robot's node towards both at once.
  graph::SearchStats stats;
  const auto path = graph::BidirectionalAStar(g, start, {behind_wall, far_left}, &stats);
  if (!path) {
    std::printf("no listed node is reachable\n");
    return 1;
  }
  std::printf("path to node %zu, %.2f m along the graph, %d vertices expanded:",
              path->vertices.back(), path->length_m, stats.expanded);
  for (const graph::Vertex v : path->vertices) {
    const Eigen::Vector2d p = g[v].configuration.translation();
    std::printf(" (%.1f, %.1f)", p.x(), p.y());
  }
  std::printf("\n");
  return path->vertices.back() == far_left ? 0 : 1;
}
