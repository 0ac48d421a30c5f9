#include "exploration/session.h"

#include <algorithm>
#include <sstream>
#include <utility>

#include "exploration/perception.h"

namespace splam::exploration {
namespace {

constexpr double kPathSpacing = 0.1;  // m between the stored points of a driven path

}  // namespace

Session::Session(const std::string& explorer, const ExplorerOptions& options, RobotInterface* robot,
                 Localization* localization)
    : options_(options),
      robot_(robot),
      localization_(localization),
      random_(options.seed),
      rules_(options, robot->description().radius_m + options.clearance_margin_m),
      paths_(options, rules_.needed_m()) {
  run_.explorer = explorer;
  run_.localization = localization->name();
}

bool Session::Start() {
  if (const kernel::Status problem = options_.Validate(); !problem.ok()) {
    run_.termination = Termination::kInvalidInput;
    run_.message = "invalid explorer options: " + problem.message();
    return false;
  }
  const double needed = paths_.Needed();
  if (needed >= options_.lsr_radius_m) {
    std::ostringstream message;
    message << "the LSR radius r = " << options_.lsr_radius_m
            << " m leaves no room for the robot: it must exceed the robot's radius plus the "
               "clearance margin, "
            << needed << " m";
    run_.termination = Termination::kInvalidInput;
    run_.message = message.str();
    return false;
  }
  if (options_.alpha * options_.lsr_radius_m + needed >= options_.lsr_radius_m) {
    run_.termination = Termination::kInvalidInput;
    run_.message = "alpha * r leaves no room for the robot inside the LSR: alpha must be below " +
                   std::to_string((options_.lsr_radius_m - needed) / options_.lsr_radius_m);
    return false;
  }
  const Perception first = robot_->ReadOdometry();
  const kernel::Pose2 start = first.true_pose.value_or(first.odometry_pose);
  if (const kernel::Status problem = localization_->Start(robot_->description(), start, first);
      !problem.ok()) {
    run_.termination = Termination::kInvalidInput;
    run_.message = problem.message();
    return false;
  }
  estimate_ = localization_->Update(first);
  run_.trace.push_back(
      {first.time_s, estimate_, first.odometry_pose, first.true_pose.value_or(estimate_)});
  return true;
}

Perception Session::SenseHere() {
  const Perception perception = robot_->Sense();
  if (localization_->needs_scans()) {
    estimate_ = localization_->Update(perception);
    run_.trace.push_back({perception.time_s, estimate_, perception.odometry_pose,
                          perception.true_pose.value_or(estimate_)});
  }
  return perception;
}

graph::Vertex Session::AddNodeHere(int parent) {
  const Perception perception = SenseHere();
  FollowRevisedNodes();
  NodeRecord record;
  record.time_s = perception.time_s;
  record.true_pose = perception.true_pose.value_or(estimate_);
  record.safe_region_scan = SafeRegionScan(perception, robot_->description());
  record.laser_beams = perception.scan.size();
  record.parent = parent;
  const graph::Vertex v = run_.graph.AddNode(estimate_);
  graph::NodeData& node = run_.graph[v];
  node.lsr = SafeRegionAt(record.safe_region_scan, estimate_, robot_->description(),
                          options_.lsr_radius_m);
  const double laser_start =
      (estimate_ * robot_->description().robot_T_laser).theta() + perception.scan.start_angle_rad;
  const double laser_width = perception.scan.angular_step_rad *
                             static_cast<double>(std::max<std::size_t>(record.laser_beams, 1) - 1);
  node.frontiers =
      rules_.FrontiersOf(node.lsr, kernel::FrontierArc{laser_start, laser_start + laser_width});
  if (options_.shadow_frontiers)
    node.shadows =
        kernel::OcclusionEdges(node.lsr, options_.shadow_edge_m, options_.frontier_view_depth_m);
  localization_->AtNode(node.lsr);
  if (parent >= 0) {
    // The path driven since the last move began, thinned to kPathSpacing.
    std::vector<Eigen::Vector2d> path{
        run_.graph[static_cast<graph::Vertex>(parent)].configuration.translation()};
    for (std::size_t k = drive_begin_; k < run_.trace.size(); ++k) {
      const Eigen::Vector2d p = run_.trace[k].estimate.translation();
      if ((p - path.back()).norm() >= kPathSpacing) path.push_back(p);
    }
    if ((estimate_.translation() - path.back()).norm() > 1e-9)
      path.push_back(estimate_.translation());
    run_.graph.AddEdge(static_cast<graph::Vertex>(parent), v, std::move(path));
  }
  run_.nodes.push_back(std::move(record));
  if (options_.on_node) options_.on_node(static_cast<int>(run_.nodes.size()), perception.time_s);
  return v;
}

void Session::FollowRevisedNodes() { run_.graph.MoveNodes(localization_->NodePoses()); }

graph::Vertex Session::NodeAfterFailedMove(graph::Vertex from) {
  constexpr double kProgress = 0.3;  // m
  if ((estimate_.translation() - run_.graph[from].configuration.translation()).norm() < kProgress)
    return from;
  return AddNodeHere(static_cast<int>(from));
}

MoveResult Session::Drive(const std::vector<Eigen::Vector2d>& waypoints,
                          const std::optional<Eigen::Vector2d>& face) {
  constexpr int kReplans = 2;
  drive_begin_ = run_.trace.size();
  MoveResult result = MoveTo(waypoints, estimate_.translation(), options_.motion, robot_,
                             localization_, &estimate_, &run_.trace);
  std::vector<Eigen::Vector2d> remaining = waypoints;
  for (int replan = 0; replan < kReplans && result.blocked && !result.reached; ++replan) {
    // The waypoints were planned in an older map frame (an edge stored when the estimate was
    // different): re-plan inside the region the robot perceives now, to the farthest remaining
    // waypoint it can reach, and go on from there.
    remaining.erase(remaining.begin(), remaining.begin() + result.waypoints_reached);
    const Perception perception = SenseHere();
    const kernel::LocalSafeRegion here =
        SafeRegionAt(SafeRegionScan(perception, robot_->description()), estimate_,
                     robot_->description(), options_.lsr_radius_m);
    // Only waypoints PathNear can reach inside `here` (within its radius plus the largest goal
    // offset) are tried: a path stored across a long edge holds thousands of waypoints, and
    // each PathNear costs thousands of clearance tests.
    const double reach = here.radius() + SafePaths::kMaxGoalOffsetM;
    std::optional<std::vector<Eigen::Vector2d>> path;
    std::size_t k = remaining.size();
    while (!path && k-- > 0) {
      if ((remaining[k] - here.center()).norm() <= reach)
        path = paths_.PathNear(here, estimate_.translation(), remaining[k]);
    }
    if (!path) break;
    ++run_.replanned_moves;
    path->insert(path->end(), remaining.begin() + static_cast<std::ptrdiff_t>(k) + 1,
                 remaining.end());
    remaining = std::move(*path);
    result = MoveTo(remaining, estimate_.translation(), options_.motion, robot_, localization_,
                    &estimate_, &run_.trace);
    result.blocked = true;  // the move as a whole was refused a step
  }
  ++run_.moves;
  if (result.blocked) ++run_.blocked_steps;
  if (result.reached) {
    failures_in_a_row_ = 0;
    if (face && options_.face_frontiers && InSight(estimate_.translation(), *face))
      TurnTowards(*face, options_.motion, robot_, localization_, &estimate_, &run_.trace);
  } else {
    ++run_.failed_moves;
    ++failures_in_a_row_;
  }
  FollowRevisedNodes();
  return result;
}

bool Session::CapReached() {
  if (options_.stop && options_.stop()) {
    run_.termination = Termination::kInterrupted;
    run_.message = "stopped on request (Ctrl-C)";
    return true;
  }
  if (failures_in_a_row_ >= options_.max_failed_moves) {
    run_.termination = Termination::kStuck;
    run_.message = std::to_string(failures_in_a_row_) + " moves in a row failed";
    return true;
  }
  if (static_cast<int>(run_.graph.num_nodes()) >= options_.max_nodes) {
    run_.termination = Termination::kNodeLimit;
    run_.message = "node limit of " + std::to_string(options_.max_nodes) + " reached";
    return true;
  }
  if (!run_.trace.empty() &&
      run_.trace.back().time_s - run_.trace.front().time_s >= options_.max_time_s) {
    run_.termination = Termination::kTimeLimit;
    run_.message = "time limit of " + std::to_string(options_.max_time_s) + " s reached";
    return true;
  }
  return false;
}

void Session::GiveUp(graph::Vertex v, const kernel::FrontierArc& arc, const std::string& reason) {
  run_.graph[v].given_up.push_back({arc, reason});
}

void Session::GiveUpShadow(graph::Vertex v, std::size_t edge, const std::string& reason) {
  run_.graph[v].given_up.push_back({{}, reason, static_cast<int>(edge)});
}

graph::Vertex Session::LookTowards(graph::Vertex from, const Eigen::Vector2d& point) {
  drive_begin_ = run_.trace.size();
  TurnTowards(point, options_.motion, robot_, localization_, &estimate_, &run_.trace);
  return AddNodeHere(static_cast<int>(from));
}

ExplorationRun Session::Finish(Termination termination, const std::string& message) {
  run_.termination = termination;
  run_.message = message;
  run_.given_up = GivenUpFrontiers();
  const auto open = std::count_if(run_.given_up.begin(), run_.given_up.end(),
                                  [](const GivenUpFrontier& f) { return f.open; });
  if (termination == Termination::kExplored && open > 0) {
    run_.termination = Termination::kIncomplete;
    run_.message = message + "; but " + std::to_string(open) +
                   " frontier pieces given up are still open in the map";
  }
  run_.distance_m = 0.0;
  for (std::size_t k = 1; k < run_.trace.size(); ++k) {
    run_.distance_m +=
        (run_.trace[k].truth.translation() - run_.trace[k - 1].truth.translation()).norm();
  }
  run_.time_s = run_.trace.empty() ? 0.0 : run_.trace.back().time_s - run_.trace.front().time_s;
  return std::move(run_);
}

}  // namespace splam::exploration
