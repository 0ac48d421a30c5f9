#include "exploration/retries.h"

#include <algorithm>
#include <limits>

#include "exploration/frontier_map.h"
#include "graph/bidirectional_astar.h"

namespace splam::exploration {

std::optional<Retry> Retries::Next(const Session& session) {
  const ExplorerOptions& options = session.options();
  constexpr double kSameTarget = 0.5;  // m: targets this close are the same frontier
  constexpr int kStride = 4;           // goals are tried on every 4th cell (20 cm)
  if (!options.grid_paths || options.retry_nodes == 0) return std::nullopt;
  const graph::ExplorationGraph& g = session.graph();
  const std::vector<Eigen::Vector2d> nodes = NodePositions(g);
  std::optional<Retry> best;
  double best_distance = std::numeric_limits<double>::infinity();
  for (const GivenUpFrontier& frontier : session.GivenUpFrontiers()) {
    if (!frontier.open) continue;
    const auto owner = static_cast<graph::Vertex>(frontier.node);
    const kernel::LocalSafeRegion& lsr = g[owner].lsr;
    if (!frontier.unseen.empty()) {
      // Looked at from the nearest node that sees its deepest point (the owner too: it never
      // tried), turning in place there.
      const Eigen::Vector2d deepest = *std::max_element(
          frontier.unseen.begin(), frontier.unseen.end(),
          [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
            return (a - lsr.center()).squaredNorm() < (b - lsr.center()).squaredNorm();
          });
      const Eigen::Vector2d target = FrontierRules::UnseenSight(lsr, deepest);
      std::vector<graph::Vertex> tried;
      for (const auto& [t, v] : made_)
        if ((t - target).norm() < kSameTarget) tried.push_back(v);
      if (static_cast<int>(tried.size()) >= options.retry_nodes) continue;
      std::vector<const kernel::LocalSafeRegion*> regions;
      for (graph::Vertex v = 0; v < nodes.size(); ++v)
        if ((nodes[v] - target).norm() <= 2.0 * options.lsr_radius_m) regions.push_back(&g[v].lsr);
      for (graph::Vertex v = 0; v < nodes.size(); ++v) {
        const double d = (nodes[v] - target).norm();
        if (d >= std::min(best_distance, options.lsr_radius_m) ||
            std::find(tried.begin(), tried.end(), v) != tried.end() ||
            !kernel::UnionLineOfSight(regions, nodes[v], target, options.shadow_edge_m))
          continue;
        best = Retry{v, {}, target};
        best_distance = d;
      }
      continue;
    }
    const Eigen::Vector2d target =
        frontier.shadow_edge >= 0
            ? FrontierRules::ShadowSight(lsr, static_cast<std::size_t>(frontier.shadow_edge))
            : FrontierRules::ArcSight(lsr, frontier.arc);
    std::vector<graph::Vertex> tried{owner};
    for (const auto& [t, v] : made_)
      if ((t - target).norm() < kSameTarget) tried.push_back(v);
    if (static_cast<int>(tried.size()) > options.retry_nodes) continue;
    std::vector<const kernel::LocalSafeRegion*> regions;
    std::vector<std::pair<double, graph::Vertex>> candidates;
    for (graph::Vertex v = 0; v < nodes.size(); ++v) {
      const double d = (nodes[v] - target).norm();
      if (d > 2.0 * options.lsr_radius_m) continue;
      regions.push_back(&g[v].lsr);
      if (std::find(tried.begin(), tried.end(), v) == tried.end()) candidates.emplace_back(d, v);
    }
    std::sort(candidates.begin(), candidates.end());
    // A goal must come nearer to the target than its owner, and see it.
    const double owner_distance = (nodes[owner] - target).norm();
    for (const auto& [d, v] : candidates) {
      const double bound = std::min(best_distance, owner_distance);
      if (d - options.lsr_radius_m >= bound) break;  // no point of v's LSR is nearer
      const std::optional<Eigen::Vector2d> goal =
          session.paths()
              .PlannerFor(g[v].lsr, nodes[v])
              ->NearestReachable(target, SafePaths::kMinTravelM, nodes, SafePaths::kMinTravelM,
                                 kStride, [&](const Eigen::Vector2d& c) {
                                   return (c - target).norm() < bound &&
                                          kernel::UnionLineOfSight(regions, c, target,
                                                                   options.shadow_edge_m);
                                 });
      if (!goal) continue;
      if (auto path = session.paths().PathInside(g[v].lsr, nodes[v], *goal)) {
        best = Retry{v, std::move(*path), target};
        best_distance = (*goal - target).norm();
      }
    }
  }
  if (best) made_.emplace_back(best->target, best->node);
  return best;
}

graph::Vertex DriveRetry(Session* session, graph::Vertex current, const Retry& retry) {
  if (current != retry.node) {
    const std::optional<graph::GraphPath> path =
        graph::BidirectionalAStar(session->graph(), current, {retry.node});
    if (!path) return current;
    if (!session->Drive(session->graph().Waypoints(path->vertices)).reached)
      return session->NodeAfterFailedMove(current);
  }
  if (retry.approach.empty()) return session->LookTowards(retry.node, retry.target);
  return session->Drive(retry.approach, retry.target).reached
             ? session->AddNodeHere(static_cast<int>(retry.node))
             : session->NodeAfterFailedMove(retry.node);
}

}  // namespace splam::exploration
