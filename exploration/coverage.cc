#include "exploration/coverage.h"

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace splam::exploration {

CoverageGrid::CoverageGrid(const kernel::Box2& bounds, double cell_m, const Eigen::Vector2d& start,
                           const std::function<bool(const Eigen::Vector2d&)>& is_free)
    : origin_(bounds.min), cell_(cell_m) {
  nx_ = std::max(1, static_cast<int>(std::ceil(bounds.Size().x() / cell_m)));
  ny_ = std::max(1, static_cast<int>(std::ceil(bounds.Size().y() / cell_m)));
  reachable_mask_.assign(static_cast<std::size_t>(nx_) * ny_, 0);
  covered_.assign(reachable_mask_.size(), 0);
  const auto center = [&](int ix, int iy) {
    return Eigen::Vector2d(origin_.x() + (ix + 0.5) * cell_, origin_.y() + (iy + 0.5) * cell_);
  };
  const int sx = static_cast<int>(std::floor((start.x() - origin_.x()) / cell_));
  const int sy = static_cast<int>(std::floor((start.y() - origin_.y()) / cell_));
  if (sx < 0 || sy < 0 || sx >= nx_ || sy >= ny_ || !is_free(center(sx, sy))) return;
  // Flood fill; `visited` also marks cells found not free.
  std::vector<char> visited(reachable_mask_.size(), 0);
  std::vector<std::pair<int, int>> stack{{sx, sy}};
  visited[static_cast<std::size_t>(sy) * nx_ + sx] = 1;
  while (!stack.empty()) {
    const auto [ix, iy] = stack.back();
    stack.pop_back();
    reachable_mask_[static_cast<std::size_t>(iy) * nx_ + ix] = 1;
    ++reachable_;
    reaches_border_ = reaches_border_ || ix == 0 || iy == 0 || ix == nx_ - 1 || iy == ny_ - 1;
    const int neighbours[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
    for (const auto& d : neighbours) {
      const int jx = ix + d[0], jy = iy + d[1];
      if (jx < 0 || jy < 0 || jx >= nx_ || jy >= ny_) continue;
      char& seen = visited[static_cast<std::size_t>(jy) * nx_ + jx];
      if (seen) continue;
      seen = 1;
      if (is_free(center(jx, jy))) stack.push_back({jx, jy});
    }
  }
}

void CoverageGrid::Cover(const kernel::LocalSafeRegion& region) {
  if (region.boundary().size() < 3) return;
  // Rasterise the polygon with OpenCV in cell coordinates (8 bits of sub-cell precision).
  constexpr int kShift = 8;
  std::vector<cv::Point> polygon;
  polygon.reserve(region.boundary().size());
  for (const Eigen::Vector2d& p : region.boundary()) {
    const Eigen::Vector2d c = (p - origin_) / cell_ - Eigen::Vector2d(0.5, 0.5);
    polygon.emplace_back(static_cast<int>(std::lround(c.x() * (1 << kShift))),
                         static_cast<int>(std::lround(c.y() * (1 << kShift))));
  }
  cv::Mat mask = cv::Mat::zeros(ny_, nx_, CV_8U);
  cv::fillPoly(mask, std::vector<std::vector<cv::Point>>{polygon}, cv::Scalar(1), cv::LINE_8,
               kShift);
  for (int iy = 0; iy < ny_; ++iy) {
    const unsigned char* row = mask.ptr<unsigned char>(iy);
    for (int ix = 0; ix < nx_; ++ix) {
      const std::size_t k = static_cast<std::size_t>(iy) * nx_ + ix;
      if (!row[ix] || covered_[k]) continue;
      covered_[k] = 1;
      if (reachable_mask_[k]) ++covered_reachable_;
    }
  }
}

double CoverageGrid::CoveredFraction() const {
  return reachable_ > 0 ? static_cast<double>(covered_reachable_) / reachable_ : 0.0;
}

}  // namespace splam::exploration
