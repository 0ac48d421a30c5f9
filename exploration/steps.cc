#include "exploration/steps.h"

#include <cmath>
#include <limits>

#include "graph/frontiers.h"

namespace splam::exploration {
namespace {

using graph::Vertex;

// Lateral offsets and fractions along a-b of the candidate waypoints of a safe path.
constexpr double kPathFractions[] = {0.5, 0.35, 0.65, 0.2, 0.8};
constexpr double kPathOffsets[] = {0.0, 0.3, -0.3, 0.6, -0.6, 0.9, -0.9};  // m

// Removes from the node's frontiers the parts `other` covers, and the shadows it sees behind.
void RemoveCovered(const Session& session, graph::NodeData* node,
                   const kernel::LocalSafeRegion& other) {
  std::vector<kernel::FrontierArc> kept;
  for (const kernel::FrontierArc& arc : node->frontiers) {
    for (const kernel::FrontierArc& rest : session.rules().UncoveredParts(node->lsr, arc, {&other}))
      kept.push_back(rest);
  }
  node->frontiers = std::move(kept);
  std::erase_if(node->shadows, [&](std::size_t edge) {
    return session.rules().ShadowCovered(node->lsr, edge, {&other});
  });
}

}  // namespace

double RandomDirection(const std::vector<kernel::FrontierArc>& arcs, kernel::Random* random) {
  double total = 0.0;
  for (const kernel::FrontierArc& arc : arcs) total += arc.AngularWidth();
  double u = random->Uniform(0.0, total);
  for (const kernel::FrontierArc& arc : arcs) {
    if (u <= arc.AngularWidth()) return arc.start_angle_rad + u;
    u -= arc.AngularWidth();
  }
  return arcs.back().end_angle_rad;
}

bool OutsideOtherLsrs(const graph::ExplorationGraph& g, Vertex current,
                      const Eigen::Vector2d& candidate) {
  for (Vertex v = 0; v < g.num_nodes(); ++v) {
    if (v == current) continue;
    const kernel::LocalSafeRegion& other = g[v].lsr;
    if ((candidate - other.center()).norm() <= other.radius() && other.Contains(candidate))
      return false;
  }
  return true;
}

void CurrIntersection(const Session& session, graph::ExplorationGraph* graph, Vertex current) {
  graph::ExplorationGraph& g = *graph;
  const kernel::LocalSafeRegion& here = g[current].lsr;
  for (Vertex v = 0; v < g.num_nodes(); ++v) {
    if (v == current) continue;
    const kernel::LocalSafeRegion& there = g[v].lsr;
    if ((there.center() - here.center()).norm() > there.radius() + here.radius()) continue;
    if (!kernel::Overlaps(here, there)) continue;
    RemoveCovered(session, &g[v], here);
    RemoveCovered(session, &g[current], there);
    if (!g.HasEdge(v, current)) {
      if (auto path = SafePath(session, g, v, current)) g.AddEdge(v, current, std::move(*path));
    }
  }
}

std::optional<std::vector<Eigen::Vector2d>> SafePath(const Session& session,
                                                     const graph::ExplorationGraph& g, Vertex a,
                                                     Vertex b) {
  const Eigen::Vector2d pa = g[a].configuration.translation();
  const Eigen::Vector2d pb = g[b].configuration.translation();
  const Eigen::Vector2d normal = Eigen::Vector2d(pa.y() - pb.y(), pb.x() - pa.x()).normalized();
  std::optional<std::vector<Eigen::Vector2d>> best;
  double best_length = std::numeric_limits<double>::infinity();
  for (double t : kPathFractions) {
    for (double offset : kPathOffsets) {
      const Eigen::Vector2d w = pa + t * (pb - pa) + offset * normal;
      const double length = (w - pa).norm() + (pb - w).norm();
      if (length >= best_length) continue;
      if (!g[a].lsr.Contains(w) || !g[b].lsr.Contains(w)) continue;
      if (!session.paths().LegIsClear(g[a].lsr, pa, w) ||
          !session.paths().LegIsClear(g[b].lsr, pb, w))
        continue;
      best = std::vector<Eigen::Vector2d>{pa, w, pb};
      best_length = length;
    }
  }
  return best;
}

kernel::FrontierArc TakePiece(const Session& session, std::vector<kernel::FrontierArc>* frontiers,
                              std::size_t k, double max_piece_rad) {
  const kernel::FrontierArc arc = (*frontiers)[k];
  const kernel::FrontierArc piece = graph::LeadingPiece(arc, max_piece_rad);
  frontiers->erase(frontiers->begin() + static_cast<std::ptrdiff_t>(k));
  for (const kernel::FrontierArc& rest :
       session.rules().LongEnough(graph::Subtract(arc, {piece}, 0.0)))
    frontiers->push_back(rest);
  return piece;
}

kernel::FrontierArc FrontRand(const Session& session, std::vector<kernel::FrontierArc>* frontiers,
                              kernel::Random* random, double max_piece_rad) {
  const std::size_t k = std::min(
      frontiers->size() - 1,
      static_cast<std::size_t>(random->Uniform(0.0, static_cast<double>(frontiers->size()))));
  return TakePiece(session, frontiers, k, max_piece_rad);
}

std::optional<std::vector<Eigen::Vector2d>> Displacement(const Session& session,
                                                         const graph::NodeData& node,
                                                         const kernel::FrontierArc& piece) {
  const ExplorerOptions& options = session.options();
  const Eigen::Vector2d here = node.configuration.translation();
  const double step = options.alpha * options.lsr_radius_m;
  const double mid = 0.5 * (piece.start_angle_rad + piece.end_angle_rad);
  const double half = 0.5 * piece.AngularWidth();
  // Directions from the midpoint outwards: first straight legs every 2 deg, then bent paths
  // (more expensive) every 6 deg; then the same with half the step, which puts a node in front
  // of a door seen at a slant (a robustness extension of the paper's fixed step).
  for (const double fraction : {1.0, 0.5}) {
    for (const double spacing : {kernel::DegToRad(2.0), kernel::DegToRad(6.0)}) {
      const bool straight_only = spacing < kernel::DegToRad(3.0);
      for (int k = 0; k * spacing <= half; ++k) {
        for (const int sign : {1, -1}) {
          if (k == 0 && sign < 0) continue;
          const double theta = mid + sign * k * spacing;
          const Eigen::Vector2d q =
              node.lsr.center() +
              fraction * step * Eigen::Vector2d(std::cos(theta), std::sin(theta));
          if (straight_only) {
            if (session.paths().LegIsClear(node.lsr, here, q))
              return std::vector<Eigen::Vector2d>{q};
          } else if (auto path = session.paths().PathInside(node.lsr, here, q)) {
            return path;
          }
        }
      }
    }
  }
  return std::nullopt;
}

}  // namespace splam::exploration
