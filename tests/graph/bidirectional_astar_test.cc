// FIND_PATH: bidirectional A* to the nearest of several targets, against Dijkstra.
#include "graph/bidirectional_astar.h"

#include <gtest/gtest.h>

#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/dijkstra_shortest_paths.hpp>
#include <limits>

#include "kernel/random.h"

namespace splam::graph {
namespace {

// Random nodes in a 20 m square, joined when closer than `radius`; every edge is at least as
// long as the straight line (a detour factor of 1-1.5), as collision-free paths are.
ExplorationGraph RandomGraph(kernel::Random* random, int nodes, double radius) {
  ExplorationGraph g;
  for (int i = 0; i < nodes; ++i)
    g.AddNode(kernel::Pose2(random->Uniform(0, 20), random->Uniform(0, 20), 0));
  for (Vertex a = 0; a < g.num_nodes(); ++a) {
    for (Vertex b = a + 1; b < g.num_nodes(); ++b) {
      const Eigen::Vector2d pa = g[a].configuration.translation();
      const Eigen::Vector2d pb = g[b].configuration.translation();
      if ((pa - pb).norm() > radius) continue;
      const Eigen::Vector2d bend =
          0.5 * (pa + pb) + random->Uniform(0, 0.5) * (pa - pb).norm() *
                                Eigen::Vector2d(-(pb - pa).y(), (pb - pa).x()).normalized();
      g.AddEdge(a, b, {pa, bend, pb});
    }
  }
  return g;
}

double DijkstraToNearest(const ExplorationGraph& g, Vertex source,
                         const std::vector<Vertex>& targets) {
  // Boost.Graph's Dijkstra on a copy of the edges: a reference independent of the class.
  using Reference =
      boost::adjacency_list<boost::vecS, boost::vecS, boost::undirectedS, boost::no_property,
                            boost::property<boost::edge_weight_t, double>>;
  Reference reference(g.num_nodes());
  for (const EdgeRef& e : g.Edges()) boost::add_edge(e.a, e.b, e.data->length_m, reference);
  std::vector<double> d(g.num_nodes());
  boost::dijkstra_shortest_paths(reference, source, boost::distance_map(d.data()));
  double best = std::numeric_limits<double>::max();
  for (const Vertex t : targets) best = std::min(best, d[t]);
  return best;
}

TEST(BidirectionalAStar, PropertyPathCostEqualsDijkstraOnRandomGraphs) {
  kernel::Random random(41);
  int unreachable = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const ExplorationGraph g =
        RandomGraph(&random, 5 + static_cast<int>(random.Index(80)), random.Uniform(2.0, 6.0));
    const Vertex n = g.num_nodes();
    const Vertex source = random.Index(n);
    std::vector<Vertex> targets;
    const int count = 1 + static_cast<int>(random.Index(4));
    for (int k = 0; k < count; ++k) targets.push_back(random.Index(n));
    const double expected = DijkstraToNearest(g, source, targets);
    SearchStats stats;
    const std::optional<GraphPath> path = BidirectionalAStar(g, source, targets, &stats);
    if (expected == std::numeric_limits<double>::max()) {
      EXPECT_FALSE(path.has_value()) << trial;
      ++unreachable;
      continue;
    }
    ASSERT_TRUE(path.has_value()) << trial;
    EXPECT_NEAR(path->length_m, expected, 1e-9) << trial;
    // A real path: from the source, along edges, to a target.
    ASSERT_FALSE(path->vertices.empty());
    EXPECT_EQ(path->vertices.front(), source);
    EXPECT_NE(std::find(targets.begin(), targets.end(), path->vertices.back()), targets.end());
    for (std::size_t k = 1; k < path->vertices.size(); ++k)
      EXPECT_TRUE(g.HasEdge(path->vertices[k - 1], path->vertices[k])) << trial;
    EXPECT_LE(stats.expanded, 2 * static_cast<int>(n) + 1);
  }
  EXPECT_GT(unreachable, 10);  // the random graphs include disconnected ones
  EXPECT_LT(unreachable, 200);
}

TEST(BidirectionalAStar, GraphDistanceNotStraightLine) {
  // Target 3 is nearer in a straight line, but the way to it goes around a wall.
  ExplorationGraph g;
  const Vertex s = g.AddNode(kernel::Pose2(0, 0, 0));
  const Vertex a = g.AddNode(kernel::Pose2(0, 5, 0));
  const Vertex near_behind_wall = g.AddNode(kernel::Pose2(1, 0, 0));
  const Vertex far_open = g.AddNode(kernel::Pose2(-3, 0, 0));
  g.AddEdge(s, a);
  g.AddEdge(a, near_behind_wall);
  g.AddEdge(s, far_open);
  const auto path = BidirectionalAStar(g, s, {near_behind_wall, far_open});
  ASSERT_TRUE(path.has_value());
  EXPECT_EQ(path->vertices, (std::vector<Vertex>{s, far_open}));
  EXPECT_DOUBLE_EQ(path->length_m, 3.0);
}

TEST(BidirectionalAStar, EdgeCases) {
  ExplorationGraph g;
  const Vertex s = g.AddNode(kernel::Pose2(0, 0, 0));
  const Vertex island = g.AddNode(kernel::Pose2(1, 0, 0));
  EXPECT_FALSE(BidirectionalAStar(g, s, {}).has_value());
  EXPECT_FALSE(BidirectionalAStar(g, s, {island}).has_value());  // not connected
  const auto here = BidirectionalAStar(g, s, {s, island});
  ASSERT_TRUE(here.has_value());
  EXPECT_EQ(here->vertices, std::vector<Vertex>{s});
  EXPECT_EQ(here->length_m, 0.0);
}

}  // namespace
}  // namespace splam::graph
