#ifndef SPLAM_EXPLORATION_SAFE_PATHS_H_
#define SPLAM_EXPLORATION_SAFE_PATHS_H_

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "exploration/explorer.h"
#include "exploration/frontier_rules.h"
#include "exploration/lsr_planner.h"
#include "kernel/local_safe_region.h"

namespace splam::exploration {

// Paths for the robot's disc inside one LSR (the robot drives only where its sensors saw free
// space): straight legs checked exactly against the LSR boundary, bent paths found on a grid of
// the LSR (LsrPlanner, ExplorerOptions::grid_paths) and shortened to the fewest exact legs, and
// approaches to the reachable point nearest a target. The robot keeps needed_m (its radius plus
// the clearance margin) from the boundary. The grid planner of the last start is kept (a step
// asks for many goals from one start), so an object is used by one thread at a time.
class SafePaths {
 public:
  // An approach takes the robot at least this far from where it starts and from every node
  // given to avoid: a new node where it sees differently, m.
  static constexpr double kMinTravelM = 0.5;
  // PathNear tries goals up to this far from the one asked, m.
  static constexpr double kMaxGoalOffsetM = 0.45;

  SafePaths(const ExplorerOptions& options, double needed_m)
      : options_(options), needed_m_(needed_m) {}

  // The robot's radius plus the clearance margin: what a leg keeps from the LSR boundary, m.
  double Needed() const { return needed_m_; }
  // True when the disc of the robot, driven straight from a to b, keeps radius + margin from the
  // boundary of `lsr` (a must lie inside it). When the robot's disc is known free at a
  // (`from_robot`: it stands there, or a is a node's configuration) and is already closer, the leg
  // must not get closer and must be fully clear after its first radius + margin.
  bool LegIsClear(const kernel::LocalSafeRegion& lsr, const Eigen::Vector2d& a,
                  const Eigen::Vector2d& b, bool from_robot = true) const;
  // A path for the robot's disc from `from` (where it stands) to `to` inside `lsr`, as waypoints
  // after `from`: the straight leg when it is clear, else with options.grid_paths the grid
  // planner's path, else the shortest clear two-leg path through a waypoint of a polar grid
  // around the LSR's centre (radii 0.4-2 m, every 10 deg); nullopt when none exists.
  std::optional<std::vector<Eigen::Vector2d>> PathInside(const kernel::LocalSafeRegion& lsr,
                                                         const Eigen::Vector2d& from,
                                                         const Eigen::Vector2d& to) const;
  // PathInside to `to`, else to the first clear point 0.15, 0.3 or 0.45 m from it (every
  // 30 deg): a goal placed with an older estimate may lie too close to an obstacle now.
  std::optional<std::vector<Eigen::Vector2d>> PathNear(const kernel::LocalSafeRegion& lsr,
                                                       const Eigen::Vector2d& from,
                                                       const Eigen::Vector2d& to) const;
  // A path inside `lsr` from `from` to the reachable point nearest to `target` that lies at least
  // kMinTravelM from `from` and from every point of `avoid` (LsrPlanner::NearestReachable);
  // nullopt when there is none or options.grid_paths is off.
  std::optional<std::vector<Eigen::Vector2d>> Approach(
      const kernel::LocalSafeRegion& lsr, const Eigen::Vector2d& from,
      const Eigen::Vector2d& target, const std::vector<Eigen::Vector2d>& avoid) const;
  // A free arc seen through a gap (a door seen at a slant, FrontierRules::GapOf): the robot
  // stands on the gap's axis in front of it and faces through it (ExplorerOptions::
  // doorway_goals). The gap must be at least 2 Needed() wide. The goal lies Needed() + 0.3 m in
  // front of the gap's middle on the LSR's side, at least kMinTravelM from `from` and from every
  // point of `avoid`; `face` is the gap's middle. nullopt when there is no such gap or no path.
  struct Move {
    std::vector<Eigen::Vector2d> path;
    std::optional<Eigen::Vector2d> face;  // what the robot turns to at the end (Session::Drive)
  };
  std::optional<Move> DoorwayApproach(const FrontierRules& rules,
                                      const kernel::LocalSafeRegion& lsr,
                                      const Eigen::Vector2d& from, const kernel::FrontierArc& arc,
                                      const std::vector<Eigen::Vector2d>& avoid) const;
  // The grid planner for (lsr, from), from the start cell or (`escape`) from Escapes, built anew
  // unless it was the last one of its kind asked for; nullptr for `escape` when there are no
  // escapes.
  const LsrPlanner* PlannerFor(const kernel::LocalSafeRegion& lsr, const Eigen::Vector2d& from,
                               bool escape = false) const;

 private:
  // The grid planner's shortest path from `from` to `to` (LegsAlong), from the start cell, else
  // from the Escapes; nullopt when there is none.
  std::optional<std::vector<Eigen::Vector2d>> GridPath(const kernel::LocalSafeRegion& lsr,
                                                       const Eigen::Vector2d& from,
                                                       const Eigen::Vector2d& to) const;
  // `planner`'s cell path to `to`, shortened to the fewest legs that pass LegIsClear; nullopt
  // when there is none.
  std::optional<std::vector<Eigen::Vector2d>> LegsAlong(const kernel::LocalSafeRegion& lsr,
                                                        const Eigen::Vector2d& from,
                                                        const Eigen::Vector2d& to,
                                                        const LsrPlanner& planner) const;
  // The straight legs out of `from` when the robot stands closer to the boundary of `lsr` than
  // Needed(): in every direction (each 5 deg) the shortest leg, in steps of a grid cell, that
  // LegIsClear takes from the robot and that ends where the exact clearance exceeds Needed();
  // their ends. Empty when the robot stands clear or options.exact_escapes is off.
  std::vector<Eigen::Vector2d> Escapes(const kernel::LocalSafeRegion& lsr,
                                       const Eigen::Vector2d& from) const;

  // A planner and the region and start it was built for.
  struct CachedPlanner {
    std::optional<LsrPlanner> planner;
    Eigen::Vector2d lsr_center, lsr_first, from;
    std::size_t lsr_size = 0;
    bool built = false;
    bool Matches(const kernel::LocalSafeRegion& lsr, const Eigen::Vector2d& at) const;
  };

  ExplorerOptions options_;
  double needed_m_;
  mutable CachedPlanner planner_, escape_planner_;
};

}  // namespace splam::exploration

#endif  // SPLAM_EXPLORATION_SAFE_PATHS_H_
