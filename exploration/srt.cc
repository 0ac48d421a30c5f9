#include "exploration/srt.h"

#include <cmath>
#include <map>
#include <optional>
#include <string>

#include "exploration/internal/session.h"
#include "exploration/internal/steps.h"

namespace splam::exploration {

ExplorationRun SrtExplorer::Run(RobotInterface* robot, Localization* localization) {
  internal::Session session("srt", options_, robot, localization);
  if (!session.Start()) return session.Finish();
  graph::ExplorationGraph& g = session.graph();
  graph::Vertex current = session.AddNodeHere(-1);
  const double step = options_.alpha * options_.lsr_radius_m;
  std::map<graph::Vertex, int> failed_returns;  // failed backtracks from each node
  while (!session.CapReached()) {
    std::optional<std::vector<Eigen::Vector2d>> path;  // to the new node's configuration
    {
      internal::Session::PlanningTimer timer(&session);
      const graph::NodeData& node = g[current];
      const Eigen::Vector2d here = node.configuration.translation();
      for (int attempt = 0; attempt < options_.srt_max_attempts && !node.frontiers.empty();
           ++attempt) {
        const double theta = internal::RandomDirection(node.frontiers, &session.random());
        const Eigen::Vector2d candidate =
            node.lsr.center() + step * Eigen::Vector2d(std::cos(theta), std::sin(theta));
        // VALID_CONF: outside the LSR of every other node, and reachable inside this one.
        const bool valid = internal::OutsideOtherLsrs(g, current, candidate);
        if (valid) path = session.PathInside(node.lsr, here, candidate);
        if (path) break;
      }
    }
    if (path) {
      current = session.Drive(*path).reached ? session.AddNodeHere(static_cast<int>(current))
                                             : session.NodeAfterFailedMove(current);
      continue;
    }
    // The node's free arcs are given up (SRT keeps them whole: the final check finds which
    // other nodes' LSRs cover them).
    g[current].given_up.clear();
    for (const kernel::FrontierArc& arc : g[current].frontiers)
      session.GiveUp(
          current, arc,
          "no valid configuration in " + std::to_string(options_.srt_max_attempts) + " draws");
    const int parent = session.run().nodes[current].parent;
    if (parent < 0) return session.Finish(Termination::kExplored, "back at the root, nothing left");
    // Backtrack along the tree edge; a failed move leaves the robot between the two nodes,
    // where a new node (child of the one it left) is perceived.
    const graph::Vertex target = static_cast<graph::Vertex>(parent);
    if (session.Drive(graph::Waypoints(g, {current, target})).reached) {
      current = target;
    } else if (++failed_returns[current] >= options_.max_failed_moves) {
      // Each failure adds a node next to `current`, which returns to it and tries again: without
      // this cap the robot circles here until the time limit.
      return session.Finish(Termination::kStuck,
                            "could not return from node " + std::to_string(current) +
                                " to its parent " + std::to_string(target) + " in " +
                                std::to_string(options_.max_failed_moves) + " tries");
    } else {
      current = session.NodeAfterFailedMove(current);
    }
  }
  return session.Finish();
}

}  // namespace splam::exploration
