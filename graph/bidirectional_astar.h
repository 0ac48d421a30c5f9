#ifndef SPLAM_GRAPH_BIDIRECTIONAL_ASTAR_H_
#define SPLAM_GRAPH_BIDIRECTIONAL_ASTAR_H_

#include <optional>
#include <vector>

#include "graph/exploration_graph.h"

namespace splam::graph {

struct GraphPath {
  std::vector<Vertex> vertices;  // from the source to the target reached
  double length_m = 0.0;         // sum of the edge lengths
};

struct SearchStats {
  int expanded = 0;  // vertices settled by both searches together
};

// FIND_PATH of REG (paper 003 §3.1): the shortest path by graph distance (edge lengths, not
// straight lines: walls make near nodes far) from `source` to the nearest of `targets`.
//
// Bidirectional A* with the average potentials of Ikeda et al. / Goldberg & Harrelson: the
// forward search estimates the distance to the target set by pi_f(v) = min_t |v - t|, the
// backward search (from all targets at once, as from one virtual node joined to each target by a
// zero-length edge) estimates the distance to the source by pi_r(v) = |v - s|. Both are
// consistent because an edge is never shorter than the straight line, so with
// p(v) = (pi_f(v) - pi_r(v)) / 2 the reduced lengths l(u, v) - p(u) + p(v) are non-negative and
// the two searches are Dijkstra's on them; they stop when the smallest keys of both queues sum to
// at least the best path found. The result is exact: its length equals Dijkstra's.
// nullopt when no target is reachable (or `targets` is empty).
std::optional<GraphPath> BidirectionalAStar(const ExplorationGraph& graph, Vertex source,
                                            const std::vector<Vertex>& targets,
                                            SearchStats* stats = nullptr);

}  // namespace splam::graph

#endif  // SPLAM_GRAPH_BIDIRECTIONAL_ASTAR_H_
