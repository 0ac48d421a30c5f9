#include "exploration/safe_paths.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <utility>

#include "kernel/angle.h"
#include "kernel/shapes.h"

namespace splam::exploration {
namespace {

// How much closer to the LSR boundary than where it stands a leg from the robot may come, m.
constexpr double kStartTolerance = 0.5 * LsrPlanner::kCellM;
// The polar grid of PathInside's waypoints around the LSR's centre.
constexpr double kWaypointRadii[] = {0.4, 0.8, 1.2, 1.6, 2.0};  // m
constexpr int kWaypointDirections = 36;
// Where PathNear looks for a clear goal around one that is not.
constexpr double kGoalOffsets[] = {0.15, 0.3, SafePaths::kMaxGoalOffsetM};  // m
constexpr int kGoalOffsetDirections = 12;

}  // namespace

bool SafePaths::LegIsClear(const kernel::LocalSafeRegion& lsr, const Eigen::Vector2d& a,
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

std::optional<std::vector<Eigen::Vector2d>> SafePaths::PathInside(
    const kernel::LocalSafeRegion& lsr, const Eigen::Vector2d& from,
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

std::optional<std::vector<Eigen::Vector2d>> SafePaths::PathNear(const kernel::LocalSafeRegion& lsr,
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

std::optional<std::vector<Eigen::Vector2d>> SafePaths::Approach(
    const kernel::LocalSafeRegion& lsr, const Eigen::Vector2d& from, const Eigen::Vector2d& target,
    const std::vector<Eigen::Vector2d>& avoid) const {
  if (!options_.grid_paths) return std::nullopt;
  for (const bool escape : {false, true}) {
    const LsrPlanner* planner = PlannerFor(lsr, from, escape);
    if (!planner) continue;
    const std::optional<Eigen::Vector2d> goal =
        planner->NearestReachable(target, kMinTravelM, avoid, kMinTravelM);
    if (!goal) continue;
    if (auto path = PathInside(lsr, from, *goal)) return path;
  }
  return std::nullopt;
}

std::optional<SafePaths::Move> SafePaths::DoorwayApproach(
    const FrontierRules& rules, const kernel::LocalSafeRegion& lsr, const Eigen::Vector2d& from,
    const kernel::FrontierArc& arc, const std::vector<Eigen::Vector2d>& avoid) const {
  constexpr double kStandOff = 0.3;  // m in front of the gap, beyond Needed()
  if (!options_.doorway_goals || !options_.grid_paths) return std::nullopt;
  const std::optional<FrontierRules::Gap> gap = rules.GapOf(lsr, arc);
  if (!gap || gap->Width() < 2.0 * Needed()) return std::nullopt;
  const Eigen::Vector2d along = (gap->left - gap->right) / gap->Width();
  const Eigen::Vector2d centre = 0.5 * (gap->left + gap->right);
  Eigen::Vector2d normal(-along.y(), along.x());
  if (normal.dot(lsr.center() - centre) < 0.0) normal = -normal;
  const Eigen::Vector2d goal = centre + (Needed() + kStandOff) * normal;
  if ((goal - from).norm() < kMinTravelM ||
      std::any_of(avoid.begin(), avoid.end(),
                  [&](const Eigen::Vector2d& a) { return (goal - a).norm() < kMinTravelM; }) ||
      !lsr.Contains(goal))
    return std::nullopt;
  std::optional<std::vector<Eigen::Vector2d>> path = PathInside(lsr, from, goal);
  if (!path) return std::nullopt;
  return Move{std::move(*path), centre};
}

bool SafePaths::CachedPlanner::Matches(const kernel::LocalSafeRegion& lsr,
                                       const Eigen::Vector2d& at) const {
  return built && lsr_center == lsr.center() && lsr_size == lsr.boundary().size() && from == at &&
         !lsr.boundary().empty() && lsr_first == lsr.boundary().front();
}

const LsrPlanner* SafePaths::PlannerFor(const kernel::LocalSafeRegion& lsr,
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

std::vector<Eigen::Vector2d> SafePaths::Escapes(const kernel::LocalSafeRegion& lsr,
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

std::optional<std::vector<Eigen::Vector2d>> SafePaths::GridPath(const kernel::LocalSafeRegion& lsr,
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

std::optional<std::vector<Eigen::Vector2d>> SafePaths::LegsAlong(const kernel::LocalSafeRegion& lsr,
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

}  // namespace splam::exploration
