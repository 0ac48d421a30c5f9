#include "estimation/pose_graph/correlative_matcher.h"

#include <algorithm>
#include <cmath>
#include <queue>

#include "kernel/angle.h"

namespace splam::estimation {
namespace {

// A block of translations (level > 0) or one translation (level 0) at one heading.
struct Candidate {
  double score;  // upper bound (level > 0) or exact score (level 0)
  int angle, row, col, level;
  bool operator<(const Candidate& o) const { return score < o.score; }
};

}  // namespace

CorrelativeMatch SearchCorrelative(const std::vector<Eigen::Vector2d>& points,
                                   const LikelihoodPyramid& map, const kernel::Pose2& guess,
                                   double linear_window_m, double angular_window_rad,
                                   double min_score, double ratio_floor,
                                   const CorrelativeOptions& options) {
  CorrelativeMatch match;
  match.pose = guess;
  const DistanceGrid& grid = map.grid();
  if (points.empty() || grid.empty()) return match;
  const double res = grid.resolution();
  // The step moves the 90th-percentile point by one cell: the few farthest points would make the
  // step, and the cost, ten times finer for little gain (the fine registration follows).
  std::vector<double> ranges;
  for (const auto& p : points) ranges.push_back(p.norm());
  std::nth_element(ranges.begin(), ranges.begin() + ranges.size() * 9 / 10, ranges.end());
  const double max_range = ranges[ranges.size() * 9 / 10];
  const double cell_step =
      std::acos(1.0 - res * res / (2.0 * std::max(max_range, res) * std::max(max_range, res)));
  // A step finer than a sixteenth of that moves no point to another cell: it would only
  // multiply the headings (1e-12 rad made 10^11 of them).
  const double step =
      options.angular_step_rad > 0 ? std::max(options.angular_step_rad, cell_step / 16) : cell_step;
  const int n_angles = static_cast<int>(std::ceil(angular_window_rad / step));
  const int window = static_cast<int>(std::ceil(linear_window_m / res));
  const int top = map.levels() - 1;
  const int block = 1 << top;
  const double n = static_cast<double>(points.size());

  // Cells of the points at every heading, translation zero (offsets are added as integers).
  std::vector<std::vector<Eigen::Vector2i>> cells(static_cast<std::size_t>(2 * n_angles + 1));
  for (int a = -n_angles; a <= n_angles; ++a) {
    const kernel::Pose2 pose(guess.translation(), guess.theta() + a * step);
    auto& c = cells[static_cast<std::size_t>(a + n_angles)];
    c.reserve(points.size());
    for (const auto& p : points) {
      const Eigen::Vector2d q = pose * p - grid.origin();
      c.emplace_back(static_cast<int>(std::floor(q.y() / res)),
                     static_cast<int>(std::floor(q.x() / res)));
    }
  }
  const auto score = [&](int angle, int row, int col, int level) {
    double sum = 0.0;
    for (const auto& c : cells[static_cast<std::size_t>(angle)])
      sum += map.At(level, c.x() + row, c.y() + col);
    ++match.evaluated;
    return sum / n;
  };

  std::priority_queue<Candidate> queue;
  for (int a = 0; a < 2 * n_angles + 1; ++a)
    for (int r = -window; r <= window; r += block)
      for (int c = -window; c <= window; c += block) {
        const double s = score(a, r, c, top);
        if (s >= min_score * ratio_floor) queue.push({s, a, r, c, top});
      }
  const auto pose_of = [&](const Candidate& c) {
    return kernel::Pose2(guess.translation() + res * Eigen::Vector2d(c.col, c.row),
                         guess.theta() + (c.angle - n_angles) * step);
  };
  // Leaves leave the queue in decreasing exact score: the first is the best, the first distinct
  // one after it the second-best distinct pose.
  while (!queue.empty()) {
    const Candidate c = queue.top();
    queue.pop();
    const double floor = match.found ? ratio_floor * match.score : min_score;
    if (c.score < floor) break;
    if (c.level == 0) {
      if (c.row < -window || c.row > window || c.col < -window || c.col > window) continue;
      const kernel::Pose2 pose = pose_of(c);
      if (!match.found) {
        match.found = true;
        match.pose = pose;
        match.score = c.score;
        continue;
      }
      const kernel::Pose2 d = match.pose.Between(pose);
      if (d.translation().norm() > options.distinct_m ||
          std::abs(d.theta()) > options.distinct_rad) {
        match.second_score = c.score;
        match.second_pose = pose;
        break;
      }
      continue;
    }
    const int h = 1 << (c.level - 1);
    for (int dr = 0; dr < 2; ++dr)
      for (int dc = 0; dc < 2; ++dc) {
        const int r = c.row + dr * h, col = c.col + dc * h;
        if (r > window || col > window) continue;
        const double s = score(c.angle, r, col, c.level - 1);
        if (s >= floor) queue.push({s, c.angle, r, col, c.level - 1});
      }
  }
  return match;
}

}  // namespace splam::estimation
