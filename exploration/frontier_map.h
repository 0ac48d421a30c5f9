#ifndef SPLAM_EXPLORATION_FRONTIER_MAP_H_
#define SPLAM_EXPLORATION_FRONTIER_MAP_H_

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "exploration/explorer.h"
#include "exploration/frontier_rules.h"
#include "graph/exploration_graph.h"
#include "kernel/local_safe_region.h"
#include "kernel/pose2.h"

// What the explorer's map, the union of its nodes' LSRs (an exploration graph), says of the
// frontiers, by the FrontierRules: which parts are still open, whether a point is in sight, and
// at the end of a run which given-up frontiers are still open.
namespace splam::exploration {

// The LSRs of the nodes other than v that can reach view_depth beyond v's circle.
std::vector<const kernel::LocalSafeRegion*> OthersNear(const FrontierRules& rules,
                                                       const graph::ExplorationGraph& g,
                                                       graph::Vertex v);
// The parts of `arc` (a frontier of node v) that the union of the other nodes' LSRs does not
// cover: what the map says is still unknown beyond it.
std::vector<kernel::FrontierArc> OpenParts(const FrontierRules& rules,
                                           const graph::ExplorationGraph& g, graph::Vertex v,
                                           const kernel::FrontierArc& arc);
// Whether no other node's LSR sees behind occlusion edge `edge` of node v's LSR.
bool ShadowOpen(const FrontierRules& rules, const graph::ExplorationGraph& g, graph::Vertex v,
                std::size_t edge);
// Whether the segment from `from` to `point` runs inside the union of the nodes' LSRs
// (kernel::UnionLineOfSight).
bool InSight(const FrontierRules& rules, const graph::ExplorationGraph& g,
             const Eigen::Vector2d& from, const Eigen::Vector2d& point);
// The configurations of all the nodes.
std::vector<Eigen::Vector2d> NodePositions(const graph::ExplorationGraph& g);

// The nodes' given-up arcs and shadows (graph::NodeData::given_up), each checked against the
// union of the other nodes' LSRs (OpenParts, ShadowOpen; an arc also against every node's laser
// hits within frontier_view_depth_m behind it), and, with unseen_frontiers, the unseen
// stretches: the stretches of the nodes' LSR boundaries that only the sonars bounded (beams past
// the laser's) and beyond which no node's laser saw nor hit an obstacle within
// frontier_view_depth_m, at least min_frontier_m long. A sonar echo may come from anywhere in its
// cone, so such a boundary is no obstacle and what lies behind it is unknown. `run` holds the
// graph and the nodes' records (their scans); the laser is mounted at robot_T_laser.
std::vector<GivenUpFrontier> GivenUpFrontiers(const FrontierRules& rules, const ExplorationRun& run,
                                              const kernel::Pose2& robot_T_laser);

}  // namespace splam::exploration

#endif  // SPLAM_EXPLORATION_FRONTIER_MAP_H_
