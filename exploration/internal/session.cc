#include "exploration/internal/session.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <sstream>
#include <unordered_set>
#include <utility>

#include "exploration/internal/lsr_planner.h"
#include "exploration/perception.h"
#include "graph/bidirectional_astar.h"
#include "graph/frontiers.h"
#include "kernel/angle.h"
#include "kernel/shapes.h"

namespace splam::exploration::internal {

// Laser hit points on a grid of kCell squares: an obstacle a laser saw bounds the space behind
// a sonar boundary in front of it (Session::UnseenStretches).
class LaserHits {
 public:
  void Add(const Eigen::Vector2d& p) { cells_.insert(Key(p)); }
  // Whether a hit lies in a cell next to the ray p + t u, 0 <= t <= length (u unit).
  bool AlongRay(const Eigen::Vector2d& p, const Eigen::Vector2d& u, double length) const {
    for (double t = 0.0; t <= length; t += 0.5 * kCell) {
      for (const double dx : {-kCell, 0.0, kCell})
        for (const double dy : {-kCell, 0.0, kCell})
          if (cells_.contains(Key(p + t * u + Eigen::Vector2d(dx, dy)))) return true;
    }
    return false;
  }

 private:
  static constexpr double kCell = 0.1;  // m
  static std::int64_t Key(const Eigen::Vector2d& p) {
    return (static_cast<std::int64_t>(std::floor(p.x() / kCell)) << 32) ^
           (static_cast<std::int64_t>(std::floor(p.y() / kCell)) & 0xffffffff);
  }
  std::unordered_set<std::int64_t> cells_;
};

namespace {

// Every node's laser hits, where the nodes are now.
LaserHits NodeLaserHits(const ExplorationRun& run, const kernel::Pose2& robot_T_laser) {
  LaserHits hits;
  for (graph::Vertex v = 0; v < run.nodes.size(); ++v) {
    kernel::Scan laser = run.nodes[v].safe_region_scan;
    laser.ranges_m.resize(run.nodes[v].laser_beams);
    const kernel::Pose2 world_T_laser = run.graph[v].configuration * robot_T_laser;
    for (const Eigen::Vector2d& hit : laser.HitPoints()) hits.Add(world_T_laser * hit);
  }
  return hits;
}

constexpr double kPathSpacing = 0.1;  // m between the stored points of a driven path
// How much closer to the LSR boundary than where it stands a leg from the robot may come, m.
constexpr double kStartTolerance = 0.5 * LsrPlanner::kCellM;
// The polar grid of PathInside's waypoints around the LSR's centre.
constexpr double kWaypointRadii[] = {0.4, 0.8, 1.2, 1.6, 2.0};  // m
constexpr int kWaypointDirections = 36;
// Where PathNear looks for a clear goal around one that is not.
constexpr double kGoalOffsets[] = {0.15, 0.3, 0.45};  // m
constexpr int kGoalOffsetDirections = 12;
// How far an approach takes the robot at least, from where it starts and from every node: a new
// node where it sees differently, m.
constexpr double kMinTravel = 0.5;
// The point of a frontier that an approach must see lies this far inside its owner's LSR, m.
constexpr double kSightInside = 0.1;

}  // namespace

Session::Session(const std::string& explorer, const ExplorerOptions& options, RobotInterface* robot,
                 Localization* localization)
    : options_(options), robot_(robot), localization_(localization), random_(options.seed) {
  run_.explorer = explorer;
  run_.localization = localization->name();
}

bool Session::Start() {
  if (const kernel::Status problem = options_.Validate(); !problem.ok()) {
    run_.termination = Termination::kInvalidInput;
    run_.message = "invalid explorer options: " + problem.message();
    return false;
  }
  const double needed = Needed();
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
  if (const std::string problem = localization_->Start(robot_->description(), start, first);
      !problem.empty()) {
    run_.termination = Termination::kInvalidInput;
    run_.message = problem;
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
  const graph::Vertex v = graph::AddNode(&run_.graph, estimate_);
  graph::NodeData& node = run_.graph[v];
  node.lsr = SafeRegionAt(record.safe_region_scan, estimate_, robot_->description(),
                          options_.lsr_radius_m);
  const double laser_start =
      (estimate_ * robot_->description().robot_T_laser).theta() + perception.scan.start_angle_rad;
  const double laser_width = perception.scan.angular_step_rad *
                             static_cast<double>(std::max<std::size_t>(record.laser_beams, 1) - 1);
  node.frontiers =
      FrontiersOf(node.lsr, kernel::FrontierArc{laser_start, laser_start + laser_width});
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
    graph::AddEdge(&run_.graph, static_cast<graph::Vertex>(parent), v, std::move(path));
  }
  run_.nodes.push_back(std::move(record));
  if (options_.on_node) options_.on_node(static_cast<int>(run_.nodes.size()), perception.time_s);
  return v;
}

void Session::FollowRevisedNodes() { graph::MoveNodes(&run_.graph, localization_->NodePoses()); }

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
    const double reach = here.radius() + kGoalOffsets[std::size(kGoalOffsets) - 1];
    std::optional<std::vector<Eigen::Vector2d>> path;
    std::size_t k = remaining.size();
    while (!path && k-- > 0) {
      if ((remaining[k] - here.center()).norm() <= reach)
        path = PathNear(here, estimate_.translation(), remaining[k]);
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
  if (static_cast<int>(boost::num_vertices(run_.graph)) >= options_.max_nodes) {
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

std::vector<const kernel::LocalSafeRegion*> Session::OthersNear(graph::Vertex v) const {
  const graph::ExplorationGraph& g = run_.graph;
  const kernel::LocalSafeRegion& owner = g[v].lsr;
  std::vector<const kernel::LocalSafeRegion*> others;
  for (graph::Vertex w = 0; w < boost::num_vertices(g); ++w) {
    const kernel::LocalSafeRegion& other = g[w].lsr;
    const double reach = other.radius() + owner.radius() + options_.frontier_view_depth_m;
    if (w != v && (other.center() - owner.center()).norm() <= reach) others.push_back(&other);
  }
  return others;
}

bool Session::ShadowCovered(const kernel::LocalSafeRegion& owner, std::size_t edge,
                            const std::vector<const kernel::LocalSafeRegion*>& others) const {
  // Seen behind at a quarter, the middle or three quarters of the edge: the hidden space is not
  // a slit then (near the occluder the ray from the middle often runs into the occluder's own
  // flank, seen at grazing incidence).
  const kernel::EdgeSide side = kernel::EdgeMiddleAndNormal(owner, edge);
  const Eigen::Vector2d& a = owner.boundary()[edge];
  const Eigen::Vector2d& b = owner.boundary()[(edge + 1) % owner.boundary().size()];
  for (const double f : {0.5, 0.25, 0.75})
    if (kernel::UnionSeesBeyond(others, a + f * (b - a), side.outward, Cover())) return true;
  return false;
}

bool Session::ShadowOpen(graph::Vertex v, std::size_t edge) const {
  return !ShadowCovered(run_.graph[v].lsr, edge, OthersNear(v));
}

Eigen::Vector2d Session::ShadowTarget(const kernel::LocalSafeRegion& lsr, std::size_t edge) {
  constexpr double kInto = 0.5;  // m
  const kernel::EdgeSide side = kernel::EdgeMiddleAndNormal(lsr, edge);
  return side.middle + kInto * side.outward;
}

Eigen::Vector2d Session::ArcSight(const kernel::LocalSafeRegion& lsr,
                                  const kernel::FrontierArc& arc) {
  const double mid = 0.5 * (arc.start_angle_rad + arc.end_angle_rad);
  return lsr.center() +
         (lsr.radius() - kSightInside) * Eigen::Vector2d(std::cos(mid), std::sin(mid));
}

Eigen::Vector2d Session::ShadowSight(const kernel::LocalSafeRegion& lsr, std::size_t edge) {
  const kernel::EdgeSide side = kernel::EdgeMiddleAndNormal(lsr, edge);
  return side.middle - kSightInside * side.outward;
}

Eigen::Vector2d Session::UnseenSight(const kernel::LocalSafeRegion& lsr,
                                     const Eigen::Vector2d& point) {
  const Eigen::Vector2d offset = point - lsr.center();
  const double norm = offset.norm();
  return norm > 2.0 * kSightInside ? Eigen::Vector2d(point - kSightInside / norm * offset) : point;
}

bool Session::InSight(const Eigen::Vector2d& from, const Eigen::Vector2d& point) const {
  const graph::ExplorationGraph& g = run_.graph;
  std::vector<const kernel::LocalSafeRegion*> regions;
  for (graph::Vertex v = 0; v < boost::num_vertices(g); ++v)
    if ((g[v].lsr.center() - point).norm() <= g[v].lsr.radius() + (point - from).norm())
      regions.push_back(&g[v].lsr);
  return kernel::UnionLineOfSight(regions, from, point, options_.shadow_edge_m);
}

std::vector<kernel::FrontierArc> Session::OpenParts(graph::Vertex v,
                                                    const kernel::FrontierArc& arc) const {
  return UncoveredParts(run_.graph[v].lsr, arc, OthersNear(v));
}

std::vector<GivenUpFrontier> Session::GivenUpFrontiers() const {
  const graph::ExplorationGraph& g = run_.graph;
  const LaserHits hits = NodeLaserHits(run_, robot_->description().robot_T_laser);
  std::vector<GivenUpFrontier> list;
  for (graph::Vertex v = 0; v < boost::num_vertices(g); ++v) {
    const kernel::LocalSafeRegion& owner = g[v].lsr;
    for (const graph::GivenUpArc& given_up : g[v].given_up) {
      if (given_up.shadow_edge >= 0) {
        const auto edge = static_cast<std::size_t>(given_up.shadow_edge);
        list.push_back({static_cast<int>(v),
                        {},
                        given_up.shadow_edge,
                        {},
                        kernel::EdgeMiddleAndNormal(owner, edge).middle,
                        given_up.reason,
                        ShadowOpen(v, edge)});
        continue;
      }
      std::vector<kernel::FrontierArc> left = OpenParts(v, given_up.arc);
      if (!left.empty()) {
        // A part behind which a laser hit an obstacle within frontier_view_depth_m at every
        // point is closed, as where an LSR's ray leaves across an obstacle (kernel::CoverOptions):
        // with a SLAM localisation the LSR that saw the obstacle may lie too far off to hold it
        // (`complex`, the paper formulation's seed 1: an arc 0.3 m inside a pillar).
        std::erase_if(left, [&](const kernel::FrontierArc& arc) {
          const int steps = std::max(
              1, static_cast<int>(std::ceil(arc.AngularWidth() / options_.arc_sampling_rad)));
          for (int k = 0; k <= steps; ++k) {
            const double angle = arc.start_angle_rad + arc.AngularWidth() * k / steps;
            if (!hits.AlongRay(owner.ArcPoint(angle),
                               Eigen::Vector2d(std::cos(angle), std::sin(angle)),
                               options_.frontier_view_depth_m))
              return false;
          }
          return true;
        });
      }
      const double mid = 0.5 * (given_up.arc.start_angle_rad + given_up.arc.end_angle_rad);
      if (left.empty())
        list.push_back({static_cast<int>(v),
                        given_up.arc,
                        -1,
                        {},
                        owner.ArcPoint(mid),
                        given_up.reason,
                        false});
      for (const kernel::FrontierArc& arc : left) {
        const double m = 0.5 * (arc.start_angle_rad + arc.end_angle_rad);
        list.push_back(
            {static_cast<int>(v), arc, -1, {}, owner.ArcPoint(m), given_up.reason, true});
      }
    }
  }
  std::vector<GivenUpFrontier> unseen =
      options_.unseen_frontiers ? UnseenStretches(hits) : std::vector<GivenUpFrontier>();
  list.insert(list.end(), std::make_move_iterator(unseen.begin()),
              std::make_move_iterator(unseen.end()));
  return list;
}

std::vector<GivenUpFrontier> Session::UnseenStretches(const LaserHits& hits) const {
  constexpr double kInside = 0.05;  // m: a boundary point is tested this far inside it
  const graph::ExplorationGraph& g = run_.graph;
  // What each node's laser alone saw, where the node is now.
  std::vector<kernel::LocalSafeRegion> laser_lsrs;
  for (graph::Vertex v = 0; v < run_.nodes.size(); ++v) {
    kernel::Scan laser = run_.nodes[v].safe_region_scan;
    laser.ranges_m.resize(run_.nodes[v].laser_beams);
    laser_lsrs.push_back(kernel::LocalSafeRegion::FromScan(
        laser, g[v].configuration * robot_->description().robot_T_laser, options_.lsr_radius_m));
  }
  std::vector<GivenUpFrontier> list;
  for (graph::Vertex v = 0; v < run_.nodes.size(); ++v) {
    const NodeRecord& record = run_.nodes[v];
    const kernel::LocalSafeRegion& lsr = g[v].lsr;
    const std::vector<Eigen::Vector2d>& boundary = lsr.boundary();
    if (!lsr.full_circle() || boundary.size() != record.safe_region_scan.size()) continue;
    std::vector<const kernel::LocalSafeRegion*> near;
    for (const kernel::LocalSafeRegion& other : laser_lsrs) {
      if ((other.center() - lsr.center()).norm() <=
          2.0 * options_.lsr_radius_m + options_.frontier_view_depth_m)
        near.push_back(&other);
    }
    std::vector<Eigen::Vector2d> stretch;
    const auto close = [&] {
      // Not empty: with min_frontier_m 0 an empty stretch is as long as it.
      if (!stretch.empty() && kernel::PolylineLength(stretch) >= options_.min_frontier_m) {
        GivenUpFrontier f;
        f.node = static_cast<int>(v);
        f.midpoint = stretch[stretch.size() / 2];
        f.reason = "bounded by the sonars only; no laser saw beyond";
        f.unseen = stretch;
        list.push_back(std::move(f));
      }
      stretch.clear();
    };
    for (std::size_t i = record.laser_beams; i < boundary.size(); ++i) {
      const double range = record.safe_region_scan.ranges_m[i];
      const Eigen::Vector2d offset = boundary[i] - lsr.center();
      bool seen = !std::isnan(range) && range >= options_.lsr_radius_m;  // a free arc
      if (!seen && offset.norm() > 1e-9) {
        const Eigen::Vector2d u = offset.normalized();
        const Eigen::Vector2d inside = boundary[i] - std::min(kInside, 0.5 * offset.norm()) * u;
        seen = hits.AlongRay(boundary[i], u, options_.frontier_view_depth_m) ||
               kernel::UnionSeesBeyond(near, inside, u, Cover());
      }
      if (seen) {
        close();
      } else {
        stretch.push_back(boundary[i]);
      }
    }
    close();
  }
  return list;
}

std::optional<Session::Retry> Session::NextRetry() {
  constexpr double kSameTarget = 0.5;  // m: targets this close are the same frontier
  constexpr int kStride = 4;           // goals are tried on every 4th cell (20 cm)
  if (!options_.grid_paths || options_.retry_nodes == 0) return std::nullopt;
  const graph::ExplorationGraph& g = run_.graph;
  const std::vector<Eigen::Vector2d> nodes = NodePositions();
  std::optional<Retry> best;
  double best_distance = std::numeric_limits<double>::infinity();
  for (const GivenUpFrontier& frontier : GivenUpFrontiers()) {
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
      const Eigen::Vector2d target = UnseenSight(lsr, deepest);
      std::vector<graph::Vertex> tried;
      for (const auto& [t, v] : retries_)
        if ((t - target).norm() < kSameTarget) tried.push_back(v);
      if (static_cast<int>(tried.size()) >= options_.retry_nodes) continue;
      std::vector<const kernel::LocalSafeRegion*> regions;
      for (graph::Vertex v = 0; v < nodes.size(); ++v)
        if ((nodes[v] - target).norm() <= 2.0 * options_.lsr_radius_m) regions.push_back(&g[v].lsr);
      for (graph::Vertex v = 0; v < nodes.size(); ++v) {
        const double d = (nodes[v] - target).norm();
        if (d >= std::min(best_distance, options_.lsr_radius_m) ||
            std::find(tried.begin(), tried.end(), v) != tried.end() ||
            !kernel::UnionLineOfSight(regions, nodes[v], target, options_.shadow_edge_m))
          continue;
        best = Retry{v, {}, target};
        best_distance = d;
      }
      continue;
    }
    const Eigen::Vector2d target =
        frontier.shadow_edge >= 0 ? ShadowSight(lsr, static_cast<std::size_t>(frontier.shadow_edge))
                                  : ArcSight(lsr, frontier.arc);
    std::vector<graph::Vertex> tried{owner};
    for (const auto& [t, v] : retries_)
      if ((t - target).norm() < kSameTarget) tried.push_back(v);
    if (static_cast<int>(tried.size()) > options_.retry_nodes) continue;
    std::vector<const kernel::LocalSafeRegion*> regions;
    std::vector<std::pair<double, graph::Vertex>> candidates;
    for (graph::Vertex v = 0; v < nodes.size(); ++v) {
      const double d = (nodes[v] - target).norm();
      if (d > 2.0 * options_.lsr_radius_m) continue;
      regions.push_back(&g[v].lsr);
      if (std::find(tried.begin(), tried.end(), v) == tried.end()) candidates.emplace_back(d, v);
    }
    std::sort(candidates.begin(), candidates.end());
    // A goal must come nearer to the target than its owner, and see it.
    const double owner_distance = (nodes[owner] - target).norm();
    for (const auto& [d, v] : candidates) {
      const double bound = std::min(best_distance, owner_distance);
      if (d - options_.lsr_radius_m >= bound) break;  // no point of v's LSR is nearer
      const std::optional<Eigen::Vector2d> goal =
          PlannerFor(g[v].lsr, nodes[v])
              ->NearestReachable(
                  target, kMinTravel, nodes, kMinTravel, kStride, [&](const Eigen::Vector2d& c) {
                    return (c - target).norm() < bound &&
                           kernel::UnionLineOfSight(regions, c, target, options_.shadow_edge_m);
                  });
      if (!goal) continue;
      if (auto path = PathInside(g[v].lsr, nodes[v], *goal)) {
        best = Retry{v, std::move(*path), target};
        best_distance = (*goal - target).norm();
      }
    }
  }
  if (best) retries_.emplace_back(best->target, best->node);
  return best;
}

graph::Vertex Session::DriveRetry(graph::Vertex current, const Retry& retry) {
  if (current != retry.node) {
    const std::optional<graph::GraphPath> path =
        graph::BidirectionalAStar(run_.graph, current, {retry.node});
    if (!path) return current;
    if (!Drive(graph::Waypoints(run_.graph, path->vertices)).reached)
      return NodeAfterFailedMove(current);
  }
  if (retry.approach.empty()) return LookTowards(retry.node, retry.target);
  return Drive(retry.approach, retry.target).reached ? AddNodeHere(static_cast<int>(retry.node))
                                                     : NodeAfterFailedMove(retry.node);
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

std::vector<Eigen::Vector2d> Session::NodePositions() const {
  std::vector<Eigen::Vector2d> nodes;
  for (graph::Vertex v = 0; v < boost::num_vertices(run_.graph); ++v)
    nodes.push_back(run_.graph[v].configuration.translation());
  return nodes;
}

double Session::Needed() const {
  return robot_->description().radius_m + options_.clearance_margin_m;
}

bool Session::LegIsClear(const kernel::LocalSafeRegion& lsr, const Eigen::Vector2d& a,
                         const Eigen::Vector2d& b, bool from_robot) const {
  const double needed = Needed();
  const double length = (b - a).norm();
  if (!from_robot) return kernel::SegmentClearance(lsr, a, b) > needed;
  // The robot may stand closer to the boundary than `needed` (the sonar's part of the boundary
  // is conservative: 0.27 m from the laser behind the robot); the leg must then not get any
  // closer and must be fully clear after its first `needed` metres. A leg shorter than that only
  // must not get closer: required to be fully clear, no such leg is (the short first leg of a
  // bent path through a door was refused).
  // "Not closer" tolerates half a cell of LsrPlanner's grid, whose paths leave such a start
  // sideways along the boundary.
  const double floor = std::min(needed, kernel::SegmentClearance(lsr, a, a)) - kStartTolerance;
  const double whole = kernel::SegmentClearance(lsr, a, b);
  if (length <= needed) return whole > needed || whole >= floor;
  const Eigen::Vector2d away = a + (b - a) * (needed / length);
  return whole >= floor && kernel::SegmentClearance(lsr, away, b) > needed;
}

std::optional<std::vector<Eigen::Vector2d>> Session::PathInside(const kernel::LocalSafeRegion& lsr,
                                                                const Eigen::Vector2d& from,
                                                                const Eigen::Vector2d& to) const {
  if (LegIsClear(lsr, from, to)) return std::vector<Eigen::Vector2d>{to};
  if (options_.grid_paths) return GridPath(lsr, from, to);
  std::vector<std::pair<double, Eigen::Vector2d>> candidates;
  for (double radius : kWaypointRadii) {
    for (int k = 0; k < kWaypointDirections; ++k) {
      const double angle = 2.0 * kernel::kPi * k / kWaypointDirections;
      const Eigen::Vector2d w =
          lsr.center() + radius * Eigen::Vector2d(std::cos(angle), std::sin(angle));
      candidates.emplace_back((w - from).norm() + (to - w).norm(), w);
    }
  }
  std::sort(candidates.begin(), candidates.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [length, w] : candidates) {
    if (LegIsClear(lsr, from, w) && LegIsClear(lsr, w, to, /*from_robot=*/false))
      return std::vector<Eigen::Vector2d>{w, to};
  }
  return std::nullopt;
}

bool Session::CachedPlanner::Matches(const kernel::LocalSafeRegion& lsr,
                                     const Eigen::Vector2d& at) const {
  return built && lsr_center == lsr.center() && lsr_size == lsr.boundary().size() && from == at &&
         !lsr.boundary().empty() && lsr_first == lsr.boundary().front();
}

const LsrPlanner* Session::PlannerFor(const kernel::LocalSafeRegion& lsr,
                                      const Eigen::Vector2d& from, bool escape) const {
  // Displacement asks for many goals from one start.
  CachedPlanner& cached = escape ? escape_planner_ : planner_;
  if (!cached.Matches(lsr, from)) {
    cached.planner.reset();
    if (!escape) {
      cached.planner.emplace(lsr, from, Needed());
    } else if (const std::vector<Eigen::Vector2d> escapes = Escapes(lsr, from); !escapes.empty()) {
      cached.planner.emplace(lsr, from, Needed(), escapes);
    }
    cached.lsr_center = lsr.center();
    cached.lsr_size = lsr.boundary().size();
    cached.lsr_first = lsr.boundary().empty() ? Eigen::Vector2d::Zero() : lsr.boundary().front();
    cached.from = from;
    cached.built = true;
  }
  return cached.planner ? &*cached.planner : nullptr;
}

std::vector<Eigen::Vector2d> Session::Escapes(const kernel::LocalSafeRegion& lsr,
                                              const Eigen::Vector2d& from) const {
  constexpr int kDirections = 72;
  const double needed = Needed();
  std::vector<Eigen::Vector2d> ends;
  if (!options_.exact_escapes || kernel::SegmentClearance(lsr, from, from) >= needed) return ends;
  for (int k = 0; k < kDirections; ++k) {
    const double angle = 2.0 * kernel::kPi * k / kDirections;
    const Eigen::Vector2d direction(std::cos(angle), std::sin(angle));
    for (double length = LsrPlanner::kCellM; length <= 2.0 * needed; length += LsrPlanner::kCellM) {
      const Eigen::Vector2d end = from + length * direction;
      if (kernel::SegmentClearance(lsr, end, end) > needed && LegIsClear(lsr, from, end)) {
        ends.push_back(end);
        break;
      }
    }
  }
  return ends;
}

std::optional<std::vector<Eigen::Vector2d>> Session::Approach(
    const kernel::LocalSafeRegion& lsr, const Eigen::Vector2d& from, const Eigen::Vector2d& target,
    const std::vector<Eigen::Vector2d>& avoid) const {
  if (!options_.grid_paths) return std::nullopt;
  for (const bool escape : {false, true}) {
    const LsrPlanner* planner = PlannerFor(lsr, from, escape);
    if (!planner) continue;
    const std::optional<Eigen::Vector2d> goal =
        planner->NearestReachable(target, kMinTravel, avoid, kMinTravel);
    if (!goal) continue;
    if (auto path = PathInside(lsr, from, *goal)) return path;
  }
  return std::nullopt;
}

std::optional<Session::Gap> Session::GapOf(const kernel::LocalSafeRegion& lsr,
                                           const kernel::FrontierArc& arc) const {
  constexpr double kSearch = kernel::kPi / 4;
  const std::vector<Eigen::Vector2d>& pts = lsr.boundary();
  const std::size_t n = pts.size();
  const Eigen::Vector2d& c = lsr.center();
  const double free_reach = lsr.radius() * (1.0 - 1e-9);
  auto range = [&](std::size_t i) { return (pts[i] - c).norm(); };
  auto bearing = [&](std::size_t i) { return std::atan2(pts[i].y() - c.y(), pts[i].x() - c.x()); };
  // The arc's vertex nearest its middle direction.
  const double mid = 0.5 * (arc.start_angle_rad + arc.end_angle_rad);
  std::optional<std::size_t> middle;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    if (range(i) < free_reach) continue;
    const double off = std::abs(kernel::WrapAngle(bearing(i) - mid));
    if (off < best) {
      best = off;
      middle = i;
    }
  }
  if (!middle) return std::nullopt;
  // Walking from the middle in `step` (+1 or -1) direction past the arc: the first edge off it
  // joins the arc to the jamb when it is short (a door at the rim), else the jamb is the near end
  // of the first shadow edge (a depth jump at the occluder), within kSearch of the middle.
  auto jamb = [&](int step) -> std::optional<Eigen::Vector2d> {
    std::size_t i = *middle;
    bool left_arc = false;
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t edge = step > 0 ? i : (i + n - 1) % n;  // from vertex edge to edge + 1
      const std::size_t next = step > 0 ? (i + 1) % n : (i + n - 1) % n;
      if (!lsr.full_circle() && (edge == 0 || edge == n - 1)) return std::nullopt;  // the sensor
      if (std::abs(kernel::WrapAngle(bearing(next) - mid)) > kSearch) return std::nullopt;
      if (range(next) < free_reach && !left_arc) {
        left_arc = true;
        if ((pts[next] - pts[i]).norm() <= options_.shadow_edge_m) return pts[next];
      }
      if (left_arc && kernel::IsShadowEdge(lsr, edge, options_.shadow_edge_m))
        return range(i) < range(next) ? pts[i] : pts[next];
      i = next;
    }
    return std::nullopt;
  };
  const std::optional<Eigen::Vector2d> left = jamb(+1), right = jamb(-1);
  if (!left || !right) return std::nullopt;
  return Gap{*left, *right};
}

std::optional<Session::Move> Session::DoorwayApproach(
    const kernel::LocalSafeRegion& lsr, const Eigen::Vector2d& from, const kernel::FrontierArc& arc,
    const std::vector<Eigen::Vector2d>& avoid) const {
  constexpr double kStandOff = 0.3;  // m in front of the gap, beyond Needed()
  if (!options_.doorway_goals || !options_.grid_paths) return std::nullopt;
  const std::optional<Gap> gap = GapOf(lsr, arc);
  if (!gap || gap->Width() < 2.0 * Needed()) return std::nullopt;
  const Eigen::Vector2d along = (gap->left - gap->right) / gap->Width();
  const Eigen::Vector2d centre = 0.5 * (gap->left + gap->right);
  Eigen::Vector2d normal(-along.y(), along.x());
  if (normal.dot(lsr.center() - centre) < 0.0) normal = -normal;
  const Eigen::Vector2d goal = centre + (Needed() + kStandOff) * normal;
  if ((goal - from).norm() < kMinTravel ||
      std::any_of(avoid.begin(), avoid.end(),
                  [&](const Eigen::Vector2d& a) { return (goal - a).norm() < kMinTravel; }) ||
      !lsr.Contains(goal))
    return std::nullopt;
  std::optional<std::vector<Eigen::Vector2d>> path = PathInside(lsr, from, goal);
  if (!path) return std::nullopt;
  return Move{std::move(*path), centre};
}

std::vector<kernel::FrontierArc> Session::FrontiersOf(
    const kernel::LocalSafeRegion& lsr,
    const std::optional<kernel::FrontierArc>& laser_view) const {
  const auto in_laser_view = [&](const kernel::FrontierArc& arc) {
    if (!laser_view) return true;
    const double mid = 0.5 * (arc.start_angle_rad + arc.end_angle_rad);
    const double from_start = kernel::WrapAngle(mid - laser_view->start_angle_rad);
    return (from_start >= 0.0 ? from_start : from_start + 2.0 * kernel::kPi) <=
           laser_view->AngularWidth();
  };
  std::vector<kernel::FrontierArc> kept;
  for (const kernel::FrontierArc& arc : lsr.frontiers()) {
    if (graph::ArcLength(arc, options_.lsr_radius_m) >= options_.min_frontier_m) {
      kept.push_back(arc);
    } else if (options_.doorway_goals && in_laser_view(arc) &&
               graph::ArcLength(arc, options_.lsr_radius_m) >= options_.min_doorway_arc_m) {
      const std::optional<Gap> gap = GapOf(lsr, arc);
      if (gap && gap->Width() >= 2.0 * Needed()) kept.push_back(arc);
    }
  }
  return kept;
}

std::optional<std::vector<Eigen::Vector2d>> Session::GridPath(const kernel::LocalSafeRegion& lsr,
                                                              const Eigen::Vector2d& from,
                                                              const Eigen::Vector2d& to) const {
  // The start planner first; its first legs may fail the exact test, the escapes' do not.
  for (const bool escape : {false, true}) {
    const LsrPlanner* planner = PlannerFor(lsr, from, escape);
    if (!planner) continue;
    if (auto path = LegsAlong(lsr, from, to, *planner)) return path;
  }
  return std::nullopt;
}

std::optional<std::vector<Eigen::Vector2d>> Session::LegsAlong(const kernel::LocalSafeRegion& lsr,
                                                               const Eigen::Vector2d& from,
                                                               const Eigen::Vector2d& to,
                                                               const LsrPlanner& planner) const {
  std::optional<std::vector<Eigen::Vector2d>> cells = planner.CellPath(to);
  if (!cells) return std::nullopt;
  std::vector<Eigen::Vector2d>& points = *cells;
  points.front() = from;
  if (points.size() < 2) points.push_back(to);
  points.back() = to;
  // The fewest legs along the cells that pass the exact test: from each point the farthest
  // cell (every 4th, then the next one) with a clear leg.
  std::vector<Eigen::Vector2d> waypoints;
  std::size_t i = 0;
  while (i + 1 < points.size()) {
    std::size_t reached = i;
    for (std::size_t j = points.size() - 1; j > i; j = j > i + 4 ? j - 4 : j - 1) {
      // A leg that begins near the start, where the robot may stand closer than `needed` to the
      // boundary, must not get closer than its beginning, as the first leg.
      const bool near_start = (points[i] - from).norm() <= Needed();
      if (LegIsClear(lsr, points[i], points[j], near_start)) {
        reached = j;
        break;
      }
    }
    // The raster's clearances are a cell off at worst: where no leg passes the exact test (a
    // door as wide as the robot needs, the way out from beside the sonar's blind spike), the next
    // cell is taken if its leg keeps a cell less than the test asks.
    if (reached == i) {
      const double asked = (points[i] - from).norm() <= Needed()
                               ? std::min(Needed(), kernel::SegmentClearance(lsr, from, from))
                               : Needed();
      if (kernel::SegmentClearance(lsr, points[i], points[i + 1]) >= asked - LsrPlanner::kCellM)
        reached = i + 1;
    }
    if (reached == i) return std::nullopt;
    waypoints.push_back(points[reached]);
    i = reached;
  }
  return waypoints;
}

std::optional<std::vector<Eigen::Vector2d>> Session::PathNear(const kernel::LocalSafeRegion& lsr,
                                                              const Eigen::Vector2d& from,
                                                              const Eigen::Vector2d& to) const {
  if (auto path = PathInside(lsr, from, to)) return path;
  for (double radius : kGoalOffsets) {
    for (int k = 0; k < kGoalOffsetDirections; ++k) {
      const double angle = 2.0 * kernel::kPi * k / kGoalOffsetDirections;
      if (auto path = PathInside(lsr, from,
                                 to + radius * Eigen::Vector2d(std::cos(angle), std::sin(angle))))
        return path;
    }
  }
  return std::nullopt;
}

std::vector<kernel::FrontierArc> Session::UncoveredParts(
    const kernel::LocalSafeRegion& owner, const kernel::FrontierArc& arc,
    const std::vector<const kernel::LocalSafeRegion*>& others) const {
  const auto covered =
      kernel::ArcPartsInside(owner, arc, others, options_.arc_sampling_rad, Cover());
  // A frontier nothing covers stays as its node made it: FrontiersOf keeps an arc shorter than
  // min_frontier_m seen through a door (doorway_goals), and re-filtering dropped it at the
  // node's first overlap with any LSR, so that REG never went for such doors.
  if (covered.empty() && options_.doorway_goals) return {arc};
  return LongEnough(graph::Subtract(arc, covered, options_.arc_sampling_rad));
}

std::vector<kernel::FrontierArc> Session::LongEnough(
    const std::vector<kernel::FrontierArc>& arcs) const {
  std::vector<kernel::FrontierArc> kept;
  for (const kernel::FrontierArc& arc : arcs) {
    if (graph::ArcLength(arc, options_.lsr_radius_m) >= options_.min_frontier_m)
      kept.push_back(arc);
  }
  return kept;
}

}  // namespace splam::exploration::internal
