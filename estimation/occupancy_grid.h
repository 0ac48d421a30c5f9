#ifndef SPLAM_ESTIMATION_OCCUPANCY_GRID_H_
#define SPLAM_ESTIMATION_OCCUPANCY_GRID_H_

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "estimation/evaluation/map_consistency.h"
#include "kernel/options.h"
#include "kernel/status.h"

// A probabilistic occupancy grid built from placed scans (the final poses of any method and the
// log's scans): the map navigation stacks (ROS's map_server, nav2) and localisers take, and the
// common picture by which laser SLAM maps are compared.
//
// Each cell holds the log-odds l = log(p / (1 - p)) of being occupied, 0 (p = 1/2) before any
// beam reaches it. A beam from the laser at s to its end e adds l_miss = logit(miss_probability)
// to every cell it crosses before e's cell and l_hit = logit(hit_probability) to e's cell when it
// is a return (the inverse sensor model of Thrun, Burgard and Fox, ch. 9, with a constant
// probability per cell). A cell is updated at most once per scan, a hit before a miss (as
// Cartographer's probability grids do): without that, the many beams that cross a cell next to
// the laser would count as many observations. Log-odds are clamped to the logits of
// [min_probability, max_probability], so that a cell can change when the world does.
namespace splam::estimation {

struct OccupancyGridOptions {
  double resolution_m = 0.05;     // side of a cell, m
  double hit_probability = 0.7;   // P(occupied) that a return in the cell implies
  double miss_probability = 0.4;  // P(occupied) that a beam through the cell implies
  double min_probability = 0.12;  // clamp of a cell's probability from below
  double max_probability = 0.97;  // clamp from above
  // Beams are traced up to this range; a return beyond it frees the cells up to it (the far
  // returns' angular error, range x beam width, spans cells), m.
  double max_range_m = 30.0;
  // A beam without return frees the cells up to this range (0: it is not used: glass, black
  // surfaces and sensor dropouts read as no return too), m.
  double no_return_free_m = 0.0;
  // Thresholds of the map_server format (map.yaml): a cell with p above occupied_threshold is
  // occupied, below free_threshold free, else unknown (ROS map_server's defaults).
  double occupied_threshold = 0.65;
  double free_threshold = 0.196;
  // The grid is refused beyond this many cells (a diverged trajectory 1e6 m away would ask for
  // terabytes).
  std::uint64_t max_cells = 200000000;

  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

enum class CellState : std::uint8_t { kUnknown, kFree, kOccupied };

class OccupancyGrid {
 public:
  // A grid of width x height cells of side resolution_m whose cell (0, 0) has its lower-left
  // corner at `origin` (world frame, m); x grows with the column, y with the row. Every cell
  // unknown (log-odds 0, never observed).
  OccupancyGrid(const Eigen::Vector2d& origin, double resolution_m, int width, int height);

  int width() const { return width_; }
  int height() const { return height_; }
  double resolution_m() const { return resolution_m_; }
  const Eigen::Vector2d& origin() const { return origin_; }

  bool Contains(int x, int y) const { return x >= 0 && y >= 0 && x < width_ && y < height_; }
  // The cell holding world point p, if the grid does.
  std::optional<Eigen::Vector2i> CellOf(const Eigen::Vector2d& p) const;
  Eigen::Vector2d CenterOf(int x, int y) const;

  float log_odds(int x, int y) const { return log_odds_[Index(x, y)]; }
  bool observed(int x, int y) const { return observed_[Index(x, y)] != 0; }
  double Probability(int x, int y) const;
  // Occupied above `occupied`, free below `free`, unknown between them or when never observed.
  CellState State(int x, int y, double occupied, double free) const;

  // Sets a cell's log-odds and marks it observed (readers of saved grids, tests).
  void Set(int x, int y, float log_odds);
  // Adds `delta` to the cell's log-odds, clamped to [lo, hi], and marks it observed.
  void Add(int x, int y, float delta, float lo, float hi);

 private:
  std::size_t Index(int x, int y) const {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) +
           static_cast<std::size_t>(x);
  }
  Eigen::Vector2d origin_;
  double resolution_m_;
  int width_, height_;
  std::vector<float> log_odds_;
  std::vector<std::uint8_t> observed_;
};

// The grid of `scans` (each placed by its robot pose and the laser's mounting), bounded by what
// they observe plus a margin of two cells. Fails when the options are invalid or the grid would
// exceed max_cells.
kernel::Result<OccupancyGrid> BuildOccupancyGrid(const std::vector<evaluation::PlacedScan>& scans,
                                                 const OccupancyGridOptions& options = {});

// The cells a segment from a to b crosses, in order from a's cell to b's (Amanatides and Woo's
// traversal: every cell the segment passes through, none it only grazes at a corner twice), in
// cell coordinates of `grid` (possibly outside it).
std::vector<Eigen::Vector2i> CellsOnSegment(const OccupancyGrid& grid, const Eigen::Vector2d& a,
                                            const Eigen::Vector2d& b);

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_OCCUPANCY_GRID_H_
