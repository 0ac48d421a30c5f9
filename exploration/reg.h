#ifndef SPLAM_EXPLORATION_REG_H_
#define SPLAM_EXPLORATION_REG_H_

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "exploration/explorer.h"
#include "graph/bidirectional_astar.h"
#include "graph/exploration_graph.h"
#include "kernel/local_safe_region.h"

namespace splam::exploration {

class Session;

// REG's own options (the shared ones are ExplorerOptions).
struct RegOptions {
  // FRONT_RAND takes at most factor * 2 r acos(alpha / 2) of arc length, the part of the circle
  // of radius r around the node that a disc of radius r alpha * r away covers.
  double piece_factor = 1.0;
  // A node with no clear leg towards a frontier piece turns in place to face the piece and
  // senses again (a new node at the same place, Session::LookTowards) before it approaches the
  // piece or gives it up; once per place. A robot that stopped in a doorway facing along the wall
  // sees the room through the door in a wedge whose apex the edge of its laser's 240 deg cuts: too
  // narrow near the robot for its disc, so no path leads in. Off by default: turning can also
  // face the robot away from the far half of a room, which the sonars' first echoes then close
  // (docs/experiments.md, Fig. 18). false: the robot plans with what it sensed on arrival, as
  // published.
  bool look_before_giving_up = false;

  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

// Random Exploration Graph (paper 003 §3.1, Figs 8-9; SPEC §9). Each iteration at the current
// node q:
//  - CURR_INTERSECTION: for every node whose LSR overlaps q's, the frontier parts of either
//    that lie inside the other's LSR are removed from it, and an edge is added when a safe path
//    through the overlap exists (a waypoint in both LSRs reached by clear straight legs);
//  - FRONTIERS / FRONT_RAND: a random remaining free arc of q; its target is the midpoint of the
//    arc, or of its leading piece when the arc is longer than what one new LSR covers; the
//    piece leaves q's frontiers; q goes on the frontier-control list if frontiers remain;
//  - DISPLACEMENT: q_dest = alpha * r along the target direction (the nearest direction in the
//    piece that the robot's disc can reach inside the LSR, straight or through one waypoint;
//    failing that, half as far; a piece with none is unreachable);
//  - MOVE_TO, perceive, VERIFIES: the part of the piece the new LSR does not cover goes back
//    to q's frontiers; ADD the node with the driven edge;
//  - with no frontier left at q: FIND_PATH (bidirectional A* by graph distance) to the nearest
//    listed node that still has frontiers, drive there, and it leaves the list.
// The run ends when the list is empty and q has no frontier: the robot returns to the start.
// The start node is in the graph from the beginning; as it has no neighbours at the first
// iteration this equals the paper's late insertion.
//
// The run loop is fixed; its three choices are steps a variant overrides (examples/exploration):
// which frontier piece next (NextPiece), where to step for it (StepTowards), and where to go
// when the node has nothing left (NextNode). A variant that changes one of them derives from
// RegExplorer and overrides that one, with name() its own.
class RegExplorer : public Explorer {
 public:
  explicit RegExplorer(const ExplorerOptions& options, const RegOptions& reg = {})
      : options_(options), reg_(reg) {}
  std::string name() const override { return "reg"; }
  ExplorationRun Run(RobotInterface* robot, Localization* localization) override;

  // Which frontier next: takes a piece off `frontiers` (node `node`'s free arcs, not empty), at
  // most max_piece_rad wide. REG: FRONT_RAND, the leading piece of a random arc (FrontRand).
  virtual kernel::FrontierArc NextPiece(Session& session, graph::Vertex node,
                                        std::vector<kernel::FrontierArc>* frontiers,
                                        double max_piece_rad);
  // Where to step for that piece: the path from the node to the next node's configuration;
  // nullopt when there is no clear leg (the piece is then approached from where the node
  // stands, or given up). REG: DISPLACEMENT, alpha r towards the piece (Displacement).
  virtual std::optional<std::vector<Eigen::Vector2d>> StepTowards(Session& session,
                                                                  graph::Vertex node,
                                                                  const kernel::FrontierArc& piece);
  // What to do when the node has nothing left: the path through the graph to the node the run
  // goes on from, one of `targets` (the listed nodes that still have frontiers, or the start
  // when none is left, to return home); nullopt when none is reachable. REG: FIND_PATH, the
  // nearest by graph distance (bidirectional A*).
  virtual std::optional<graph::GraphPath> NextNode(Session& session, graph::Vertex current,
                                                   const std::vector<graph::Vertex>& targets);

  const ExplorerOptions& options() const { return options_; }
  const RegOptions& reg_options() const { return reg_; }

 private:
  ExplorerOptions options_;
  RegOptions reg_;
};

}  // namespace splam::exploration

#endif  // SPLAM_EXPLORATION_REG_H_
