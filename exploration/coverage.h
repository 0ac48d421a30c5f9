#ifndef SPLAM_EXPLORATION_COVERAGE_H_
#define SPLAM_EXPLORATION_COVERAGE_H_

#include <Eigen/Core>
#include <functional>
#include <vector>

#include "kernel/local_safe_region.h"
#include "kernel/shapes.h"

namespace splam::exploration {

// How much of the reachable free space the LSRs of an exploration have covered, on a grid of
// square cells. The reachable free space is the set of free cells connected to the start cell
// through edge-adjacent free cells; a cell is free when `is_free` accepts its centre (the caller
// should demand a clearance of half a cell diagonal, so that no wall passes through a free cell
// and the flood cannot leak through thin walls). It includes free space the robot's body cannot
// enter (gaps narrower than the robot), which an exploration can only see.
class CoverageGrid {
 public:
  CoverageGrid(const kernel::Box2& bounds, double cell_m, const Eigen::Vector2d& start,
               const std::function<bool(const Eigen::Vector2d&)>& is_free);

  // Marks the cells the region's rasterisation touches (OpenCV fillPoly: the cells whose centre
  // is inside plus those its boundary crosses, a band of at most one cell).
  void Cover(const kernel::LocalSafeRegion& region);
  int reachable_cells() const { return reachable_; }
  // True when the reachable free space touches the grid's outer cells: nothing encloses the
  // start within the bounds (a start outside the walls, or a world with an opening).
  bool reaches_border() const { return reaches_border_; }
  // Covered reachable cells over reachable cells (0 when nothing is reachable).
  double CoveredFraction() const;
  double cell_m() const { return cell_; }

 private:
  Eigen::Vector2d origin_;  // corner of cell (0, 0)
  double cell_;
  int nx_, ny_;
  std::vector<char> reachable_mask_;  // row-major, y first
  std::vector<char> covered_;
  int reachable_ = 0;
  int covered_reachable_ = 0;
  bool reaches_border_ = false;
};

}  // namespace splam::exploration

#endif  // SPLAM_EXPLORATION_COVERAGE_H_
