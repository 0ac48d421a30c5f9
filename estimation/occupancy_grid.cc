#include "estimation/occupancy_grid.h"

#include <fmt/core.h>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace splam::estimation {
namespace {

double Logit(double p) { return std::log(p / (1.0 - p)); }

// Calls visit(x, y) for every cell the segment a-b crosses, from a's cell to b's, in cell
// coordinates of `grid`. Exactly |dx| + |dy| steps, each to a side neighbour: the axis whose
// next cell boundary the segment meets first (t_max), and the other once one axis has arrived,
// so the walk ends in b's cell whatever the rounding.
template <class Visit>
void TraverseCells(const OccupancyGrid& grid, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                   Visit visit) {
  const Eigen::Vector2d u = (a - grid.origin()) / grid.resolution_m();
  const Eigen::Vector2d v = (b - grid.origin()) / grid.resolution_m();
  int x = static_cast<int>(std::floor(u.x())), y = static_cast<int>(std::floor(u.y()));
  const int end_x = static_cast<int>(std::floor(v.x())),
            end_y = static_cast<int>(std::floor(v.y()));
  const Eigen::Vector2d d = v - u;
  const int step_x = d.x() > 0 ? 1 : -1, step_y = d.y() > 0 ? 1 : -1;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // Parameter t in [0, 1] along the segment at which it meets the next column / row boundary,
  // and the parameter span of one cell.
  double t_max_x = d.x() == 0 ? kInf : ((d.x() > 0 ? x + 1 : x) - u.x()) / d.x();
  double t_max_y = d.y() == 0 ? kInf : ((d.y() > 0 ? y + 1 : y) - u.y()) / d.y();
  const double t_delta_x = d.x() == 0 ? kInf : 1.0 / std::abs(d.x());
  const double t_delta_y = d.y() == 0 ? kInf : 1.0 / std::abs(d.y());
  visit(x, y);
  for (int n = std::abs(end_x - x) + std::abs(end_y - y); n > 0; --n) {
    if (y == end_y || (x != end_x && t_max_x < t_max_y)) {
      x += step_x;
      t_max_x += t_delta_x;
    } else {
      y += step_y;
      t_max_y += t_delta_y;
    }
    visit(x, y);
  }
}

// A beam to trace: from the laser to `end`, a return at `end` when `hit`.
struct Beam {
  Eigen::Vector2d end;
  bool hit;
};

// The beams of one placed scan that OccupancyGridOptions says to trace, and the laser's position.
Eigen::Vector2d BeamsOf(const evaluation::PlacedScan& placed, const OccupancyGridOptions& options,
                        std::vector<Beam>* beams) {
  beams->clear();
  const kernel::Pose2 laser = placed.pose * placed.robot_T_laser;
  const kernel::Scan& scan = *placed.scan;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    double range = 0.0;
    bool hit = false;
    if (scan.IsHit(i)) {
      hit = scan.ranges_m[i] <= options.max_range_m;
      range = std::min(scan.ranges_m[i], options.max_range_m);
    } else if (scan.IsNoReturn(i) && options.no_return_free_m > 0) {
      range = std::min(options.no_return_free_m, options.max_range_m);
    } else {
      continue;
    }
    const double angle = scan.BeamAngle(i);
    if (!std::isfinite(angle)) continue;  // the readers refuse such scans; a caller may not
    beams->push_back(
        {laser * Eigen::Vector2d(range * std::cos(angle), range * std::sin(angle)), hit});
  }
  return laser.translation();
}

bool Finite(const kernel::Pose2& p) {
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.theta());
}

}  // namespace

void OccupancyGridOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Field("resolution_m", &resolution_m, "side of a cell, m");
  v.Field("hit_probability", &hit_probability, "P(occupied) a return in the cell implies");
  v.Field("miss_probability", &miss_probability, "P(occupied) a beam through the cell implies");
  v.Field("min_probability", &min_probability, "clamp of a cell's probability from below");
  v.Field("max_probability", &max_probability, "clamp of a cell's probability from above");
  v.Field("max_range_m", &max_range_m,
          "beams are traced up to this range; a return beyond frees the cells up to it, m");
  v.Field("no_return_free_m", &no_return_free_m,
          "a beam without return frees the cells up to this range (0: not used), m");
  v.Field("occupied_threshold", &occupied_threshold, "map.yaml: occupied above this probability");
  v.Field("free_threshold", &free_threshold, "map.yaml: free below this probability");
  v.Field("max_cells", &max_cells, "the grid is refused beyond this many cells");
}

kernel::Status OccupancyGridOptions::Validate() const {
  if (!(resolution_m > 0)) return kernel::Status::Error("resolution_m must be positive");
  if (!(0 < min_probability && min_probability < miss_probability && miss_probability < 0.5 &&
        0.5 < hit_probability && hit_probability < max_probability && max_probability < 1))
    return kernel::Status::Error(
        "need 0 < min_probability < miss_probability < 0.5 < hit_probability < "
        "max_probability < 1");
  if (!(max_range_m > 0) || !(no_return_free_m >= 0))
    return kernel::Status::Error("max_range_m must be positive and no_return_free_m >= 0");
  if (!(0 < free_threshold && free_threshold < occupied_threshold && occupied_threshold < 1))
    return kernel::Status::Error("need 0 < free_threshold < occupied_threshold < 1");
  if (max_cells < 1) return kernel::Status::Error("max_cells must be >= 1");
  return kernel::Status::Ok();
}

OccupancyGrid::OccupancyGrid(const Eigen::Vector2d& origin, double resolution_m, int width,
                             int height)
    : origin_(origin),
      resolution_m_(resolution_m),
      width_(width),
      height_(height),
      log_odds_(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), 0.0f),
      observed_(log_odds_.size(), 0) {}

std::optional<Eigen::Vector2i> OccupancyGrid::CellOf(const Eigen::Vector2d& p) const {
  const Eigen::Vector2d u = (p - origin_) / resolution_m_;
  if (!(u.x() >= 0 && u.y() >= 0 && u.x() < width_ && u.y() < height_)) return std::nullopt;
  return Eigen::Vector2i(static_cast<int>(u.x()), static_cast<int>(u.y()));
}

Eigen::Vector2d OccupancyGrid::CenterOf(int x, int y) const {
  return origin_ + resolution_m_ * Eigen::Vector2d(x + 0.5, y + 0.5);
}

double OccupancyGrid::Probability(int x, int y) const {
  return 1.0 / (1.0 + std::exp(-static_cast<double>(log_odds(x, y))));
}

CellState OccupancyGrid::State(int x, int y, double occupied, double free) const {
  if (!observed(x, y)) return CellState::kUnknown;
  const double p = Probability(x, y);
  if (p > occupied) return CellState::kOccupied;
  if (p < free) return CellState::kFree;
  return CellState::kUnknown;
}

void OccupancyGrid::Set(int x, int y, float log_odds) {
  log_odds_[Index(x, y)] = log_odds;
  observed_[Index(x, y)] = 1;
}

void OccupancyGrid::Add(int x, int y, float delta, float lo, float hi) {
  float& l = log_odds_[Index(x, y)];
  l = std::clamp(l + delta, lo, hi);
  observed_[Index(x, y)] = 1;
}

std::vector<Eigen::Vector2i> CellsOnSegment(const OccupancyGrid& grid, const Eigen::Vector2d& a,
                                            const Eigen::Vector2d& b) {
  std::vector<Eigen::Vector2i> cells;
  TraverseCells(grid, a, b, [&cells](int x, int y) { cells.emplace_back(x, y); });
  return cells;
}

kernel::Result<OccupancyGrid> BuildOccupancyGrid(const std::vector<evaluation::PlacedScan>& scans,
                                                 const OccupancyGridOptions& options) {
  using R = kernel::Result<OccupancyGrid>;
  if (const kernel::Status problem = options.Validate(); !problem.ok())
    return R::Fail("occupancy grid: " + problem.message());
  // The bounds of every laser position and beam end.
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  std::vector<Beam> beams;
  for (const evaluation::PlacedScan& s : scans) {
    if (!Finite(s.pose) || !Finite(s.pose * s.robot_T_laser)) continue;
    const Eigen::Vector2d laser = BeamsOf(s, options, &beams);
    lo = lo.cwiseMin(laser);
    hi = hi.cwiseMax(laser);
    for (const Beam& b : beams) {
      lo = lo.cwiseMin(b.end);
      hi = hi.cwiseMax(b.end);
    }
  }
  if (!(lo.x() <= hi.x())) return R::Fail("occupancy grid: no scan with a finite pose");
  // Beyond this, doubles no longer tell cells apart (at 1e300 m the whole map is one cell).
  if (!(lo.cwiseAbs().maxCoeff() <= kernel::kMaxCoordinateM &&
        hi.cwiseAbs().maxCoeff() <= kernel::kMaxCoordinateM))
    return R::Fail(
        fmt::format("occupancy grid: scans placed beyond +-{:g} m (a diverged estimate?)",
                    kernel::kMaxCoordinateM));
  const double res = options.resolution_m;
  const Eigen::Vector2d origin = lo - Eigen::Vector2d::Constant(2 * res);
  const double w = std::floor((hi.x() - lo.x()) / res) + 5,
               h = std::floor((hi.y() - lo.y()) / res) + 5;
  if (!(w * h <= static_cast<double>(options.max_cells)) || w > 1e9 || h > 1e9)
    return R::Fail(fmt::format(
        "occupancy grid: {:.0f} x {:.0f} cells of {} m for {:.1f} x {:.1f} m exceed max_cells = {}",
        w, h, res, hi.x() - lo.x(), hi.y() - lo.y(), options.max_cells));
  OccupancyGrid grid(origin, res, static_cast<int>(w), static_cast<int>(h));
  const auto l_hit = static_cast<float>(Logit(options.hit_probability));
  const auto l_miss = static_cast<float>(Logit(options.miss_probability));
  const auto l_lo = static_cast<float>(Logit(options.min_probability));
  const auto l_hi = static_cast<float>(Logit(options.max_probability));
  // The scan that last updated each cell (one update per cell and scan).
  std::vector<std::uint32_t> updated_by(
      static_cast<std::size_t>(grid.width()) * static_cast<std::size_t>(grid.height()), 0);
  const auto once = [&](int x, int y, std::uint32_t stamp) {
    std::uint32_t& u =
        updated_by[static_cast<std::size_t>(y) * static_cast<std::size_t>(grid.width()) +
                   static_cast<std::size_t>(x)];
    if (u == stamp) return false;
    u = stamp;
    return true;
  };
  std::uint32_t stamp = 0;
  for (const evaluation::PlacedScan& s : scans) {
    if (!Finite(s.pose) || !Finite(s.pose * s.robot_T_laser)) continue;
    ++stamp;
    const Eigen::Vector2d laser = BeamsOf(s, options, &beams);
    for (const Beam& b : beams) {
      if (!b.hit) continue;
      const Eigen::Vector2i c = *grid.CellOf(b.end);
      if (once(c.x(), c.y(), stamp)) grid.Add(c.x(), c.y(), l_hit, l_lo, l_hi);
    }
    for (const Beam& b : beams) {
      const Eigen::Vector2i end = *grid.CellOf(b.end);
      TraverseCells(grid, laser, b.end, [&](int x, int y) {
        if ((x != end.x() || y != end.y() || !b.hit) && once(x, y, stamp))
          grid.Add(x, y, l_miss, l_lo, l_hi);
      });
    }
  }
  return R::Ok(std::move(grid));
}

}  // namespace splam::estimation
