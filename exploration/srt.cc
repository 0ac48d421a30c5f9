#include "exploration/srt.h"

#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <string>

#include "exploration/active_loop_closing.h"
#include "exploration/retries.h"
#include "exploration/session.h"
#include "exploration/steps.h"

namespace splam::exploration {
namespace {

// Relaxed VALID_CONF (SrtOptions::relaxed_valid_conf): once the draws of SRT ran out at
// node v, the parts of its free arcs that no other LSR saw beyond (Session::OpenParts) are drawn
// from instead, the candidate may lie inside other LSRs, and closer (1, 2/3, 1/3 of alpha r);
// failing that the robot approaches the widest open part, or an open shadow frontier, as near as
// it can. Only while what is open at v shrinks from one relaxed move to the next (the open width
// in rad plus the number of open shadows; neither grows, as nodes are only added): a part that a
// new node cannot see beyond is not tried forever. `last_open` holds that measure at v's previous
// relaxed move. A part seen only through a door at a slant is approached on the door's axis,
// facing through it (SafePaths::DoorwayApproach).
using Move = SafePaths::Move;
std::optional<Move> RelaxedMove(Session* session, graph::Vertex v, int max_attempts,
                                double* last_open) {
  const graph::ExplorationGraph& g = session->graph();
  const graph::NodeData& node = g[v];
  std::vector<kernel::FrontierArc> open;
  double width = 0.0;
  for (const kernel::FrontierArc& arc : node.frontiers)
    for (const kernel::FrontierArc& part : session->OpenParts(v, arc)) {
      open.push_back(part);
      width += part.AngularWidth();
    }
  std::vector<std::size_t> shadows_open;
  for (const std::size_t edge : node.shadows)
    if (session->ShadowOpen(v, edge)) shadows_open.push_back(edge);
  const double measure = width + static_cast<double>(shadows_open.size());
  if (measure == 0.0 || measure >= *last_open - 1e-9) return std::nullopt;
  *last_open = measure;
  const ExplorerOptions& options = session->options();
  const double step = options.alpha * options.lsr_radius_m;
  const Eigen::Vector2d here = node.configuration.translation();
  for (int attempt = 0; attempt < max_attempts && !open.empty(); ++attempt) {
    const double theta = RandomDirection(open, &session->random());
    for (const double fraction : {1.0, 2.0 / 3.0, 1.0 / 3.0}) {
      const Eigen::Vector2d candidate =
          node.lsr.center() + fraction * step * Eigen::Vector2d(std::cos(theta), std::sin(theta));
      if (auto path = session->paths().PathInside(node.lsr, here, candidate))
        return Move{*path, {}};
    }
  }
  const std::vector<Eigen::Vector2d> nodes = session->NodePositions();
  if (!open.empty()) {
    const kernel::FrontierArc* widest = &open.front();
    for (const kernel::FrontierArc& part : open)
      if (part.AngularWidth() > widest->AngularWidth()) widest = &part;
    if (auto door =
            session->paths().DoorwayApproach(session->rules(), node.lsr, here, *widest, nodes))
      return door;
    const double mid = 0.5 * (widest->start_angle_rad + widest->end_angle_rad);
    if (auto path = session->paths().Approach(node.lsr, here, node.lsr.ArcPoint(mid), nodes))
      return Move{*path, {}};
  }
  for (const std::size_t edge : shadows_open)
    if (auto path = session->paths().Approach(node.lsr, here,
                                              FrontierRules::ShadowTarget(node.lsr, edge), nodes))
      return Move{*path, {}};
  return std::nullopt;
}

}  // namespace

void SrtOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Field("max_attempts", &max_attempts, "RANDOM_DIR draws before backtracking");
  v.Field("relaxed_valid_conf", &relaxed_valid_conf,
          "VALID_CONF relaxed for arcs no other LSR saw beyond (false: as published)");
}

kernel::Status SrtOptions::Validate() const {
  if (max_attempts < 1 || max_attempts > 10000)
    return kernel::Status::Error("max_attempts must be in [1, 10000]");
  return kernel::Status::Ok();
}

ExplorationRun SrtExplorer::Run(RobotInterface* robot, Localization* localization) {
  Session session(name(), options_, robot, localization);
  if (!session.Start()) return session.Finish();
  graph::ExplorationGraph& g = session.graph();
  graph::Vertex current = session.AddNodeHere(-1);
  std::map<graph::Vertex, int> failed_returns;  // failed backtracks from each node
  std::map<graph::Vertex, double> last_open;    // RelaxedMove's open width at each node, rad
  Retries retries;                              // given-up frontiers, once back at the root
  ActiveLoopClosing active(options_.active_loop_closing);
  while (!session.CapReached()) {
    // Active loop closing: a round trip to a place that closes a loop, back to the tree's node.
    if (const auto back = active.Step(&session, current, /*come_back=*/true)) {
      current = *back;
      continue;
    }
    std::optional<std::vector<Eigen::Vector2d>> path;  // to the new node's configuration
    std::optional<Eigen::Vector2d> face;               // what to face there (RelaxedMove)
    {
      Session::PlanningTimer timer(&session);
      const graph::NodeData& node = g[current];
      for (int attempt = 0; attempt < srt_.max_attempts && !node.frontiers.empty(); ++attempt) {
        path = StepTowards(session, current, NextDirection(session, current, node.frontiers));
        if (path) break;
      }
      if (!path && srt_.relaxed_valid_conf) {
        const auto [it, added] =
            last_open.try_emplace(current, std::numeric_limits<double>::infinity());
        if (std::optional<Move> move =
                RelaxedMove(&session, current, srt_.max_attempts, &it->second)) {
          path = std::move(move->path);
          face = move->face;
        }
      }
    }
    if (path) {
      current = session.Drive(*path, face).reached ? session.AddNodeHere(static_cast<int>(current))
                                                   : session.NodeAfterFailedMove(current);
      continue;
    }
    // The node's free arcs are given up (SRT keeps them whole: the final check finds which
    // other nodes' LSRs cover them).
    g[current].given_up.clear();
    const std::string reason =
        "no valid configuration in " + std::to_string(srt_.max_attempts) + " draws";
    for (const kernel::FrontierArc& arc : g[current].frontiers)
      session.GiveUp(current, arc, reason);
    for (const std::size_t edge : g[current].shadows) session.GiveUpShadow(current, edge, reason);
    const int parent = BacktrackTo(session, current);
    if (parent < 0) {
      // Back at the root: the frontiers given up and still open are retried from other nodes
      // (ExplorerOptions::retry_nodes), each a new subtree.
      std::optional<Retry> retry;
      {
        Session::PlanningTimer timer(&session);
        retry = retries.Next(session);
      }
      if (!retry) return session.Finish(Termination::kExplored, "back at the root, nothing left");
      current = DriveRetry(&session, current, *retry);
      continue;
    }
    // Backtrack along the tree edge; a failed move leaves the robot between the two nodes,
    // where a new node (child of the one it left) is perceived.
    const graph::Vertex target = static_cast<graph::Vertex>(parent);
    if (session.Drive(g.Waypoints({current, target})).reached) {
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

double SrtExplorer::NextDirection(Session& session, graph::Vertex /*node*/,
                                  const std::vector<kernel::FrontierArc>& frontiers) {
  return RandomDirection(frontiers, &session.random());
}

std::optional<std::vector<Eigen::Vector2d>> SrtExplorer::StepTowards(Session& session,
                                                                     graph::Vertex node,
                                                                     double direction_rad) {
  const graph::NodeData& data = session.graph()[node];
  const double step = options_.alpha * options_.lsr_radius_m;
  const Eigen::Vector2d candidate =
      data.lsr.center() + step * Eigen::Vector2d(std::cos(direction_rad), std::sin(direction_rad));
  // VALID_CONF: outside the LSR of every other node, and reachable inside this one.
  if (!OutsideOtherLsrs(session.graph(), node, candidate)) return std::nullopt;
  return session.paths().PathInside(data.lsr, data.configuration.translation(), candidate);
}

int SrtExplorer::BacktrackTo(Session& session, graph::Vertex node) {
  return session.run().nodes[node].parent;
}

}  // namespace splam::exploration
