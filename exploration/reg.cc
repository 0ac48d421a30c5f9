#include "exploration/reg.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <set>

#include "exploration/active_loop_closing.h"
#include "exploration/retries.h"
#include "exploration/session.h"
#include "exploration/steps.h"
#include "graph/bidirectional_astar.h"
#include "graph/frontiers.h"

namespace splam::exploration {
namespace {

using graph::Vertex;

class Reg {
 public:
  Reg(RegExplorer* steps, RobotInterface* robot, Localization* localization)
      : session_(steps->name(), steps->options(), robot, localization),
        steps_(*steps),
        options_(session_.options()),
        reg_(steps->reg_options()),
        g_(session_.graph()),
        active_(options_.active_loop_closing) {}

  ExplorationRun Run();

 private:
  // Puts v on the frontier-control list (once).
  void List(Vertex v);
  void Unlist(Vertex v);

  Session session_;
  RegExplorer& steps_;              // the choices (a variant's overrides)
  const ExplorerOptions& options_;  // the session's
  const RegOptions& reg_;
  graph::ExplorationGraph& g_;
  ActiveLoopClosing active_;     // revisits when the pose grows uncertain
  Retries retries_;              // given-up frontiers retried once nothing else is left
  std::vector<Vertex> list_;     // the frontier-control list
  std::set<Vertex> approached_;  // nodes that retried a piece from another node (Approach)
  std::set<Vertex>
      looked_;  // nodes that turned to face a piece (LookTowards), and the nodes added by it
  bool sweeping_ = false;  // shadow frontiers are being explored (Sweep)

  // Whether node v has frontiers left to explore: free arcs, or shadows while sweeping.
  bool Pending(Vertex v) const {
    return !g_[v].frontiers.empty() || (sweeping_ && !g_[v].shadows.empty());
  }
  // Once no free arc is left: each node keeps the shadows that the union of all the other LSRs
  // does not see behind (Session::ShadowOpen), and the nodes with one are listed. Each shadow is
  // approached once (popped when tried); new nodes bring their own, checked at the next sweep.
  void Sweep() {
    sweeping_ = true;
    for (Vertex v = 0; v < g_.num_nodes(); ++v) {
      std::erase_if(g_[v].shadows, [&](std::size_t edge) { return !session_.ShadowOpen(v, edge); });
      if (!g_[v].shadows.empty()) List(v);
    }
  }
};

ExplorationRun Reg::Run() {
  if (!session_.Start()) return session_.Finish();
  const Vertex start = session_.AddNodeHere(-1);
  Vertex current = start;
  const double max_piece = reg_.piece_factor * 2.0 * std::acos(options_.alpha / 2.0);
  while (!session_.CapReached()) {
    // Active loop closing: the robot leaves the node (listed when it has frontiers left) for a
    // place that closes a loop, and REG goes on from there.
    if (options_.active_loop_closing.enabled && Pending(current)) List(current);
    if (const auto revisited = active_.Step(&session_, current, /*come_back=*/false)) {
      current = *revisited;
      continue;
    }
    std::optional<kernel::FrontierArc> piece;
    std::optional<std::size_t> shadow;  // the occlusion edge approached instead of a piece
    std::optional<std::vector<Eigen::Vector2d>> destination;  // path to q_dest
    std::optional<graph::GraphPath> path;
    std::optional<Retry> retry;           // once nothing else is left (Retries)
    std::optional<Eigen::Vector2d> face;  // what an approach came to see (Session::Drive)
    std::optional<Eigen::Vector2d> look;  // turn in place to face this and sense again
    {
      Session::PlanningTimer timer(&session_);
      CurrIntersection(session_, &g_, current);
      // FRONTIERS / FRONT_RAND, until a piece with a clear leg is found.
      std::vector<kernel::FrontierArc>& frontiers = g_[current].frontiers;
      while (!frontiers.empty() && !destination && !look) {
        piece = steps_.NextPiece(session_, current, &frontiers, max_piece);
        destination = steps_.StepTowards(session_, current, *piece);
        if (!destination && reg_.look_before_giving_up && !looked_.contains(current)) {
          // Before anything else the robot looks at the piece from where it stands: the piece
          // goes back to the node, and what the new LSR covers of it leaves (CurrIntersection).
          looked_.insert(current);
          frontiers.push_back(*piece);
          look = FrontierRules::ArcSight(g_[current].lsr, *piece);
          break;
        }
        if (!destination && !approached_.contains(current)) {
          // Retried from another node: the robot moves as near the piece as it can inside the
          // LSR (a node beside a door sees the room through it at a slant, a node in front of it
          // squarely), once per node.
          // A piece seen through a door at a slant: in front of the door, facing through it.
          const Eigen::Vector2d here = g_[current].configuration.translation();
          if (auto door = session_.paths().DoorwayApproach(session_.rules(), g_[current].lsr, here,
                                                           *piece, session_.NodePositions())) {
            destination = std::move(door->path);
            face = door->face;
          } else {
            const double mid = 0.5 * (piece->start_angle_rad + piece->end_angle_rad);
            destination = session_.paths().Approach(
                g_[current].lsr, here, g_[current].lsr.ArcPoint(mid), session_.NodePositions());
            if (destination) face = FrontierRules::ArcSight(g_[current].lsr, *piece);
          }
          if (destination) approached_.insert(current);
        }
        if (!destination) {
          ++session_.run().unreachable_frontiers;
          session_.GiveUp(current, *piece, "no clear leg from its node");
        }
      }
      // The shadow frontiers, once no free arc is left anywhere (Sweep): the robot moves as near
      // the hidden space as the LSR lets it (ExplorerOptions::shadow_frontiers).
      std::vector<std::size_t>& shadows = g_[current].shadows;
      shadow.reset();
      while (!destination && !look && sweeping_ && !shadows.empty()) {
        shadow = shadows.back();
        shadows.pop_back();
        piece.reset();
        face = FrontierRules::ShadowSight(g_[current].lsr, *shadow);
        destination = session_.paths().Approach(
            g_[current].lsr, g_[current].configuration.translation(),
            FrontierRules::ShadowTarget(g_[current].lsr, *shadow), session_.NodePositions());
        if (!destination) {
          ++session_.run().unreachable_frontiers;
          session_.GiveUpShadow(current, *shadow, "no reachable point nearer the hidden space");
        }
      }
      if (destination || look) {
        if (Pending(current)) List(current);
      } else {
        Unlist(current);
        std::erase_if(list_, [&](Vertex v) { return !Pending(v); });
        if (list_.empty() && options_.shadow_frontiers) Sweep();
        if (list_.empty()) retry = retries_.Next(session_);
        if (!retry)
          path = steps_.NextNode(session_, current,
                                 list_.empty() ? std::vector<Vertex>{start} : list_);
      }
    }
    if (destination) {
      const MoveResult move = session_.Drive(*destination, face);
      const Vertex previous = current;
      current = move.reached ? session_.AddNodeHere(static_cast<int>(previous))
                             : session_.NodeAfterFailedMove(previous);
      // VERIFIES: what the new LSR does not cover of the piece goes back to the previous node
      // (all of it is dropped when the move failed: the way there is not clear).
      Session::PlanningTimer timer(&session_);
      if (shadow) {
        // The approach is the attempt: what the new LSR does not see behind the edge is given
        // up, and the new node's own shadows carry on the search.
        if (!move.reached ||
            !session_.rules().ShadowCovered(g_[previous].lsr, *shadow, {&g_[current].lsr}))
          session_.GiveUpShadow(previous, *shadow,
                                move.reached ? "not seen from the node that approached it"
                                             : "the move towards it failed");
      } else if (move.reached) {
        for (const kernel::FrontierArc& rest :
             session_.rules().UncoveredParts(g_[previous].lsr, *piece, {&g_[current].lsr}))
          g_[previous].frontiers.push_back(rest);
      } else {
        ++session_.run().unreachable_frontiers;
        session_.GiveUp(previous, *piece, "the move towards it failed");
      }
      if (Pending(previous)) List(previous);
      continue;
    }
    if (look) {
      current = session_.LookTowards(current, *look);
      looked_.insert(current);
      continue;
    }
    if (retry) {
      // A given-up frontier retried from another node.
      current = DriveRetry(&session_, current, *retry);
      continue;
    }
    if (list_.empty()) {
      // Nothing left: return home.
      if (path && path->vertices.size() > 1) session_.Drive(g_.Waypoints(path->vertices));
      return session_.Finish(Termination::kExplored, "no frontier left; returned to the start");
    }
    if (!path) {
      for (const Vertex v : list_) {
        for (const kernel::FrontierArc& arc : g_[v].frontiers)
          session_.GiveUp(v, arc, "its node is unreachable in the graph");
        for (const std::size_t edge : g_[v].shadows)
          session_.GiveUpShadow(v, edge, "its node is unreachable in the graph");
      }
      return session_.Finish(Termination::kExplored,
                             std::to_string(list_.size()) +
                                 " listed nodes with frontiers are unreachable in the graph");
    }
    // FIND_PATH found the nearest listed node: drive there; it leaves the list.
    const Vertex target = path->vertices.back();
    if (session_.Drive(g_.Waypoints(path->vertices)).reached) {
      Unlist(target);
      current = target;
    } else {
      current = session_.NodeAfterFailedMove(current);
    }
  }
  return session_.Finish();
}

void Reg::List(Vertex v) {
  if (std::find(list_.begin(), list_.end(), v) == list_.end()) list_.push_back(v);
}

void Reg::Unlist(Vertex v) { std::erase(list_, v); }

}  // namespace

ExplorationRun RegExplorer::Run(RobotInterface* robot, Localization* localization) {
  return Reg(this, robot, localization).Run();
}

kernel::FrontierArc RegExplorer::NextPiece(Session& session, graph::Vertex /*node*/,
                                           std::vector<kernel::FrontierArc>* frontiers,
                                           double max_piece_rad) {
  return FrontRand(session, frontiers, &session.random(), max_piece_rad);
}

std::optional<std::vector<Eigen::Vector2d>> RegExplorer::StepTowards(
    Session& session, graph::Vertex node, const kernel::FrontierArc& piece) {
  return Displacement(session, session.graph()[node], piece);
}

std::optional<graph::GraphPath> RegExplorer::NextNode(Session& session, graph::Vertex current,
                                                      const std::vector<graph::Vertex>& targets) {
  return graph::BidirectionalAStar(session.graph(), current, targets);
}

void RegOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Field("piece_factor", &piece_factor, "FRONT_RAND piece length, times 2 r acos(alpha / 2)");
  v.Field("look_before_giving_up", &look_before_giving_up,
          "a node with no clear leg to a piece turns to face it and senses again first (false: "
          "as published)");
}

kernel::Status RegOptions::Validate() const {
  if (!(piece_factor > 0.0 && piece_factor <= 100.0))
    return kernel::Status::Error("piece_factor must be in (0, 100]");
  return kernel::Status::Ok();
}

}  // namespace splam::exploration
