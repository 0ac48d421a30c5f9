#ifndef SPLAM_EXPLORATION_INTERNAL_SESSION_H_
#define SPLAM_EXPLORATION_INTERNAL_SESSION_H_

#include <Eigen/Core>
#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "exploration/explorer.h"
#include "exploration/internal/lsr_planner.h"
#include "kernel/local_safe_region.h"
#include "kernel/random.h"

// What SRT and REG share: the robot, the localisation, the run record, the caps, and the
// geometry of safe legs.
namespace splam::exploration::internal {

class LaserHits;  // every node's laser hits on a grid (session.cc)

class Session {
 public:
  Session(const std::string& explorer, const ExplorerOptions& options, RobotInterface* robot,
          Localization* localization);

  // Validates the options, reads the first perception and starts the localisation; false (with
  // the run's termination and message set) when the run cannot start.
  bool Start();
  // Senses here and adds a node (its LSR at the current estimate, its frontiers the LSR's free
  // arcs of at least min_frontier_m). With parent >= 0 the node is joined to it along the path
  // driven since the last Drive() began.
  graph::Vertex AddNodeHere(int parent);
  // Where the robot is after a move from node `from` that failed: a new node (child of `from`)
  // when it got more than 0.3 m away, else `from` itself (no node is added).
  graph::Vertex NodeAfterFailedMove(graph::Vertex from);
  // MOVE_TO through the waypoints; counts moves and failures. When the robot is refused a step
  // (the waypoints came from an older estimate), it senses and re-plans inside the LSR it
  // perceives there (PathNear) to the farthest remaining waypoint it can reach, then follows
  // the rest; at most twice per move.
  // With `face` (and options.face_frontiers), a robot that reached the last waypoint and has that
  // point in sight (InSight) turns in place to face it (TurnTowards): what an approach came to
  // see. Facing a point behind a wall would only turn the laser from the free space to the wall.
  MoveResult Drive(const std::vector<Eigen::Vector2d>& waypoints,
                   const std::optional<Eigen::Vector2d>& face = std::nullopt);
  // Moves the nodes where the localisation now puts them (Localization::NodePoses, nothing when
  // it does not revise the past; graph::MoveNodes). Called after every move and sensing, so
  // that planning uses the optimised graph.
  void FollowRevisedNodes();
  // True when a cap is reached; the termination is then set.
  bool CapReached();
  // Records that the explorer gave up frontier `arc` of node v (graph::NodeData::given_up).
  void GiveUp(graph::Vertex v, const kernel::FrontierArc& arc, const std::string& reason);
  // The same for the shadow frontier behind occlusion edge `edge` of node v's LSR.
  void GiveUpShadow(graph::Vertex v, std::size_t edge, const std::string& reason);
  // Ends the run: fills distance and time and returns the record. A strategy that ends as
  // kExplored is checked against its own map first: the parts of the frontiers it gave up that the
  // union of the other nodes' LSRs does not cover (UncoveredParts) are listed open in
  // run.given_up, and the run is kIncomplete when there is one.
  ExplorationRun Finish(Termination termination, const std::string& message);
  // Ends the run with the termination already set (by Start() or CapReached()).
  ExplorationRun Finish() { return Finish(run_.termination, run_.message); }
  // The parts of `arc` (a frontier of node v) that the union of the other nodes' LSRs does not
  // cover: what the explorer's map says is still unknown beyond it.
  std::vector<kernel::FrontierArc> OpenParts(graph::Vertex v, const kernel::FrontierArc& arc) const;
  // Whether the space behind occlusion edge `edge` of `owner` is seen by the union of `others`:
  // the ray out of `owner` from the edge's middle, or from a quarter of it either side
  // (kernel::UnionSeesBeyond, the view_depth and shadow_edge options).
  bool ShadowCovered(const kernel::LocalSafeRegion& owner, std::size_t edge,
                     const std::vector<const kernel::LocalSafeRegion*>& others) const;
  // Whether no other node's LSR sees behind occlusion edge `edge` of node v's LSR.
  bool ShadowOpen(graph::Vertex v, std::size_t edge) const;
  // A point 0.5 m into the space hidden behind occlusion edge `edge` of `lsr`: what the robot
  // approaches (Approach) to see it.
  static Eigen::Vector2d ShadowTarget(const kernel::LocalSafeRegion& lsr, std::size_t edge);
  // The point of a frontier that an approach must see (NextRetry) and turns to (Drive): 0.1 m
  // inside the LSR on the middle of free arc `arc`, or of occlusion edge `edge`.
  static Eigen::Vector2d ArcSight(const kernel::LocalSafeRegion& lsr,
                                  const kernel::FrontierArc& arc);
  static Eigen::Vector2d ShadowSight(const kernel::LocalSafeRegion& lsr, std::size_t edge);
  // The same for a point of an unseen stretch (UnseenStretches) of `lsr`.
  static Eigen::Vector2d UnseenSight(const kernel::LocalSafeRegion& lsr,
                                     const Eigen::Vector2d& point);
  // Whether the segment from `from` to `point` runs inside the union of the nodes' LSRs
  // (kernel::UnionLineOfSight).
  bool InSight(const Eigen::Vector2d& from, const Eigen::Vector2d& point) const;
  // The parts of `arc` (a frontier of `owner`) that the union of `others` does not cover (the
  // view_depth and shadow_edge options), long enough to stay frontiers; with doorway_goals, the
  // whole arc when they cover none of it (it passed FrontiersOf).
  std::vector<kernel::FrontierArc> UncoveredParts(
      const kernel::LocalSafeRegion& owner, const kernel::FrontierArc& arc,
      const std::vector<const kernel::LocalSafeRegion*>& others) const;

  // True when the disc of the robot, driven straight from a to b, keeps radius + margin from the
  // boundary of `lsr` (a must lie inside it). When the robot's disc is known free at a
  // (`from_robot`: it stands there, or a is a node's configuration) and is already closer, the leg
  // must not get closer and must be fully clear after its first radius + margin.
  bool LegIsClear(const kernel::LocalSafeRegion& lsr, const Eigen::Vector2d& a,
                  const Eigen::Vector2d& b, bool from_robot = true) const;
  // A path for the robot's disc from `from` (where it stands) to `to` inside `lsr`, as waypoints
  // after `from`: the straight leg when it is clear, else with options.grid_paths the grid
  // planner's path (GridPath), else the shortest clear two-leg path through a waypoint of a
  // polar grid around the LSR's centre (radii 0.4-2 m, every 10 deg); nullopt when none exists.
  std::optional<std::vector<Eigen::Vector2d>> PathInside(const kernel::LocalSafeRegion& lsr,
                                                         const Eigen::Vector2d& from,
                                                         const Eigen::Vector2d& to) const;
  // A path inside `lsr` from `from` to the reachable point nearest to `target` that lies at least
  // 0.5 m from `from` and from every point of `avoid` (LsrPlanner::NearestReachable); nullopt
  // when there is none or options.grid_paths is off.
  std::optional<std::vector<Eigen::Vector2d>> Approach(
      const kernel::LocalSafeRegion& lsr, const Eigen::Vector2d& from,
      const Eigen::Vector2d& target, const std::vector<Eigen::Vector2d>& avoid) const;
  // A free arc seen through a gap (a door seen at a slant, GapOf): the robot stands on the gap's
  // axis in front of it and faces through it (ExplorerOptions::doorway_goals). The gap must be at
  // least 2 Needed() wide. The goal lies Needed() + 0.3 m in front of the gap's middle on the
  // LSR's side, at least 0.5 m from `from` and from every point of `avoid`; `face` is the gap's
  // middle. nullopt when there is no such gap or no path.
  struct Move {
    std::vector<Eigen::Vector2d> path;
    std::optional<Eigen::Vector2d> face;  // what the robot turns to at the end (Drive)
  };
  std::optional<Move> DoorwayApproach(const kernel::LocalSafeRegion& lsr,
                                      const Eigen::Vector2d& from, const kernel::FrontierArc& arc,
                                      const std::vector<Eigen::Vector2d>& avoid) const;
  // A given-up frontier retried from another node (ExplorerOptions::retry_nodes): the robot drives
  // to `node` along the graph, then `approach` inside its LSR, as near to `target` (the
  // frontier's middle, or ShadowTarget) as it gets.
  struct Retry {
    graph::Vertex node;
    std::vector<Eigen::Vector2d> approach;
    Eigen::Vector2d target;
  };
  // The next retry, recorded as made: among the frontiers given up and still open (the final
  // check's), retried from fewer than retry_nodes other nodes, the node (neither the owner nor
  // one tried for it) with the reachable point nearest to the target (0.1 m inside the owner's
  // LSR, on the arc's middle or the shadow edge's) that is nearer than the owner and sees it
  // through the union of the LSRs (kernel::UnionLineOfSight); nullopt when there is none.
  std::optional<Retry> NextRetry();
  // Carries a retry out from node `current`: along the graph (graph::BidirectionalAStar) to the
  // retry's node, then its approach, facing the target; returns the node where the robot is then
  // (a new one, child of the retry's node, when the approach was driven).
  graph::Vertex DriveRetry(graph::Vertex current, const Retry& retry);
  // Turns in place to face `point` (TurnTowards) and senses: a new node, child of `from`, at the
  // same place, whose LSR has the laser towards the point.
  graph::Vertex LookTowards(graph::Vertex from, const Eigen::Vector2d& point);
  // The configurations of all the nodes (what Approach keeps away from).
  std::vector<Eigen::Vector2d> NodePositions() const;
  // When another LSR covers a frontier (the view_depth and shadow_edge options).
  kernel::CoverOptions Cover() const {
    kernel::CoverOptions cover;
    cover.view_depth_m = options_.frontier_view_depth_m;
    cover.shadow_edge_m = options_.shadow_edge_m;
    if (options_.frontiers_carry_on) cover.min_free_arc_m = options_.min_frontier_m;
    return cover;
  }
  // The robot's radius plus the clearance margin: what a leg keeps from the LSR boundary, m.
  double Needed() const;
  // PathInside to `to`, else to the first clear point 0.15, 0.3 or 0.45 m from it (every
  // 30 deg): a goal placed with an older estimate may lie too close to an obstacle now.
  std::optional<std::vector<Eigen::Vector2d>> PathNear(const kernel::LocalSafeRegion& lsr,
                                                       const Eigen::Vector2d& from,
                                                       const Eigen::Vector2d& to) const;
  // The free arcs of an LSR that are frontiers: those at least min_frontier_m long, and with
  // doorway_goals the shorter ones seen through a gap at least 2 Needed() wide (GapOf): a door at
  // a slant near the LSR's rim leaves an arc shorter than the door (office-doors: a room whose
  // door a node saw 2.9 m away at 50 deg left a 0.36 m arc, dropped, and the run said
  // `explored`). Only within the laser's field of view `laser_view` (world frame; nullopt: all
  // around): the sonars' cones are 30 deg wide, and a short arc between two of them is an
  // artefact of the cone model, which may lie inside an obstacle a cone's edge did not echo
  // (`complex`, SRT seed 1: a 0.11 m arc in a pillar, open at the end of a run that explored
  // everything).
  std::vector<kernel::FrontierArc> FrontiersOf(
      const kernel::LocalSafeRegion& lsr,
      const std::optional<kernel::FrontierArc>& laser_view = std::nullopt) const;
  // The gap through which the sensor saw free arc `arc` of `lsr`: its jambs, the boundary
  // vertices on either side of the arc's middle where the region narrows to the occluders: the
  // near end of the first shadow edge (kernel::IsShadowEdge) past the arc, or the first vertex
  // off the arc when the edge to it is shorter than shadow_edge_m (a door at the rim); within 45
  // deg of the arc's middle. nullopt when a side has none.
  struct Gap {
    Eigen::Vector2d left, right;
    double Width() const { return (left - right).norm(); }
  };
  std::optional<Gap> GapOf(const kernel::LocalSafeRegion& lsr,
                           const kernel::FrontierArc& arc) const;
  // The free arcs of `arcs` at least min_frontier_m long.
  std::vector<kernel::FrontierArc> LongEnough(const std::vector<kernel::FrontierArc>& arcs) const;

  const kernel::Pose2& estimate() const { return estimate_; }
  graph::ExplorationGraph& graph() { return run_.graph; }
  ExplorationRun& run() { return run_; }
  kernel::Random& random() { return random_; }
  const ExplorerOptions& options() const { return options_; }

  // Adds the wall time of its scope to the run's planning time.
  class PlanningTimer {
   public:
    explicit PlanningTimer(Session* session)
        : session_(session), begin_(std::chrono::steady_clock::now()) {}
    ~PlanningTimer() {
      session_->run_.planning_wall_s +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - begin_).count();
    }
    PlanningTimer(const PlanningTimer&) = delete;
    PlanningTimer& operator=(const PlanningTimer&) = delete;

   private:
    Session* session_;
    std::chrono::steady_clock::time_point begin_;
  };

 private:
  // Senses (odometry, laser, sonar); a localisation that needs scans updates the estimate with
  // the reading, which is then traced.
  Perception SenseHere();
  // LsrPlanner's shortest path from `from` to `to` (LegsAlong), from the start cell, else from
  // the Escapes; nullopt when there is none.
  std::optional<std::vector<Eigen::Vector2d>> GridPath(const kernel::LocalSafeRegion& lsr,
                                                       const Eigen::Vector2d& from,
                                                       const Eigen::Vector2d& to) const;
  // `planner`'s cell path to `to`, shortened to the fewest legs that pass LegIsClear; nullopt
  // when there is none.
  std::optional<std::vector<Eigen::Vector2d>> LegsAlong(const kernel::LocalSafeRegion& lsr,
                                                        const Eigen::Vector2d& from,
                                                        const Eigen::Vector2d& to,
                                                        const LsrPlanner& planner) const;
  // The nodes' given-up arcs and shadows, each checked against the union of the other nodes' LSRs
  // (OpenParts, ShadowOpen; an arc also against every node's laser hits within
  // frontier_view_depth_m behind it), and the unseen stretches (UnseenStretches).
  std::vector<GivenUpFrontier> GivenUpFrontiers() const;
  // The stretches of the nodes' LSR boundaries that only the sonars bounded (beams past the
  // laser's) and beyond which no node's laser saw (kernel::UnionSeesBeyond over the laser-only
  // LSRs) nor hit an obstacle within frontier_view_depth_m, at least min_frontier_m long: a
  // sonar echo may come from anywhere in its cone, so such a boundary is no obstacle and what
  // lies behind it is unknown (ExplorerOptions::unseen_frontiers). `hits`: every node's laser
  // hits (NodeLaserHits).
  std::vector<GivenUpFrontier> UnseenStretches(const LaserHits& hits) const;
  // The LSRs of the nodes other than v that can reach view_depth beyond v's circle.
  std::vector<const kernel::LocalSafeRegion*> OthersNear(graph::Vertex v) const;

  ExplorerOptions options_;
  RobotInterface* robot_;
  Localization* localization_;
  kernel::Random random_;
  ExplorationRun run_;
  kernel::Pose2 estimate_;
  std::size_t drive_begin_ = 0;  // trace index where the last Drive() began
  int failures_in_a_row_ = 0;
  std::vector<std::pair<Eigen::Vector2d, graph::Vertex>> retries_;  // NextRetry's (target, node)
  // The straight legs out of `from` when the robot stands closer to the boundary of `lsr` than
  // Needed(): in every direction (each 5 deg) the shortest leg, in steps of a grid cell, that
  // LegIsClear takes from the robot and that ends where the exact clearance exceeds Needed();
  // their ends. Empty when the robot stands clear or options.exact_escapes is off.
  std::vector<Eigen::Vector2d> Escapes(const kernel::LocalSafeRegion& lsr,
                                       const Eigen::Vector2d& from) const;
  // GridPath's planner for (lsr, from), from the start cell or (`escape`) from Escapes, built
  // anew unless it was the last one of its kind asked for; nullptr for `escape` when there are no
  // escapes.
  const LsrPlanner* PlannerFor(const kernel::LocalSafeRegion& lsr, const Eigen::Vector2d& from,
                               bool escape = false) const;
  // A planner and the region and start it was built for.
  struct CachedPlanner {
    std::optional<LsrPlanner> planner;
    Eigen::Vector2d lsr_center, lsr_first, from;
    std::size_t lsr_size = 0;
    bool built = false;
    bool Matches(const kernel::LocalSafeRegion& lsr, const Eigen::Vector2d& at) const;
  };
  mutable CachedPlanner planner_, escape_planner_;
};

}  // namespace splam::exploration::internal

#endif  // SPLAM_EXPLORATION_INTERNAL_SESSION_H_
