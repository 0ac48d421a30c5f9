#ifndef SPLAM_EXPLORATION_LSR_PLANNER_H_
#define SPLAM_EXPLORATION_LSR_PLANNER_H_

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <vector>

#include "kernel/local_safe_region.h"

namespace splam::exploration {

// Shortest paths for the robot's disc inside one LSR, from where the robot stands (SafePaths::
// PathInside when no straight leg is clear). The LSR is rasterised at cell_m; a cell's clearance
// is its distance to the nearest cell outside the region; the search (Dijkstra, 8-connected) keeps
// to cells whose clearance exceeds `needed` (the robot's radius plus margin), and within `needed`
// of the start, where the robot may stand closer to the boundary than that, to cells no closer
// than the start's. Doors narrow for the robot, seen at a slant, and rooms behind a corner are
// reached through as many bends as they need; the two-leg paths of a polar grid of waypoints
// missed doors off the grid's 10 deg rays (docs/experiments.md, Fig. 18). The raster only finds the
// way: SafePaths::PathInside checks every leg of the result with the exact clearance test.
//
// The raster's clearances are a cell off the exact ones, and from a start closer to the boundary
// than `needed` the cells it leaves by may bring the robot a few millimetres closer than it stands
// (REG in `office`, seed 7: every path out of a node beside the sonar's boundary was refused by the
// exact test). Given `escapes`, points that straight legs from the start reach and that the exact
// test already passed (SafePaths::Escapes), the search begins at them instead, each at the cost of
// its leg, and keeps to cells whose clearance exceeds `needed` everywhere.
class LsrPlanner {
 public:
  static constexpr double kCellM = 0.05;

  LsrPlanner(const kernel::LocalSafeRegion& lsr, const Eigen::Vector2d& from, double needed,
             const std::vector<Eigen::Vector2d>& escapes = {});

  // The centres of the cells along the shortest path from the start to the cell of `to`, the
  // start's cell first (with escapes: `from`, then the escape point, then the cells); nullopt
  // when `to` is not reachable.
  std::optional<std::vector<Eigen::Vector2d>> CellPath(const Eigen::Vector2d& to) const;

  // The centre of the reachable cell nearest to `target` among those at least min_travel_m from
  // the start and min_spacing_m from every point of `avoid`; nullopt when there is none.
  std::optional<Eigen::Vector2d> NearestReachable(const Eigen::Vector2d& target,
                                                  double min_travel_m,
                                                  const std::vector<Eigen::Vector2d>& avoid,
                                                  double min_spacing_m) const;
  // The same among the cells of every `stride`-th row and column that `accept` takes, tried
  // nearest first (for a test too costly to run on every cell).
  std::optional<Eigen::Vector2d> NearestReachable(
      const Eigen::Vector2d& target, double min_travel_m, const std::vector<Eigen::Vector2d>& avoid,
      double min_spacing_m, int stride,
      const std::function<bool(const Eigen::Vector2d&)>& accept) const;

 private:
  // Cell index of p, -1 outside the grid.
  int Index(const Eigen::Vector2d& p) const;
  Eigen::Vector2d Centre(int index) const;
  // Whether cell i is reached, min_travel_m from the start and min_spacing_m from every point of
  // `avoid`.
  bool Eligible(int i, double min_travel_m, const std::vector<Eigen::Vector2d>& avoid,
                double min_spacing_m) const;

  Eigen::Vector2d from_;
  Eigen::Vector2d origin_;  // the grid's lower-left corner
  int cols_ = 0, rows_ = 0;
  std::vector<int> parent_;  // -1: not reached; the start is its own parent
  // With escapes, the cells the search began at and the escape point in each.
  std::vector<std::pair<int, Eigen::Vector2d>> escape_cells_;
};

}  // namespace splam::exploration

#endif  // SPLAM_EXPLORATION_LSR_PLANNER_H_
