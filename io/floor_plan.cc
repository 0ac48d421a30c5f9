#include "io/floor_plan.h"

#include <cmath>
#include <filesystem>
#include <opencv2/imgproc.hpp>

#include "io/internal/image.h"

namespace splam::io {

kernel::Status FloorPlanOptions::Validate() const {
  if (!(resolution_m_per_px >= kMinResolutionM && resolution_m_per_px <= kMaxResolutionM)) {
    return kernel::Status::Error("floor-plan resolution must be within [1e-4, 10] m per pixel");
  }
  if (dark_threshold < 1 || dark_threshold > 255)
    return kernel::Status::Error("dark threshold must be in 1..255");
  if (!origin_m.allFinite()) return kernel::Status::Error("floor-plan origin must be finite");
  if (!(simplify_tolerance_px >= 0.0))
    return kernel::Status::Error("simplify tolerance must be >= 0");
  return kernel::Status::Ok();
}

namespace {

// The image in grey levels; an error names the file.
Result<cv::Mat> ReadGrey(const std::string& path, const FloorPlanOptions& options) {
  if (kernel::Status problem = options.Validate(); !problem.ok())
    return Result<cv::Mat>::Fail(FileError(path, 0, problem.message()));
  return internal::ReadGreyImage(path);
}

}  // namespace

Result<bool> FloorPlanIsDarkAt(const std::string& path, const FloorPlanOptions& options,
                               const Eigen::Vector2d& point) {
  Result<cv::Mat> grey = ReadGrey(path, options);
  if (!grey.ok()) return Result<bool>::Fail(grey.error);
  const cv::Mat& image = *grey.value;
  // Pixel (column, row) covers x in origin + [column, column + 1) * res, rows counted from the top.
  const Eigen::Vector2d pixel = (point - options.origin_m) / options.resolution_m_per_px;
  const double column = std::floor(pixel.x()), row = image.rows - 1 - std::floor(pixel.y());
  if (!(column >= 0 && column < image.cols && row >= 0 && row < image.rows))
    return Result<bool>::Ok(false);
  return Result<bool>::Ok(image.at<unsigned char>(static_cast<int>(row), static_cast<int>(column)) <
                          options.dark_threshold);
}

Result<sim::World> ReadFloorPlan(const std::string& path, const FloorPlanOptions& options) {
  using R = Result<sim::World>;
  Result<cv::Mat> read = ReadGrey(path, options);
  if (!read.ok()) return R::Fail(read.error);
  const cv::Mat& grey = *read.value;

  cv::Mat dark;
  cv::threshold(grey, dark, options.dark_threshold - 1, 255, cv::THRESH_BINARY_INV);
  // Dark everywhere: one solid block, no room in it (its outline alone read as walls around
  // free space, and an exploration "covered" 91 % of it).
  if (cv::countNonZero(dark) == static_cast<int>(dark.total()))
    return R::Fail(FileError(path, 0,
                             "every pixel is dark (below grey level " +
                                 std::to_string(options.dark_threshold) +
                                 "): a solid block with no free space"));
  // A one-pixel white frame so that regions touching the border still get closed outlines.
  cv::copyMakeBorder(dark, dark, 1, 1, 1, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(dark, contours, cv::RETR_LIST, cv::CHAIN_APPROX_NONE);

  sim::World world;
  world.name = std::filesystem::path(path).stem().string();
  const double res = options.resolution_m_per_px;
  const int rows = grey.rows;
  for (const auto& contour : contours) {
    std::vector<cv::Point> simplified;
    cv::approxPolyDP(contour, simplified, options.simplify_tolerance_px, true);
    sim::Polyline loop;
    for (const cv::Point& p : simplified) {
      // Pixel centres (minus the frame offset); image rows grow downwards, y grows upwards.
      const Eigen::Vector2d v(options.origin_m.x() + (p.x - 1 + 0.5) * res,
                              options.origin_m.y() + (rows - (p.y - 1) - 0.5) * res);
      if (loop.vertices.empty() || loop.vertices.back() != v) loop.vertices.push_back(v);
    }
    if (loop.vertices.size() >= 2 && loop.vertices.front() == loop.vertices.back())
      loop.vertices.pop_back();
    if (loop.vertices.size() == 1) {
      // A single dark pixel: a square of walls around its centre.
      const Eigen::Vector2d c = loop.vertices[0];
      const double h = 0.5 * res;
      loop.vertices = {c + Eigen::Vector2d(-h, -h), c + Eigen::Vector2d(h, -h),
                       c + Eigen::Vector2d(h, h), c + Eigen::Vector2d(-h, h)};
    }
    if (loop.vertices.size() >= 3)
      loop.vertices.push_back(loop.vertices.front());  // close the loop
    world.obstacles.push_back(std::move(loop));
  }
  if (world.obstacles.empty()) {
    return R::Fail(FileError(path, 0,
                             "no dark pixels (below grey level " +
                                 std::to_string(options.dark_threshold) + "): the world is empty"));
  }
  return R::Ok(std::move(world));
}

}  // namespace splam::io
