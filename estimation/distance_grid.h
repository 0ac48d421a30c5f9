#ifndef SPLAM_ESTIMATION_DISTANCE_GRID_H_
#define SPLAM_ESTIMATION_DISTANCE_GRID_H_

#include <Eigen/Core>
#include <vector>

namespace splam::estimation {

// A truncated Euclidean distance field on a regular grid: value(r, c) is the distance from the
// centre of cell (r, c) to the nearest of a set of points (the samples of a submap's curves),
// capped at `truncation_m`. Cell (r, c) has its centre at origin + ((c + 0.5) res, (r + 0.5) res).
//
// The distance is exact to the stored point of the nearest occupied cell (found by a
// distance transform), not to the cell's centre: a wall 1 cm inside a 5 cm cell reads 1 cm off
// its centre, so the field keeps the sub-cell position of the curves.
class DistanceGrid {
 public:
  DistanceGrid() = default;
  // The field of `points` (any frame) over their bounding box widened by `margin_m`.
  // Preconditions: resolution_m > 0, truncation_m > 0, finite points.
  static DistanceGrid Build(const std::vector<Eigen::Vector2d>& points, double resolution_m,
                            double truncation_m, double margin_m);

  bool empty() const { return values_.empty(); }
  int rows() const { return rows_; }
  int cols() const { return cols_; }
  double resolution() const { return resolution_m_; }
  double truncation() const { return truncation_m_; }
  const Eigen::Vector2d& origin() const { return origin_; }
  // Row-major values, rows() * cols().
  const std::vector<double>& values() const { return values_; }
  double At(int row, int col) const { return values_[static_cast<std::size_t>(row) * cols_ + col]; }
  // The value of the cell holding p; the truncation outside the grid.
  double Nearest(const Eigen::Vector2d& p) const;
  // Fractional (row, col) of a point, in the convention of ceres::Grid2D (cell centres at
  // integers).
  Eigen::Vector2d CellCoordinates(const Eigen::Vector2d& p) const {
    return {(p.y() - origin_.y()) / resolution_m_ - 0.5,
            (p.x() - origin_.x()) / resolution_m_ - 0.5};
  }

 private:
  int rows_ = 0, cols_ = 0;
  double resolution_m_ = 0.05, truncation_m_ = 1.0;
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  std::vector<double> values_;
};

// Score grids for the correlative search (Olson 2009): level 0 holds the likelihood
// exp(-d^2 / (2 sigma^2)) of every cell of a distance grid; level k holds, for each cell, the
// maximum of level 0 over the 2^k x 2^k block of cells starting there, so that a translation
// on a coarse 2^k grid bounds the score of every finer translation inside its block.
class LikelihoodPyramid {
 public:
  LikelihoodPyramid(const DistanceGrid& grid, double sigma_m, int levels);
  int levels() const { return static_cast<int>(levels_.size()); }
  const DistanceGrid& grid() const { return *grid_; }
  // Likelihood (level 0) or block maximum at integer cell (row, col); 0 outside.
  double At(int level, int row, int col) const {
    if (row < 0 || col < 0 || row >= grid_->rows() || col >= grid_->cols()) return 0.0;
    return levels_[level][static_cast<std::size_t>(row) * grid_->cols() + col];
  }

 private:
  const DistanceGrid* grid_;
  std::vector<std::vector<float>> levels_;
};

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_DISTANCE_GRID_H_
