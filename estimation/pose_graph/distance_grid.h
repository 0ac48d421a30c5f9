#ifndef SPLAM_ESTIMATION_POSE_GRAPH_DISTANCE_GRID_H_
#define SPLAM_ESTIMATION_POSE_GRAPH_DISTANCE_GRID_H_

#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace splam::estimation {

// A point of an outline and the unit normal of its free side (towards the sensor that saw it);
// zero when unknown.
struct OrientedPoint {
  Eigen::Vector2d point = Eigen::Vector2d::Zero();
  Eigen::Vector2d normal = Eigen::Vector2d::Zero();
};

// Whether p[i] and p[i + 1] of an ordered run (a scan's hits in beam order) lie on one outline:
// at most max_gap_m apart, or, when line_tolerance_m > 0, on one straight line with a third
// neighbour (p[i - 1] or p[i + 2]): the middle point of the three lies between the other two
// and within line_tolerance_m of their chord, and the two spacings differ by at most 3 times. The
// second case is a wall seen at grazing incidence, where a laser's points lie metres apart (1 deg
// beams 20 m along a wall 1.25 m away fall 5.6 m apart); a depth jump from an object to a wall
// behind it has no such third point. The result has one entry per point (the last is false).
std::vector<bool> LinkedToNext(const std::vector<Eigen::Vector2d>& points, double max_gap_m,
                               double line_tolerance_m);

// An ordered run of points (a curve's samples, a scan's hits) with the normals of their free
// side: the normal of the line fitted (total least squares) to the run's points within
// max_gap_m of p[i] (and its immediate neighbours linked to it by LinkedToNext), turned towards
// the sensor at `sensor`; the direction to the sensor for isolated points. A fit over a
// neighbourhood, not p[i+1] - p[i-1]: on a dense noisy laser (a URG's 2 cm noise at 2.5 cm
// spacing) the difference of two neighbours points anywhere, and a cell's outline piece along a
// wrong tangent reads zero far off the wall.
std::vector<OrientedPoint> OrientTowards(const std::vector<Eigen::Vector2d>& points,
                                         const Eigen::Vector2d& sensor, double max_gap_m,
                                         double line_tolerance_m = 0.0);

// Points every spacing_m along the chords between consecutive `oriented` points that are
// linked (LinkedToNext) but farther apart than max_gap_m (a line through them), with the chord's
// normal turned to the side of the points' normals: the outline between a grazing wall's sparse
// points, so that a field rasterised from them reads zero all along the wall instead of having a
// valley at each point (which holds a scan registered against it at the pose that sampled those
// points).
std::vector<OrientedPoint> FillLinkedGaps(const std::vector<OrientedPoint>& oriented,
                                          double max_gap_m, double line_tolerance_m,
                                          double spacing_m);

// A view (DistanceGrid::Build's `seen`: a polygon from the sensor, its first vertex, through
// every beam's end) rasterised on the plane's lattice of resolution_m cells, lattice cell (i, j)
// covering [j, j + 1) x [i, i + 1) times resolution_m: the runs of cells it fills along each row,
// whole and pulled back by seen_margin_m towards the sensor. Every DistanceGrid lies on the
// lattice of its resolution, so a grid fills its masks from these runs without rasterising the
// polygons again: the graph SLAM keeps a keyframe's until the keyframe moves. The polygon is
// clipped to a square of 4096 cells about the sensor (the largest grid is 2^24 cells).
struct ViewCells {
  struct Run {
    int row = 0, first = 0, last = 0;  // lattice row, first and last column (inclusive)
  };
  double resolution_m = 0.0;
  std::vector<Run> whole, inner;
};
ViewCells RasteriseView(const std::vector<Eigen::Vector2d>& polygon, double resolution_m,
                        double seen_margin_m);

// A truncated Euclidean distance field on a regular grid: value(r, c) is the distance from the
// centre of cell (r, c) to the nearest of a set of points (the samples of a submap's curves),
// capped at `truncation_m`. Cell (r, c) has its centre at origin + ((c + 0.5) res, (r + 0.5) res),
// and the origin is a multiple of the resolution (a lattice cell, see ViewCells).
//
// The distance is exact to the stored point of the nearest occupied cell (found by a
// distance transform), not to the cell's centre: a wall 1 cm inside a 5 cm cell reads 1 cm off
// its centre, so the field keeps the sub-cell position of the curves.
class DistanceGrid {
 public:
  DistanceGrid() = default;
  // The field of `points` (any frame) over their bounding box widened by `margin_m`.
  // Preconditions: resolution_m > 0, truncation_m > 0, finite points.
  //
  // `seen` are the regions the points' scans saw (polygons from the sensor through every beam's
  // end, same frame): cells inside one of them, widened by seen_margin_m, are known, the others
  // were never seen. A wall seen to its end by range only continues in the unseen part, so the
  // points a registration finds there must not be pulled back to where the known part ends.
  // Empty `seen`: every cell is known.
  static DistanceGrid Build(const std::vector<Eigen::Vector2d>& points, double resolution_m,
                            double truncation_m, double margin_m,
                            const std::vector<std::vector<Eigen::Vector2d>>& seen = {});
  // Oriented points stand for pieces of outline: each occupied cell keeps a short segment through
  // its point, perpendicular to its normal (1.5 cells either side), and the field holds the
  // distance to the nearest cell's segment. One point per cell would read up to half a cell off
  // on the outline itself (a bumpy valley that biases a registration); the segments read zero
  // all along it.
  // `signed_field`: negative behind the outline (against the normal), so that the
  // field is linear across it, which bicubic interpolation reproduces exactly; it needs normals
  // that are right (smooth outlines), and a wrong sign on clutter makes false zero crossings.
  // `seen_margin_m`: how far the `seen` polygons reach behind their hits (their vertices after
  // the first, the sensor); the cells inside the polygons pulled back by it towards the sensor
  // were seen free (SeenFree). `seen_by_hits`: the same views of the beams that returned
  // (ScanView without no-returns), whose cells pulled back alike were crossed by a beam that
  // returned from farther (SeenFreeByHits).
  static DistanceGrid Build(const std::vector<OrientedPoint>& points, double resolution_m,
                            double truncation_m, double margin_m,
                            const std::vector<std::vector<Eigen::Vector2d>>& seen = {},
                            bool signed_field = false, double seen_margin_m = 0.0,
                            const std::vector<std::vector<Eigen::Vector2d>>& seen_by_hits = {});
  // The same with the views already rasterised (RasteriseView at resolution_m and seen_margin_m):
  // `seen` fills the known cells (whole) and those seen free (inner), `seen_by_hits` (inner)
  // those seen free by a beam that returned. Empty `seen`: every cell is known.
  static DistanceGrid Build(const std::vector<OrientedPoint>& points, double resolution_m,
                            double truncation_m, double margin_m,
                            const std::vector<const ViewCells*>& seen, bool signed_field,
                            const std::vector<const ViewCells*>& seen_by_hits);

  // Adds a keyframe's outline and view to the field in place (the graph SLAM's submap between two
  // builds): every point joins its cell's sums, so that each piece is the mean of all the points
  // in its cell as Build makes it (a cell without one gets a new piece). As in Build, a cell's
  // piece is that of the occupied cell whose centre is nearest to its own (here by Euclidean
  // distance, there by a chamfer distance transform within 2 % of it): a new piece takes the
  // cells within Reach() whose piece lies farther, and the cells of a moved piece follow it (one
  // that moved no distance within its reach by a hundredth of a cell keeps its cells' values:
  // Distance is exact to it all the same). The views raise the cells' knowledge as Build's
  // `seen` (`seen_by_hits` is not updated).
  // Returns false, having changed nothing, when a point lies nearer than the truncation to the
  // grid's edge, or beyond it (Build would have made the grid larger): build again.
  bool Insert(const std::vector<OrientedPoint>& points, const std::vector<const ViewCells*>& seen);
  // How many cells from its own a piece can bring a cell's centre within the truncation:
  // ceil(truncation / resolution + sqrt(1/2) + kSegmentHalfLength).
  int Reach() const;

  // A grid holds at most this many cells (about 1 GB while it is built): points spanning more,
  // at the resolution asked, give an empty grid whose too_large() is true and whose extent()
  // says how far they spread (an odometry jump of kilometres, a resolution of a micrometre).
  static constexpr double kMaxCells = 1 << 24;
  bool too_large() const { return extent_.x() > 0; }
  const Eigen::Vector2d& extent() const { return extent_; }

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
  // Whether the cell holding p was seen (false outside the grid).
  bool Known(const Eigen::Vector2d& p) const;
  // Whether a beam crossed the cell holding p, or an outline lies in it: known, and not only as
  // the margin behind a hit (true everywhere without `seen`, false outside the grid).
  bool SeenFree(const Eigen::Vector2d& p) const;
  // Whether a beam that returned from farther crossed the cell holding p (Build's
  // `seen_by_hits`; false without them).
  bool SeenFreeByHits(const Eigen::Vector2d& p) const;
  // The exact distance from p to the outline piece of the occupied cell nearest to p's cell
  // (the piece the field's value at that cell measures to), signed by the side of the piece's
  // normal (its sign only orients the gradient: |Distance| is the distance), and its gradient
  // d Distance / dp when `gradient` is not null. Unlike an interpolation of the cell values it
  // has no bias within a cell: the valley of the field lies on the outline wherever the outline
  // crosses the cell, so a registration does not shift with the grid's origin. Returns the
  // truncation (gradient zero) beyond it and outside the grid.
  double Distance(const Eigen::Vector2d& p, Eigen::Vector2d* gradient = nullptr) const;
  // The outline piece Distance(p) measures to; null where there is none within the truncation.
  const OrientedPoint* NearestPiece(const Eigen::Vector2d& p) const;
  // Where the cell of that piece holds an outline seen from both sides (a thin wall, a door's
  // leaf: some of its points' normals, which point towards the sensors that saw them, turned more
  // than 90 deg from the others), the normal of the side the piece's does not show (unit);
  // zero for a one-sided piece and where there is none.
  Eigen::Vector2d BackNormal(const Eigen::Vector2d& p) const;
  // Half the length of an outline piece, m.
  double PieceHalfLength() const;
  // Fractional (row, col) of a point, in the convention of ceres::Grid2D (cell centres at
  // integers).
  Eigen::Vector2d CellCoordinates(const Eigen::Vector2d& p) const {
    return {(p.y() - origin_.y()) / resolution_m_ - 0.5,
            (p.x() - origin_.x()) / resolution_m_ - 0.5};
  }

 private:
  friend class LikelihoodPyramid;
  // Row-major index of the cell holding p; -1 outside the grid.
  long CellIndex(const Eigen::Vector2d& p) const;
  // Raises known_ to at least `value` on the runs' cells inside the grid.
  void RaiseKnown(const std::vector<ViewCells::Run>& runs, unsigned char value);

  int rows_ = 0, cols_ = 0;
  Eigen::Vector2d extent_ = Eigen::Vector2d::Zero();  // of a grid too large to build, m
  double resolution_m_ = 0.05, truncation_m_ = 1.0;
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  long first_row_ = 0, first_col_ = 0;  // the lattice cell of cell (0, 0)
  std::vector<double> values_;
  // 0 unseen, 1 behind a hit, 2 seen free, 3 seen free by a beam that returned; empty: all 2.
  std::vector<unsigned char> known_;
  bool signed_ = false;        // Build's signed_field
  std::vector<int> nearest_;   // per cell: index into pieces_ of its nearest piece
  std::vector<int> piece_of_;  // per cell: index into pieces_ of its own, or -1
  // The sums of an occupied cell's points, from which its piece is made.
  struct CellSums {
    std::size_t cell = 0;
    Eigen::Vector2d sum = Eigen::Vector2d::Zero(), normal = Eigen::Vector2d::Zero();
    // The normals turned more than 90 deg from the cell's first normal (`reference`), summed: an
    // outline seen from both sides (normals point towards the sensor that saw the point).
    Eigen::Vector2d reference = Eigen::Vector2d::Zero(), opposed = Eigen::Vector2d::Zero();
    int count = 0;
    void Add(const Eigen::Vector2d& p, const Eigen::Vector2d& n);
    // The piece: the mean of the points, the normalised sum of their normals.
    OrientedPoint Piece() const;
    // BackNormal of the piece: the normal of the side the summed normal does not point to, zero
    // for a one-sided piece.
    Eigen::Vector2d Back() const;
  };
  std::vector<CellSums> sums_;                 // per piece (Insert adds to them)
  std::vector<OrientedPoint> pieces_;          // the occupied cells' outline pieces
  std::vector<Eigen::Vector2d> back_normals_;  // per piece: BackNormal, or zero
};

// Score grids for the correlative search (Olson 2009): level 0 holds the likelihood
// exp(-d^2 / (2 sigma^2)) of every cell of a distance grid; level k holds, for each cell, the
// maximum of level 0 over the 2^k x 2^k block of cells starting there, so that a translation
// on a coarse 2^k grid bounds the score of every finer translation inside its block.
class LikelihoodPyramid {
 public:
  // `seen_free_score` (<= 0) replaces the likelihood of cells that a beam which returned from
  // farther crossed (SeenFreeByHits) at `free_distance_m` or more from the outline: a point there
  // is evidence against the pose, which a likelihood of zero does not tell from a point where the
  // grid never looked.
  LikelihoodPyramid(const DistanceGrid& grid, double sigma_m, int levels,
                    double seen_free_score = 0.0, double free_distance_m = 0.0);
  int levels() const { return static_cast<int>(levels_.size()); }
  const DistanceGrid& grid() const { return *grid_; }
  // Likelihood (level 0) or the maximum over the block of 2^level x 2^level cells from integer
  // cell (row, col); 0 where that holds no cell of the grid. A block that starts before the grid
  // and reaches into it is bounded by the block at the grid's edge, which holds its part inside:
  // taking 0 there let the branch and bound prune a block holding the best pose, on queries
  // searched in windows wider than the target (a 12 m loop search found a pose scoring 0.79
  // where one scoring 0.95 lay in its window).
  double At(int level, int row, int col) const {
    const int block = 1 << level;
    if (row < 0 && row + block > 0) row = 0;
    if (col < 0 && col + block > 0) col = 0;
    if (row < 0 || col < 0 || row >= grid_->rows() || col >= grid_->cols()) return 0.0;
    return levels_[level][static_cast<std::size_t>(row) * grid_->cols() + col];
  }

 private:
  const DistanceGrid* grid_;
  std::vector<std::vector<float>> levels_;
};

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_POSE_GRAPH_DISTANCE_GRID_H_
