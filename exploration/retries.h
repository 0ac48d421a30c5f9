#ifndef SPLAM_EXPLORATION_RETRIES_H_
#define SPLAM_EXPLORATION_RETRIES_H_

#include <Eigen/Core>
#include <optional>
#include <utility>
#include <vector>

#include "exploration/session.h"
#include "graph/exploration_graph.h"

namespace splam::exploration {

// A frontier given up at its node and still open in the map, retried from another node
// (ExplorerOptions::retry_nodes): the robot drives to `node` along the graph, then `approach`
// inside its LSR, as near to `target` (the frontier's sight point, FrontierRules::ArcSight,
// ShadowSight or UnseenSight) as it gets; an empty approach turns in place at the node.
struct Retry {
  graph::Vertex node;
  std::vector<Eigen::Vector2d> approach;
  Eigen::Vector2d target;
};

// The retries of one run: which frontier was retried from which node. A node in a doorway
// perceives the corridor behind it with the sonars only, whose blind spikes between the cones
// close the way back (docs/experiments.md, Fig. 18); the papers give a frontier up for good.
class Retries {
 public:
  // The next retry, recorded as made: among the frontiers given up and still open
  // (Session::GivenUpFrontiers), retried from fewer than retry_nodes other nodes, the node
  // (neither the owner nor one tried for it) with the reachable point nearest to the target
  // that is nearer than the owner and sees it through the union of the LSRs
  // (kernel::UnionLineOfSight); an unseen stretch is looked at from the nearest node that sees
  // its deepest point. nullopt when there is none, or grid_paths is off, or retry_nodes is 0.
  std::optional<Retry> Next(const Session& session);

 private:
  std::vector<std::pair<Eigen::Vector2d, graph::Vertex>> made_;  // (target, node)
};

// Carries a retry out from node `current`: along the graph (graph::BidirectionalAStar) to the
// retry's node, then its approach, facing the target; returns the node where the robot is then
// (a new one, child of the retry's node, when the approach was driven).
graph::Vertex DriveRetry(Session* session, graph::Vertex current, const Retry& retry);

}  // namespace splam::exploration

#endif  // SPLAM_EXPLORATION_RETRIES_H_
