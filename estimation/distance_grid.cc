#include "estimation/distance_grid.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace splam::estimation {

DistanceGrid DistanceGrid::Build(const std::vector<Eigen::Vector2d>& points, double resolution_m,
                                 double truncation_m, double margin_m) {
  DistanceGrid g;
  g.resolution_m_ = resolution_m;
  g.truncation_m_ = truncation_m;
  if (points.empty()) return g;
  Eigen::Vector2d lo = points.front(), hi = points.front();
  for (const auto& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  g.origin_ = lo.array() - margin_m;
  g.cols_ = static_cast<int>(std::ceil((hi.x() - lo.x() + 2 * margin_m) / resolution_m)) + 1;
  g.rows_ = static_cast<int>(std::ceil((hi.y() - lo.y() + 2 * margin_m) / resolution_m)) + 1;

  // Occupied cells keep the mean of their points: on a curve sampled densely, a point on it.
  cv::Mat free_cells(g.rows_, g.cols_, CV_8U, cv::Scalar(255));
  std::vector<Eigen::Vector2d> sum(static_cast<std::size_t>(g.rows_) * g.cols_,
                                   Eigen::Vector2d::Zero());
  std::vector<int> count(sum.size(), 0);
  for (const auto& p : points) {
    const int c = static_cast<int>((p.x() - g.origin_.x()) / resolution_m);
    const int r = static_cast<int>((p.y() - g.origin_.y()) / resolution_m);
    const std::size_t i = static_cast<std::size_t>(r) * g.cols_ + c;
    sum[i] += p;
    ++count[i];
    free_cells.at<unsigned char>(r, c) = 0;
  }
  cv::Mat distance, labels;
  cv::distanceTransform(free_cells, distance, labels, cv::DIST_L2, cv::DIST_MASK_5,
                        cv::DIST_LABEL_PIXEL);
  // label -> the point kept by that occupied cell.
  std::vector<Eigen::Vector2d> kept;
  for (int r = 0; r < g.rows_; ++r)
    for (int c = 0; c < g.cols_; ++c) {
      const std::size_t i = static_cast<std::size_t>(r) * g.cols_ + c;
      if (count[i] == 0) continue;
      const auto label = static_cast<std::size_t>(labels.at<int>(r, c));
      if (kept.size() <= label) kept.resize(label + 1, Eigen::Vector2d::Zero());
      kept[label] = sum[i] / count[i];
    }
  g.values_.resize(sum.size());
  for (int r = 0; r < g.rows_; ++r)
    for (int c = 0; c < g.cols_; ++c) {
      const Eigen::Vector2d centre = g.origin_ + resolution_m * Eigen::Vector2d(c + 0.5, r + 0.5);
      const auto label = static_cast<std::size_t>(labels.at<int>(r, c));
      const double d = label < kept.size() ? (kept[label] - centre).norm()
                                           : distance.at<float>(r, c) * resolution_m;
      g.values_[static_cast<std::size_t>(r) * g.cols_ + c] = std::min(d, truncation_m);
    }
  return g;
}

double DistanceGrid::Nearest(const Eigen::Vector2d& p) const {
  const int c = static_cast<int>(std::floor((p.x() - origin_.x()) / resolution_m_));
  const int r = static_cast<int>(std::floor((p.y() - origin_.y()) / resolution_m_));
  if (r < 0 || c < 0 || r >= rows_ || c >= cols_) return truncation_m_;
  return At(r, c);
}

LikelihoodPyramid::LikelihoodPyramid(const DistanceGrid& grid, double sigma_m, int levels)
    : grid_(&grid) {
  const std::size_t n = grid.values().size();
  levels_.emplace_back(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double d = grid.values()[i];
    levels_[0][i] = static_cast<float>(std::exp(-d * d / (2 * sigma_m * sigma_m)));
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
