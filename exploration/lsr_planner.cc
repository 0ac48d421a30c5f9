#include "exploration/lsr_planner.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <queue>
#include <utility>

namespace splam::exploration {

LsrPlanner::LsrPlanner(const kernel::LocalSafeRegion& lsr, const Eigen::Vector2d& from,
                       double needed, const std::vector<Eigen::Vector2d>& escapes)
    : from_(from) {
  const double r = lsr.radius() + 2 * kCellM;
  origin_ = lsr.center() - Eigen::Vector2d(r, r);
  cols_ = rows_ = static_cast<int>(std::ceil(2 * r / kCellM));
  parent_.assign(static_cast<std::size_t>(cols_) * rows_, -1);
  // Free cells: those whose centre the polygon covers.
  cv::Mat free_cells(rows_, cols_, CV_8U, cv::Scalar(0));
  std::vector<cv::Point> polygon;
  for (const Eigen::Vector2d& p : lsr.boundary()) {
    const Eigen::Vector2d q = (p - origin_) / kCellM - Eigen::Vector2d(0.5, 0.5);
    polygon.emplace_back(static_cast<int>(std::lround(q.x())),
                         static_cast<int>(std::lround(q.y())));
  }
  cv::fillPoly(free_cells, std::vector<std::vector<cv::Point>>{polygon}, cv::Scalar(255));
  // The boundary itself is drawn as outside: a spike one beam wide (a reading between two sonar
  // cones, 0.27 m from the laser) is thinner than a cell and the fill alone would lose it, while
  // the exact test of the legs does not.
  cv::polylines(free_cells, std::vector<std::vector<cv::Point>>{polygon}, true, cv::Scalar(0));
  cv::Mat distance;  // to the nearest cell outside, cells
  cv::distanceTransform(free_cells, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  auto clearance = [&](int i) { return (distance.at<float>(i / cols_, i % cols_) - 0.5) * kCellM; };
  const int start = Index(from);
  if (start < 0) return;
  const double start_clearance = std::min(needed, clearance(start));
  auto passable = [&](int i) {
    const double c = clearance(i);
    if (c > needed) return true;
    return escapes.empty() && (Centre(i) - from).norm() <= needed &&
           c >= start_clearance - 0.5 * kCellM;
  };
  // Dijkstra from the start, or from the escapes (costs in cells).
  std::vector<double> cost(parent_.size(), std::numeric_limits<double>::infinity());
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  auto seed = [&](int i, double c) {
    if (c >= cost[static_cast<std::size_t>(i)]) return false;
    cost[static_cast<std::size_t>(i)] = c;
    parent_[static_cast<std::size_t>(i)] = i;
    queue.emplace(c, i);
    return true;
  };
  if (escapes.empty()) seed(start, 0.0);
  for (const Eigen::Vector2d& p : escapes) {
    const int i = Index(p);
    if (i >= 0 && seed(i, (p - from).norm() / kCellM)) {
      std::erase_if(escape_cells_, [&](const auto& e) { return e.first == i; });
      escape_cells_.emplace_back(i, p);
    }
  }
  while (!queue.empty()) {
    const auto [c, i] = queue.top();
    queue.pop();
    if (c > cost[static_cast<std::size_t>(i)]) continue;
    const int row = i / cols_, col = i % cols_;
    for (int dr = -1; dr <= 1; ++dr) {
      for (int dc = -1; dc <= 1; ++dc) {
        if ((dr == 0 && dc == 0) || row + dr < 0 || row + dr >= rows_ || col + dc < 0 ||
            col + dc >= cols_)
          continue;
        const int j = (row + dr) * cols_ + col + dc;
        const double next = c + ((dr != 0 && dc != 0) ? M_SQRT2 : 1.0);
        if (next >= cost[static_cast<std::size_t>(j)] || !passable(j)) continue;
        cost[static_cast<std::size_t>(j)] = next;
        parent_[static_cast<std::size_t>(j)] = i;
        queue.emplace(next, j);
      }
    }
  }
}

int LsrPlanner::Index(const Eigen::Vector2d& p) const {
  const Eigen::Vector2d q = (p - origin_) / kCellM;
  const int col = static_cast<int>(std::floor(q.x())), row = static_cast<int>(std::floor(q.y()));
  if (row < 0 || col < 0 || row >= rows_ || col >= cols_) return -1;
  return row * cols_ + col;
}

Eigen::Vector2d LsrPlanner::Centre(int index) const {
  return origin_ + kCellM * Eigen::Vector2d(index % cols_ + 0.5, index / cols_ + 0.5);
}

bool LsrPlanner::Eligible(int i, double min_travel_m, const std::vector<Eigen::Vector2d>& avoid,
                          double min_spacing_m) const {
  if (parent_[static_cast<std::size_t>(i)] < 0) return false;
  const Eigen::Vector2d c = Centre(i);
  if ((c - from_).norm() < min_travel_m) return false;
  return std::none_of(avoid.begin(), avoid.end(),
                      [&](const Eigen::Vector2d& a) { return (c - a).norm() < min_spacing_m; });
}

std::optional<Eigen::Vector2d> LsrPlanner::NearestReachable(
    const Eigen::Vector2d& target, double min_travel_m, const std::vector<Eigen::Vector2d>& avoid,
    double min_spacing_m) const {
  std::optional<Eigen::Vector2d> best;
  double best_distance = std::numeric_limits<double>::infinity();
  for (int i = 0; i < static_cast<int>(parent_.size()); ++i) {
    if (parent_[static_cast<std::size_t>(i)] < 0) continue;
    const double d = (Centre(i) - target).norm();
    if (d >= best_distance || !Eligible(i, min_travel_m, avoid, min_spacing_m)) continue;
    best = Centre(i);
    best_distance = d;
  }
  return best;
}

std::optional<Eigen::Vector2d> LsrPlanner::NearestReachable(
    const Eigen::Vector2d& target, double min_travel_m, const std::vector<Eigen::Vector2d>& avoid,
    double min_spacing_m, int stride,
    const std::function<bool(const Eigen::Vector2d&)>& accept) const {
  std::vector<std::pair<double, int>> cells;
  for (int row = 0; row < rows_; row += stride)
    for (int col = 0; col < cols_; col += stride)
      if (const int i = row * cols_ + col; Eligible(i, min_travel_m, avoid, min_spacing_m))
        cells.emplace_back((Centre(i) - target).norm(), i);
  std::sort(cells.begin(), cells.end());
  for (const auto& [distance, i] : cells)
    if (accept(Centre(i))) return Centre(i);
  return std::nullopt;
}

std::optional<std::vector<Eigen::Vector2d>> LsrPlanner::CellPath(const Eigen::Vector2d& to) const {
  int i = Index(to);
  if (i < 0 || parent_[static_cast<std::size_t>(i)] < 0) return std::nullopt;
  std::vector<Eigen::Vector2d> path;
  while (parent_[static_cast<std::size_t>(i)] != i) {
    path.push_back(Centre(i));
    i = parent_[static_cast<std::size_t>(i)];
  }
  const auto escape = std::find_if(escape_cells_.begin(), escape_cells_.end(),
                                   [&](const auto& e) { return e.first == i; });
  if (escape == escape_cells_.end()) {
    path.push_back(Centre(i));
  } else {
    path.push_back(escape->second);
    path.push_back(from_);
  }
  std::reverse(path.begin(), path.end());
  return path;
}

}  // namespace splam::exploration
