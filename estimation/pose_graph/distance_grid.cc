#include "estimation/pose_graph/distance_grid.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <opencv2/imgproc.hpp>
#include <unordered_map>

namespace splam::estimation {
namespace {

// Each occupied cell stands for the piece of outline through its point: a segment along the
// tangent (perpendicular to the normal) this many cells long either side, so that the pieces of
// neighbouring cells (up to a diagonal apart) join.
constexpr double kSegmentHalfLength = 1.5;

// Distance from the point s + v to the piece of outline at s with unit normal n, `half` either
// side along its tangent t = (-n.y, n.x) and round beyond (to s itself when n is zero), signed
// by the side of n; its gradient d/dv in *gradient when not null.
double PieceDistance(const Eigen::Vector2d& v, const Eigen::Vector2d& n, double half,
                     Eigen::Vector2d* gradient) {
  if (n.isZero()) {
    const double d = v.norm();
    if (gradient != nullptr)
      *gradient = d > 1e-12 ? Eigen::Vector2d(v / d) : Eigen::Vector2d::Zero();
    return d;
  }
  const Eigen::Vector2d t(-n.y(), n.x());
  const double across = n.dot(v), along_signed = t.dot(v);
  const double along = std::max(0.0, std::abs(along_signed) - half);
  // sqrt rather than std::hypot: the terms are metres, far from overflow, and hypot took 6 % of a
  // graph SLAM run on intel.
  const double d = std::sqrt(across * across + along * along);
  const double sign = across < 0 ? -1.0 : 1.0;
  if (gradient != nullptr)
    *gradient = along <= 0.0 || d < 1e-12
                    ? n
                    : Eigen::Vector2d(
                          sign * (across * n + along * std::copysign(1.0, along_signed) * t) / d);
  return sign * d;
}

// A cell whose centre lies at least this many cells from the centre of its nearest occupied cell
// reads the truncation: that cell's piece lies within sqrt(1/2) + kSegmentHalfLength cells of
// its centre, and the 5x5 chamfer distance (Build's distance transform) is within 2 % of the
// Euclidean one (at most 1.9 % above it, midway between the (1, 0) and (2, 1) moves).
double FarCells(double truncation_m, double resolution_m) {
  return (truncation_m / resolution_m + std::sqrt(0.5) + kSegmentHalfLength) / 0.95;
}

}  // namespace

void DistanceGrid::CellSums::Add(const Eigen::Vector2d& p, const Eigen::Vector2d& n) {
  sum += p;
  normal += n;
  if (reference.isZero()) reference = n;
  if (n.dot(reference) < 0) opposed += n;
  ++count;
}

OrientedPoint DistanceGrid::CellSums::Piece() const {
  OrientedPoint piece{sum / count, normal};
  if (piece.normal.norm() > 1e-12) piece.normal.normalize();
  return piece;
}

Eigen::Vector2d DistanceGrid::CellSums::Back() const {
  if (opposed.isZero()) return Eigen::Vector2d::Zero();
  const Eigen::Vector2d same_as_reference = normal - opposed;
  const Eigen::Vector2d back = normal.dot(same_as_reference) >= 0 ? opposed : same_as_reference;
  if (back.dot(normal) >= 0 || back.norm() < 1e-12) return Eigen::Vector2d::Zero();
  return back.normalized();
}

DistanceGrid DistanceGrid::Build(const std::vector<Eigen::Vector2d>& points, double resolution_m,
                                 double truncation_m, double margin_m,
                                 const std::vector<std::vector<Eigen::Vector2d>>& seen) {
  std::vector<OrientedPoint> oriented;
  oriented.reserve(points.size());
  for (const auto& p : points) oriented.push_back({p, Eigen::Vector2d::Zero()});
  return Build(oriented, resolution_m, truncation_m, margin_m, seen);
}

DistanceGrid DistanceGrid::Build(const std::vector<OrientedPoint>& oriented, double resolution_m,
                                 double truncation_m, double margin_m,
                                 const std::vector<std::vector<Eigen::Vector2d>>& seen,
                                 bool signed_field, double seen_margin_m,
                                 const std::vector<std::vector<Eigen::Vector2d>>& seen_by_hits) {
  std::vector<ViewCells> rasterised;
  rasterised.reserve(seen.size() + seen_by_hits.size());
  for (const auto& polygon : seen)
    rasterised.push_back(RasteriseView(polygon, resolution_m, seen_margin_m));
  for (const auto& polygon : seen_by_hits)
    rasterised.push_back(RasteriseView(polygon, resolution_m, seen_margin_m));
  std::vector<const ViewCells*> views, by_hits;
  for (std::size_t i = 0; i < rasterised.size(); ++i)
    (i < seen.size() ? views : by_hits).push_back(&rasterised[i]);
  return Build(oriented, resolution_m, truncation_m, margin_m, views, signed_field, by_hits);
}

DistanceGrid DistanceGrid::Build(const std::vector<OrientedPoint>& oriented, double resolution_m,
                                 double truncation_m, double margin_m,
                                 const std::vector<const ViewCells*>& seen, bool signed_field,
                                 const std::vector<const ViewCells*>& seen_by_hits) {
  DistanceGrid g;
  g.resolution_m_ = resolution_m;
  g.truncation_m_ = truncation_m;
  g.signed_ = signed_field;
  if (oriented.empty()) return g;
  Eigen::Vector2d lo = oriented.front().point, hi = lo;
  for (const auto& o : oriented) {
    lo = lo.cwiseMin(o.point);
    hi = hi.cwiseMax(o.point);
  }
  const Eigen::Vector2d extent = (hi - lo).array() + 2 * margin_m;
  // The lattice cell of the corner, and the cells up to the far corner.
  const Eigen::Vector2d first = ((lo.array() - margin_m) / resolution_m).floor();
  const Eigen::Vector2d last = ((hi.array() + margin_m) / resolution_m).floor();
  const double cols = last.x() - first.x() + 1, rows = last.y() - first.y() + 1;
  if (!(cols * rows <= kMaxCells) || !(std::abs(first.x()) < 1e9 && std::abs(first.y()) < 1e9)) {
    g.extent_ = extent.cwiseMax(resolution_m);
    return g;
  }
  g.cols_ = static_cast<int>(cols);
  g.rows_ = static_cast<int>(rows);
  g.first_col_ = static_cast<long>(first.x());
  g.first_row_ = static_cast<long>(first.y());
  g.origin_ = first * resolution_m;

  // Occupied cells keep the mean of their points: on a curve sampled densely, a point on it.
  // Their sums live in one slot per occupied cell (a grid spans far more cells than its points
  // occupy: an accumulator per cell made most of a submap's build time), filled in the points'
  // order.
  const std::size_t cells = static_cast<std::size_t>(g.rows_) * g.cols_;
  cv::Mat free_cells(g.rows_, g.cols_, CV_8U, cv::Scalar(255));
  std::vector<int> slot_of(cells, -1);
  std::vector<CellSums> occupied;
  for (const auto& [p, n] : oriented) {
    // Clamped: a point on the far corner's lattice line may round past it.
    const int c = std::min(static_cast<int>((p.x() - g.origin_.x()) / resolution_m), g.cols_ - 1);
    const int r = std::min(static_cast<int>((p.y() - g.origin_.y()) / resolution_m), g.rows_ - 1);
    const std::size_t i = static_cast<std::size_t>(r) * g.cols_ + c;
    if (slot_of[i] < 0) {
      slot_of[i] = static_cast<int>(occupied.size());
      occupied.push_back({.cell = i});
      free_cells.at<unsigned char>(r, c) = 0;
    }
    occupied[static_cast<std::size_t>(slot_of[i])].Add(p, n);
  }
  cv::Mat distance, labels;
  cv::distanceTransform(free_cells, distance, labels, cv::DIST_L2, cv::DIST_MASK_5,
                        cv::DIST_LABEL_PIXEL);
  // label -> the piece of that occupied cell.
  g.piece_of_.assign(cells, -1);
  for (const CellSums& o : occupied) {
    const auto label = static_cast<std::size_t>(labels.at<int>(static_cast<int>(o.cell)));
    if (g.pieces_.size() <= label) {
      g.pieces_.resize(label + 1);
      g.back_normals_.resize(label + 1, Eigen::Vector2d::Zero());
      g.sums_.resize(label + 1);
    }
    g.pieces_[label] = o.Piece();
    g.back_normals_[label] = o.Back();
    g.sums_[label] = o;
    g.piece_of_[o.cell] = static_cast<int>(label);
  }
  const double half = kSegmentHalfLength * resolution_m;
  const double far = FarCells(truncation_m, resolution_m);
  g.values_.resize(cells);
  g.nearest_.assign(cells, -1);
  for (int r = 0; r < g.rows_; ++r)
    for (int c = 0; c < g.cols_; ++c) {
      const std::size_t i = static_cast<std::size_t>(r) * g.cols_ + c;
      const Eigen::Vector2d centre = g.origin_ + resolution_m * Eigen::Vector2d(c + 0.5, r + 0.5);
      const auto label = static_cast<std::size_t>(labels.at<int>(r, c));
      const float cells_away = distance.at<float>(r, c);
      double d = cells_away * resolution_m;
      if (label < g.pieces_.size()) {
        const OrientedPoint& piece = g.pieces_[label];
        if (cells_away >= far) {
          d = signed_field && piece.normal.dot(centre - piece.point) < 0 ? -truncation_m
                                                                         : truncation_m;
        } else {
          d = PieceDistance(centre - piece.point, piece.normal, half, nullptr);
          if (!signed_field) d = std::abs(d);
        }
        g.nearest_[i] = static_cast<int>(label);
      }
      g.values_[i] = std::clamp(d, -truncation_m, truncation_m);
    }
  if (seen.empty()) return g;
  // A cell's value is the highest any view gives it: every view's whole polygon 1, the parts
  // seen free 2 (so that no view's margin covers another's free space), those crossed by a beam
  // that returned 3; an outline's cells are seen free.
  g.known_.assign(cells, 0);
  for (const ViewCells* view : seen) g.RaiseKnown(view->whole, 1);
  for (const ViewCells* view : seen) g.RaiseKnown(view->inner, 2);
  for (const CellSums& o : occupied)
    g.known_[o.cell] = std::max<unsigned char>(g.known_[o.cell], 2);
  for (const ViewCells* view : seen_by_hits) g.RaiseKnown(view->inner, 3);
  return g;
}

void DistanceGrid::RaiseKnown(const std::vector<ViewCells::Run>& runs, unsigned char value) {
  for (const ViewCells::Run& run : runs) {
    const long r = run.row - first_row_;
    const long c0 = std::max<long>(run.first - first_col_, 0);
    const long c1 = std::min<long>(run.last - first_col_, cols_ - 1);
    if (r < 0 || r >= rows_ || c0 > c1) continue;
    unsigned char* row = known_.data() + r * cols_;
    for (long c = c0; c <= c1; ++c) row[c] = std::max(row[c], value);
  }
}

int DistanceGrid::Reach() const {
  return static_cast<int>(
      std::ceil(truncation_m_ / resolution_m_ + std::sqrt(0.5) + kSegmentHalfLength));
}

bool DistanceGrid::Insert(const std::vector<OrientedPoint>& oriented,
                          const std::vector<const ViewCells*>& seen) {
  if (empty()) return false;
  // As Build's margin: the field within the truncation of every point.
  const double margin = truncation_m_ / resolution_m_;
  std::vector<std::size_t> cell_of;
  cell_of.reserve(oriented.size());
  for (const OrientedPoint& o : oriented) {
    const Eigen::Vector2d q = (o.point - origin_) / resolution_m_;
    // Compared in doubles: a point kilometres off is no int.
    if (!(q.x() >= margin && q.y() >= margin && q.x() < cols_ - margin && q.y() < rows_ - margin))
      return false;
    cell_of.push_back(static_cast<std::size_t>(static_cast<int>(q.y())) * cols_ +
                      static_cast<std::size_t>(static_cast<int>(q.x())));
  }
  // Every point joins its cell's sums, in the points' order; a cell without a piece gets one.
  const auto first_new = static_cast<int>(pieces_.size());
  std::vector<int> changed;
  for (std::size_t k = 0; k < oriented.size(); ++k) {
    const std::size_t i = cell_of[k];
    if (piece_of_[i] < 0) {
      piece_of_[i] = static_cast<int>(pieces_.size());
      pieces_.emplace_back();
      back_normals_.emplace_back(Eigen::Vector2d::Zero());
      sums_.push_back({.cell = i});
      if (!known_.empty()) known_[i] = std::max<unsigned char>(known_[i], 2);
    }
    const int label = piece_of_[i];
    if (changed.empty() || changed.back() != label) changed.push_back(label);
    sums_[static_cast<std::size_t>(label)].Add(oriented[k].point, oriented[k].normal);
  }
  std::sort(changed.begin(), changed.end());
  changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
  const double half = kSegmentHalfLength * resolution_m_;
  const int reach = Reach();
  const double far = FarCells(truncation_m_, resolution_m_);
  for (const int label : changed) {
    const auto l = static_cast<std::size_t>(label);
    const OrientedPoint before = pieces_[l];
    const bool fresh = label >= first_new;
    pieces_[l] = sums_[l].Piece();
    back_normals_[l] = sums_[l].Back();
    const OrientedPoint& piece = pieces_[l];
    // A piece that a few more points moved so little that no distance within its reach changed
    // by a hundredth of a cell (the point's shift plus the normal's turn times the reach) keeps
    // its cells' values: Distance is exact to the piece all the same, and the values feed the
    // correlative search.
    const double shift = (piece.point - before.point).norm() +
                         reach * resolution_m_ * (piece.normal - before.normal).norm();
    if (!fresh && shift < 0.01 * resolution_m_) continue;
    // As Build: a cell's own piece is that of the occupied cell whose centre is nearest to its
    // centre (here Euclidean, there the 5x5 chamfer distance within 2 % of it), and its value the
    // exact distance to that piece, or the truncation from `far` cells on. A new piece takes the
    // cells within the reach whose own lies farther; a moved one changes its own cells' values.
    const std::size_t cell = sums_[l].cell;
    const int r0 = static_cast<int>(cell / static_cast<std::size_t>(cols_));
    const int c0 = static_cast<int>(cell % static_cast<std::size_t>(cols_));
    for (int r = std::max(r0 - reach, 0); r <= std::min(r0 + reach, rows_ - 1); ++r)
      for (int c = std::max(c0 - reach, 0); c <= std::min(c0 + reach, cols_ - 1); ++c) {
        const std::size_t i = static_cast<std::size_t>(r) * cols_ + c;
        const int away2 = (r - r0) * (r - r0) + (c - c0) * (c - c0);
        const int own = nearest_[i];
        if (own != label) {
          if (!fresh) continue;
          if (own >= 0) {
            const std::size_t other = sums_[static_cast<std::size_t>(own)].cell;
            const int dr = r - static_cast<int>(other / static_cast<std::size_t>(cols_));
            const int dc = c - static_cast<int>(other % static_cast<std::size_t>(cols_));
            if (dr * dr + dc * dc <= away2) continue;
          }
          nearest_[i] = label;
        }
        const Eigen::Vector2d centre = origin_ + resolution_m_ * Eigen::Vector2d(c + 0.5, r + 0.5);
        double d = PieceDistance(centre - piece.point, piece.normal, half, nullptr);
        if (std::sqrt(static_cast<double>(away2)) >= far)
          d = d < 0 ? -truncation_m_ : truncation_m_;
        values_[i] = std::clamp(signed_ ? d : std::abs(d), -truncation_m_, truncation_m_);
      }
  }
  if (!known_.empty()) {
    for (const ViewCells* view : seen) RaiseKnown(view->whole, 1);
    for (const ViewCells* view : seen) RaiseKnown(view->inner, 2);
  }
  return true;
}

ViewCells RasteriseView(const std::vector<Eigen::Vector2d>& polygon, double resolution_m,
                        double seen_margin_m) {
  ViewCells v;
  v.resolution_m = resolution_m;
  // Vertices that are not finite (a pose or a margin that is not) are left out.
  if (polygon.empty() || !polygon.front().allFinite()) return v;
  // The window: 4096 cells square about the sensor's cell, in lattice cells.
  constexpr long kHalf = 2048;
  const auto lattice = [&](const Eigen::Vector2d& p) {
    const Eigen::Vector2d q = p / resolution_m;
    return Eigen::Vector2d(std::round(std::clamp(q.x(), -1e12, 1e12)),
                           std::round(std::clamp(q.y(), -1e12, 1e12)));
  };
  const Eigen::Vector2d corner = lattice(polygon.front()).array() - kHalf;
  if (!(corner.cwiseAbs().maxCoeff() < 1e9)) return v;  // beyond any grid (DistanceGrid::Build)
  // A vertex in the window's cells (far ones clamped: the fill clips them), unless it falls in
  // the cell of the previous one: a dense laser's beams end a few per cell, and the fill (each
  // edge drawn, then the scanlines between) is the same without the zero-length edges.
  const auto add_vertex = [&](std::vector<cv::Point>* out, const Eigen::Vector2d& p) {
    if (!p.allFinite()) return;
    const Eigen::Vector2d q = (lattice(p) - corner).cwiseMax(-1e6).cwiseMin(1e6);
    const cv::Point vertex(static_cast<int>(q.x()), static_cast<int>(q.y()));
    if (out->empty() || out->back() != vertex) out->push_back(vertex);
  };
  std::vector<cv::Point> whole, inner;
  for (const auto& p : polygon) {
    add_vertex(&whole, p);
    // Pulled back by seen_margin_m towards the sensor (the first vertex).
    const Eigen::Vector2d ray = p - polygon.front();
    const double length = ray.norm();
    add_vertex(&inner, length <= seen_margin_m ? polygon.front()
                                               : Eigen::Vector2d(p - seen_margin_m / length * ray));
  }
  // The cells of the window the polygon can touch.
  cv::Rect box = cv::boundingRect(whole) & cv::Rect(0, 0, 2 * kHalf, 2 * kHalf);
  if (box.empty()) return v;
  cv::Mat cells(box.height, box.width, CV_8U);
  const auto runs_of = [&](std::vector<cv::Point> vertices, std::vector<ViewCells::Run>* runs) {
    for (cv::Point& p : vertices) p -= box.tl();
    cells.setTo(cv::Scalar(0));
    cv::fillPoly(cells, std::vector<std::vector<cv::Point>>{vertices}, cv::Scalar(1));
    // The runs of each row, found with memchr: most of a view's box is outside it (the long
    // thin views of beams without a return).
    const auto width = static_cast<std::size_t>(cells.cols);
    for (int r = 0; r < cells.rows; ++r) {
      const unsigned char* row = cells.ptr<unsigned char>(r);
      const unsigned char* end = row + width;
      for (const unsigned char* at = row; at < end;) {
        const auto* start = static_cast<const unsigned char*>(
            std::memchr(at, 1, static_cast<std::size_t>(end - at)));
        if (start == nullptr) break;
        const auto* stop = static_cast<const unsigned char*>(
            std::memchr(start, 0, static_cast<std::size_t>(end - start)));
        if (stop == nullptr) stop = end;
        runs->push_back({static_cast<int>(corner.y()) + box.y + r,
                         static_cast<int>(corner.x()) + box.x + static_cast<int>(start - row),
                         static_cast<int>(corner.x()) + box.x + static_cast<int>(stop - row) - 1});
        at = stop;
      }
    }
  };
  runs_of(whole, &v.whole);
  if (seen_margin_m > 0)
    runs_of(inner, &v.inner);
  else
    v.inner = v.whole;
  return v;
}

long DistanceGrid::CellIndex(const Eigen::Vector2d& p) const {
  const int c = static_cast<int>(std::floor((p.x() - origin_.x()) / resolution_m_));
  const int r = static_cast<int>(std::floor((p.y() - origin_.y()) / resolution_m_));
  if (r < 0 || c < 0 || r >= rows_ || c >= cols_) return -1;
  return static_cast<long>(r) * cols_ + c;
}

bool DistanceGrid::Known(const Eigen::Vector2d& p) const {
  const long i = CellIndex(p);
  return i >= 0 && (known_.empty() || known_[static_cast<std::size_t>(i)] != 0);
}

bool DistanceGrid::SeenFree(const Eigen::Vector2d& p) const {
  const long i = CellIndex(p);
  return i >= 0 && (known_.empty() || known_[static_cast<std::size_t>(i)] >= 2);
}

bool DistanceGrid::SeenFreeByHits(const Eigen::Vector2d& p) const {
  const long i = CellIndex(p);
  return i >= 0 && !known_.empty() && known_[static_cast<std::size_t>(i)] == 3;
}

double DistanceGrid::Distance(const Eigen::Vector2d& p, Eigen::Vector2d* gradient) const {
  if (gradient != nullptr) gradient->setZero();
  const OrientedPoint* piece = NearestPiece(p);
  if (piece == nullptr) return truncation_m_;
  Eigen::Vector2d g;
  const double d =
      PieceDistance(p - piece->point, piece->normal, kSegmentHalfLength * resolution_m_, &g);
  if (std::abs(d) >= truncation_m_) return truncation_m_;
  if (gradient != nullptr) *gradient = g;
  return d;
}

const OrientedPoint* DistanceGrid::NearestPiece(const Eigen::Vector2d& p) const {
  const long i = CellIndex(p);
  const int label = i < 0 ? -1 : nearest_[static_cast<std::size_t>(i)];
  return label < 0 ? nullptr : &pieces_[static_cast<std::size_t>(label)];
}

Eigen::Vector2d DistanceGrid::BackNormal(const Eigen::Vector2d& p) const {
  const long i = CellIndex(p);
  const int label = i < 0 ? -1 : nearest_[static_cast<std::size_t>(i)];
  return label < 0 ? Eigen::Vector2d::Zero() : back_normals_[static_cast<std::size_t>(label)];
}

double DistanceGrid::PieceHalfLength() const { return kSegmentHalfLength * resolution_m_; }

double DistanceGrid::Nearest(const Eigen::Vector2d& p) const {
  const long i = CellIndex(p);
  return i < 0 ? truncation_m_ : values_[static_cast<std::size_t>(i)];
}

namespace {

// Consecutive spacings of a surface's points grow smoothly with the incidence (by about 1.6
// times per beam 14-22 m along a wall 1.25 m from a 1 deg laser); a spacing more than this
// times its neighbour is a jump, however well the short one lines up with it.
constexpr double kMaxSpacingRatio = 3.0;

// Whether b lies strictly between a and c along their chord and within `tolerance` of it, with
// |b - a| and |c - b| within kMaxSpacingRatio of each other.
bool Collinear(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
               double tolerance) {
  const Eigen::Vector2d chord = c - a;
  const double length = chord.norm();
  const double first = (b - a).norm(), second = (c - b).norm();
  if (length < 1e-12 || first > kMaxSpacingRatio * second || second > kMaxSpacingRatio * first)
    return false;
  const Eigen::Vector2d u = chord / length;
  const Eigen::Vector2d v = b - a;
  const double along = u.dot(v);
  return along > 0 && along < length && std::abs(u.x() * v.y() - u.y() * v.x()) <= tolerance;
}

}  // namespace

std::vector<bool> LinkedToNext(const std::vector<Eigen::Vector2d>& p, double max_gap_m,
                               double line_tolerance_m) {
  const std::size_t n = p.size();
  std::vector<bool> linked(n, false);
  for (std::size_t i = 0; i + 1 < n; ++i)
    linked[i] = (p[i + 1] - p[i]).norm() <= max_gap_m ||
                (line_tolerance_m > 0 &&
                 ((i > 0 && Collinear(p[i - 1], p[i], p[i + 1], line_tolerance_m)) ||
                  (i + 2 < n && Collinear(p[i], p[i + 1], p[i + 2], line_tolerance_m))));
  return linked;
}

std::vector<OrientedPoint> OrientTowards(const std::vector<Eigen::Vector2d>& points,
                                         const Eigen::Vector2d& sensor, double max_gap_m,
                                         double line_tolerance_m) {
  const std::vector<bool> linked = LinkedToNext(points, max_gap_m, line_tolerance_m);
  std::vector<OrientedPoint> out(points.size());
  // Prefix sums of the points and their products, relative to the first point (which keeps
  // the sums' cancellation small: a scan's extent against a centimetre scatter), so that each
  // point's run costs O(1): sum_j (q_j - m)(q_j - m)^T = sum_j q_j q_j^T - n m m^T.
  const Eigen::Vector2d origin = points.empty() ? Eigen::Vector2d::Zero() : points.front();
  std::vector<Eigen::Vector2d> sum(points.size() + 1, Eigen::Vector2d::Zero());
  std::vector<Eigen::Vector3d> products(points.size() + 1, Eigen::Vector3d::Zero());  // xx xy yy
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector2d q = points[i] - origin;
    sum[i + 1] = sum[i] + q;
    products[i + 1] = products[i] + Eigen::Vector3d(q.x() * q.x(), q.x() * q.y(), q.y() * q.y());
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector2d& p = points[i];
    // The run's points within max_gap_m of p (reached through gaps of at most max_gap_m), and
    // at least its immediate linked neighbours.
    std::size_t first = i, last = i;
    if (first > 0 && linked[first - 1]) --first;
    while (first > 0 && (points[first - 1] - p).norm() <= max_gap_m &&
           (points[first - 1] - points[first]).norm() <= max_gap_m)
      --first;
    if (last + 1 < points.size() && linked[last]) ++last;
    while (last + 1 < points.size() && (points[last + 1] - p).norm() <= max_gap_m &&
           (points[last + 1] - points[last]).norm() <= max_gap_m)
      ++last;
    const Eigen::Vector2d to_sensor = sensor - p;
    Eigen::Vector2d n = to_sensor;
    if (last - first >= 2) {
      // The normal of the total-least-squares line through them: the eigenvector of their
      // scatter with the smaller eigenvalue.
      const double count = static_cast<double>(last - first + 1);
      const Eigen::Vector2d mean = (sum[last + 1] - sum[first]) / count;
      const Eigen::Vector3d product = products[last + 1] - products[first];
      Eigen::Matrix2d scatter;
      scatter << product(0) - count * mean.x() * mean.x(), product(1) - count * mean.x() * mean.y(),
          product(1) - count * mean.x() * mean.y(), product(2) - count * mean.y() * mean.y();
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen;
      eigen.computeDirect(scatter);  // closed form
      n = eigen.eigenvectors().col(0);
    } else if (last > first) {
      const Eigen::Vector2d tangent = points[last] - points[first];
      n = Eigen::Vector2d(-tangent.y(), tangent.x());
    }
    if (n.dot(to_sensor) < 0) n = -n;
    out[i] = {p, n.norm() > 1e-12 ? Eigen::Vector2d(n.normalized()) : Eigen::Vector2d::Zero()};
  }
  return out;
}

std::vector<OrientedPoint> FillLinkedGaps(const std::vector<OrientedPoint>& oriented,
                                          double max_gap_m, double line_tolerance_m,
                                          double spacing_m) {
  std::vector<Eigen::Vector2d> points;
  points.reserve(oriented.size());
  for (const OrientedPoint& o : oriented) points.push_back(o.point);
  const std::vector<bool> linked = LinkedToNext(points, max_gap_m, line_tolerance_m);
  std::vector<OrientedPoint> fill;
  for (std::size_t i = 0; i + 1 < points.size(); ++i) {
    const Eigen::Vector2d chord = points[i + 1] - points[i];
    const double length = chord.norm();
    if (!linked[i] || length <= max_gap_m) continue;
    Eigen::Vector2d n(-chord.y() / length, chord.x() / length);
    if (n.dot(oriented[i].normal + oriented[i + 1].normal) < 0) n = -n;
    const int steps = static_cast<int>(std::ceil(length / spacing_m));
    for (int s = 1; s < steps; ++s)
      fill.push_back({points[i] + chord * (static_cast<double>(s) / steps), n});
  }
  return fill;
}

LikelihoodPyramid::LikelihoodPyramid(const DistanceGrid& grid, double sigma_m, int levels,
                                     double seen_free_score, double free_distance_m)
    : grid_(&grid) {
  const std::size_t n = grid.values().size();
  levels_.emplace_back(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double d = grid.values()[i];
    const bool seen_free = seen_free_score != 0.0 && d >= free_distance_m && !grid.known_.empty() &&
                           grid.known_[i] == 3;
    levels_[0][i] = static_cast<float>(seen_free ? seen_free_score
                                                 : std::exp(-d * d / (2 * sigma_m * sigma_m)));
  }
  for (int k = 1; k < levels; ++k) {
    const int h = 1 << (k - 1);
    std::vector<float> next(n);
    const auto& prev = levels_.back();
    const auto at = [&](int r, int c) {
      return r < grid.rows() && c < grid.cols()
                 ? prev[static_cast<std::size_t>(r) * grid.cols() + c]
                 : 0.0f;
    };
    for (int r = 0; r < grid.rows(); ++r)
      for (int c = 0; c < grid.cols(); ++c)
        next[static_cast<std::size_t>(r) * grid.cols() + c] =
            std::max({at(r, c), at(r, c + h), at(r + h, c), at(r + h, c + h)});
    levels_.push_back(std::move(next));
  }
}

}  // namespace splam::estimation
