#ifndef SPLAM_EXPLORATION_SESSION_H_
#define SPLAM_EXPLORATION_SESSION_H_

#include <Eigen/Core>
#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "exploration/explorer.h"
#include "exploration/frontier_map.h"
#include "exploration/frontier_rules.h"
#include "exploration/safe_paths.h"
#include "kernel/local_safe_region.h"
#include "kernel/random.h"

namespace splam::exploration {

// One exploration run as an explorer drives it: the robot, the localisation, the graph of nodes
// with their LSRs and frontiers, the run's record, and the caps. An explorer (SRT, REG, a
// variant) is a loop over a Session: Start(), AddNodeHere() at the start, then choose a path
// (with paths(), rules() and steps.h), Drive() it and AddNodeHere() (or NodeAfterFailedMove()),
// until it decides it is done or CapReached(); Finish() returns the run. The session keeps the
// nodes where the localisation puts them (FollowRevisedNodes after every move and sensing).
class Session {
 public:
  // `explorer` names the run (ExplorationRun::explorer); the options are the shared ones.
  Session(const std::string& explorer, const ExplorerOptions& options, RobotInterface* robot,
          Localization* localization);

  // Validates the options, reads the first perception and starts the localisation; false (with
  // the run's termination and message set) when the run cannot start.
  bool Start();
  // Senses here and adds a node (its LSR at the current estimate, its frontiers the LSR's free
  // arcs that FrontierRules::FrontiersOf keeps, its shadows with shadow_frontiers). With
  // parent >= 0 the node is joined to it along the path driven since the last Drive() began.
  graph::Vertex AddNodeHere(int parent);
  // Where the robot is after a move from node `from` that failed: a new node (child of `from`)
  // when it got more than 0.3 m away, else `from` itself (no node is added).
  graph::Vertex NodeAfterFailedMove(graph::Vertex from);
  // MOVE_TO through the waypoints; counts moves and failures. When the robot is refused a step
  // (the waypoints came from an older estimate), it senses and re-plans inside the LSR it
  // perceives there (SafePaths::PathNear) to the farthest remaining waypoint it can reach, then
  // follows the rest; at most twice per move.
  // With `face` (and options.face_frontiers), a robot that reached the last waypoint and has that
  // point in sight (InSight) turns in place to face it (TurnTowards): what an approach came to
  // see. Facing a point behind a wall would only turn the laser from the free space to the wall.
  MoveResult Drive(const std::vector<Eigen::Vector2d>& waypoints,
                   const std::optional<Eigen::Vector2d>& face = std::nullopt);
  // Turns in place to face `point` (TurnTowards) and senses: a new node, child of `from`, at the
  // same place, whose LSR has the laser towards the point.
  graph::Vertex LookTowards(graph::Vertex from, const Eigen::Vector2d& point);
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
  // kExplored is checked against its own map first: the given-up frontiers still open
  // (GivenUpFrontiers) are listed in run.given_up, and the run is kIncomplete when there is one.
  ExplorationRun Finish(Termination termination, const std::string& message);
  // Ends the run with the termination already set (by Start() or CapReached()).
  ExplorationRun Finish() { return Finish(run_.termination, run_.message); }

  // The session's map (frontier_map.h on graph()).
  std::vector<GivenUpFrontier> GivenUpFrontiers() const {
    return exploration::GivenUpFrontiers(rules_, run_, robot_->description().robot_T_laser);
  }
  std::vector<kernel::FrontierArc> OpenParts(graph::Vertex v,
                                             const kernel::FrontierArc& arc) const {
    return exploration::OpenParts(rules_, run_.graph, v, arc);
  }
  bool ShadowOpen(graph::Vertex v, std::size_t edge) const {
    return exploration::ShadowOpen(rules_, run_.graph, v, edge);
  }
  bool InSight(const Eigen::Vector2d& from, const Eigen::Vector2d& point) const {
    return exploration::InSight(rules_, run_.graph, from, point);
  }
  std::vector<Eigen::Vector2d> NodePositions() const {
    return exploration::NodePositions(run_.graph);
  }

  const FrontierRules& rules() const { return rules_; }
  const SafePaths& paths() const { return paths_; }
  const ExplorerOptions& options() const { return options_; }
  const Localization& localization() const { return *localization_; }
  const kernel::Pose2& estimate() const { return estimate_; }
  graph::ExplorationGraph& graph() { return run_.graph; }
  const graph::ExplorationGraph& graph() const { return run_.graph; }
  ExplorationRun& run() { return run_; }
  const ExplorationRun& run() const { return run_; }
  kernel::Random& random() { return random_; }

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

  ExplorerOptions options_;
  RobotInterface* robot_;
  Localization* localization_;
  kernel::Random random_;
  FrontierRules rules_;
  SafePaths paths_;
  ExplorationRun run_;
  kernel::Pose2 estimate_;
  std::size_t drive_begin_ = 0;  // trace index where the last Drive() began
  int failures_in_a_row_ = 0;
};

}  // namespace splam::exploration

#endif  // SPLAM_EXPLORATION_SESSION_H_
