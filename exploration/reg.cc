#include "exploration/reg.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "exploration/internal/session.h"
#include "graph/bidirectional_astar.h"
#include "graph/frontiers.h"

namespace splam::exploration {
namespace {

using graph::Vertex;

// Lateral offsets and fractions along a-b of the candidate waypoints of a safe path.
constexpr double kPathFractions[] = {0.5, 0.35, 0.65, 0.2, 0.8};
constexpr double kPathOffsets[] = {0.0, 0.3, -0.3, 0.6, -0.6, 0.9, -0.9};  // m

class Reg {
 public:
  Reg(const ExplorerOptions& options, RobotInterface* robot, Localization* localization)
      : session_("reg", options, robot, localization),
        options_(session_.options()),
        g_(session_.graph()) {}

  ExplorationRun Run();

 private:
  // CURR_INTERSECTION at `current`.
  void CurrIntersection(Vertex current);
  // Removes from node v's frontiers the parts inside `other`.
  void RemoveCovered(Vertex v, const kernel::LocalSafeRegion& other);
  // The shortest path a -> w -> b with w in both LSRs and both legs clear; nullopt if none of the
  // candidate waypoints works.
  std::optional<std::vector<Eigen::Vector2d>> SafePath(Vertex a, Vertex b) const;
  // DISPLACEMENT: q_dest alpha * r from the node towards the piece's midpoint, or towards the
  // direction of the piece nearest to it that the robot can reach inside the LSR (failing that,
  // half as far); the path there.
  std::optional<std::vector<Eigen::Vector2d>> Displacement(Vertex v,
                                                           const kernel::FrontierArc& piece) const;
  // Puts v on the frontier-control list (once).
  void List(Vertex v);
  void Unlist(Vertex v);

  internal::Session session_;
  const ExplorerOptions& options_;  // the session's
  graph::ExplorationGraph& g_;
  std::vector<Vertex> list_;  // the frontier-control list
};

ExplorationRun Reg::Run() {
  if (!session_.Start()) return session_.Finish();
  const Vertex start = session_.AddNodeHere(-1);
  Vertex current = start;
  const double max_piece = options_.reg_piece_factor * 2.0 * std::acos(options_.alpha / 2.0);
  while (!session_.CapReached()) {
    std::optional<kernel::FrontierArc> piece;
    std::optional<std::vector<Eigen::Vector2d>> destination;  // path to q_dest
    std::optional<graph::GraphPath> path;
    {
      internal::Session::PlanningTimer timer(&session_);
      CurrIntersection(current);
      // FRONTIERS / FRONT_RAND, until a piece with a clear leg is found.
      std::vector<kernel::FrontierArc>& frontiers = g_[current].frontiers;
      while (!frontiers.empty() && !destination) {
        const std::size_t k =
            std::min(frontiers.size() - 1, static_cast<std::size_t>(session_.random().Uniform(
                                               0.0, static_cast<double>(frontiers.size()))));
        const kernel::FrontierArc arc = frontiers[k];
        piece = graph::LeadingPiece(arc, max_piece);
        frontiers.erase(frontiers.begin() + static_cast<std::ptrdiff_t>(k));
        for (const kernel::FrontierArc& rest :
             session_.LongEnough(graph::Subtract(arc, {*piece}, 0.0)))
          frontiers.push_back(rest);
        destination = Displacement(current, *piece);
        if (!destination) ++session_.run().unreachable_frontiers;
      }
      if (destination) {
        if (!frontiers.empty()) List(current);
      } else {
        Unlist(current);
        std::erase_if(list_, [&](Vertex v) { return g_[v].frontiers.empty(); });
        path = graph::BidirectionalAStar(g_, current,
                                         list_.empty() ? std::vector<Vertex>{start} : list_);
      }
    }
    if (destination) {
      const MoveResult move = session_.Drive(*destination);
      const Vertex previous = current;
      current = move.reached ? session_.AddNodeHere(static_cast<int>(previous))
                             : session_.NodeAfterFailedMove(previous);
      // VERIFIES: what the new LSR does not cover of the piece goes back to the previous node
      // (all of it is dropped when the move failed: the way there is not clear).
      internal::Session::PlanningTimer timer(&session_);
      if (move.reached) {
        for (const kernel::FrontierArc& rest :
             session_.UncoveredParts(g_[previous].lsr, *piece, g_[current].lsr))
          g_[previous].frontiers.push_back(rest);
      } else {
        ++session_.run().unreachable_frontiers;
      }
      if (!g_[previous].frontiers.empty()) List(previous);
      continue;
    }
    if (list_.empty()) {
      // Nothing left: return home.
      if (path && path->vertices.size() > 1) session_.Drive(graph::Waypoints(g_, path->vertices));
      return session_.Finish(Termination::kExplored, "no frontier left; returned to the start");
    }
    if (!path) {
      return session_.Finish(Termination::kExplored,
                             std::to_string(list_.size()) +
                                 " listed nodes with frontiers are unreachable in the graph");
    }
    // FIND_PATH found the nearest listed node: drive there; it leaves the list.
    const Vertex target = path->vertices.back();
    if (session_.Drive(graph::Waypoints(g_, path->vertices)).reached) {
      Unlist(target);
      current = target;
    } else {
      current = session_.NodeAfterFailedMove(current);
    }
  }
  return session_.Finish();
}

void Reg::CurrIntersection(Vertex current) {
  const kernel::LocalSafeRegion& here = g_[current].lsr;
  for (Vertex v = 0; v < boost::num_vertices(g_); ++v) {
    if (v == current) continue;
    const kernel::LocalSafeRegion& there = g_[v].lsr;
    if ((there.center() - here.center()).norm() > there.radius() + here.radius()) continue;
    if (!kernel::Overlaps(here, there)) continue;
    RemoveCovered(v, here);
    RemoveCovered(current, there);
    if (!graph::HasEdge(g_, v, current)) {
      if (auto path = SafePath(v, current)) graph::AddEdge(&g_, v, current, std::move(*path));
    }
  }
}

void Reg::RemoveCovered(Vertex v, const kernel::LocalSafeRegion& other) {
  std::vector<kernel::FrontierArc> kept;
  for (const kernel::FrontierArc& arc : g_[v].frontiers) {
    for (const kernel::FrontierArc& rest : session_.UncoveredParts(g_[v].lsr, arc, other))
      kept.push_back(rest);
  }
  g_[v].frontiers = std::move(kept);
}

std::optional<std::vector<Eigen::Vector2d>> Reg::SafePath(Vertex a, Vertex b) const {
  const Eigen::Vector2d pa = g_[a].configuration.translation();
  const Eigen::Vector2d pb = g_[b].configuration.translation();
  const Eigen::Vector2d normal = Eigen::Vector2d(pa.y() - pb.y(), pb.x() - pa.x()).normalized();
  std::optional<std::vector<Eigen::Vector2d>> best;
  double best_length = std::numeric_limits<double>::infinity();
  for (double t : kPathFractions) {
    for (double offset : kPathOffsets) {
      const Eigen::Vector2d w = pa + t * (pb - pa) + offset * normal;
      const double length = (w - pa).norm() + (pb - w).norm();
      if (length >= best_length) continue;
      if (!g_[a].lsr.Contains(w) || !g_[b].lsr.Contains(w)) continue;
      if (!session_.LegIsClear(g_[a].lsr, pa, w) || !session_.LegIsClear(g_[b].lsr, pb, w))
        continue;
      best = std::vector<Eigen::Vector2d>{pa, w, pb};
      best_length = length;
    }
  }
  return best;
}

std::optional<std::vector<Eigen::Vector2d>> Reg::Displacement(
    Vertex v, const kernel::FrontierArc& piece) const {
  const graph::NodeData& node = g_[v];
  const Eigen::Vector2d here = node.configuration.translation();
  const double step = options_.alpha * options_.lsr_radius_m;
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
            if (session_.LegIsClear(node.lsr, here, q)) return std::vector<Eigen::Vector2d>{q};
          } else if (auto path = session_.PathInside(node.lsr, here, q)) {
            return path;
          }
        }
      }
    }
  }
  return std::nullopt;
}

void Reg::List(Vertex v) {
  if (std::find(list_.begin(), list_.end(), v) == list_.end()) list_.push_back(v);
}

void Reg::Unlist(Vertex v) { std::erase(list_, v); }

}  // namespace

ExplorationRun RegExplorer::Run(RobotInterface* robot, Localization* localization) {
  return Reg(options_, robot, localization).Run();
}

}  // namespace splam::exploration
