#include "io/occupancy_grid_file.h"

#include <fmt/core.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "io/internal/image.h"
#include "io/render.h"
#include "io/text.h"
#include "io/trajectory.h"

namespace splam::io {
namespace {

using estimation::CellState;
using estimation::OccupancyGrid;

constexpr unsigned char kOccupiedPixel = 0, kFreePixel = 254, kUnknownPixel = 205;

// The grid as an image, top row first: one grey value per cell from `value(x, y)`.
template <class Value>
cv::Mat GridImage(const OccupancyGrid& grid, Value value) {
  cv::Mat image(grid.height(), grid.width(), CV_8U);
  for (int y = 0; y < grid.height(); ++y)
    for (int x = 0; x < grid.width(); ++x)
      image.at<unsigned char>(grid.height() - 1 - y, x) = value(x, y);
  return image;
}

// A key of the map_server YAML file as a finite number; errors name the file and line.
Result<double> Number(const std::string& path, const YAML::Node& map, const char* key) {
  const YAML::Node node = map[key];
  if (!node) return Result<double>::Fail(FileError(path, 0, fmt::format("no '{}' key", key)));
  const int line = node.Mark().line + 1;
  double value = 0.0;
  if (!node.IsScalar() || !YAML::convert<double>::decode(node, value) || !std::isfinite(value))
    return Result<double>::Fail(
        FileError(path, line, fmt::format("'{}' must be a finite number", key)));
  return Result<double>::Ok(value);
}

}  // namespace

kernel::Status WriteOccupancyGrid(const OccupancyGrid& grid, const std::string& yaml_path,
                                  const estimation::OccupancyGridOptions& thresholds) {
  const std::filesystem::path pgm = std::filesystem::path(yaml_path).replace_extension(".pgm");
  const cv::Mat image = GridImage(grid, [&](int x, int y) {
    switch (grid.State(x, y, thresholds.occupied_threshold, thresholds.free_threshold)) {
      case CellState::kOccupied:
        return kOccupiedPixel;
      case CellState::kFree:
        return kFreePixel;
      default:
        return kUnknownPixel;
    }
  });
  // Encoded in memory, written by WriteTextFile: cv::imwrite reports success for a file a full
  // disk cut short.
  std::vector<unsigned char> encoded;
  if (!cv::imencode(".pgm", image, encoded, {cv::IMWRITE_PXM_BINARY, 1}))
    return FileError(pgm.string(), 0, "cannot encode the grid as PGM");
  if (kernel::Status e = WriteTextFile(pgm.string(), std::string(encoded.begin(), encoded.end()));
      !e.ok())
    return e;
  return WriteTextFile(
      yaml_path,
      fmt::format("image: {}\nmode: trinary\nresolution: {}\norigin: [{}, {}, 0.0]\nnegate: 0\n"
                  "occupied_thresh: {}\nfree_thresh: {}\n",
                  pgm.filename().string(), FormatDouble(grid.resolution_m()),
                  FormatDouble(grid.origin().x()), FormatDouble(grid.origin().y()),
                  FormatDouble(thresholds.occupied_threshold),
                  FormatDouble(thresholds.free_threshold)));
}

Result<OccupancyGrid> ReadOccupancyGrid(const std::string& yaml_path) {
  using R = Result<OccupancyGrid>;
  YAML::Node root;
  try {
    root = YAML::LoadFile(yaml_path);
  } catch (const YAML::BadFile&) {
    return R::Fail(FileError(yaml_path, 0, "cannot open"));
  } catch (const YAML::Exception& e) {
    return R::Fail(FileError(yaml_path, e.mark.line + 1, e.msg));
  }
  if (!root.IsMap()) return R::Fail(FileError(yaml_path, 0, "not a map_server YAML map"));
  const YAML::Node image_key = root["image"];
  if (!image_key || !image_key.IsScalar() || image_key.Scalar().empty())
    return R::Fail(FileError(yaml_path, 0, "no 'image' key naming the map's image"));
  const Result<double> resolution = Number(yaml_path, root, "resolution");
  if (!resolution.ok()) return R::Fail(resolution.error);
  if (!(*resolution.value > 0))
    return R::Fail(
        FileError(yaml_path, root["resolution"].Mark().line + 1, "'resolution' must be positive"));
  const YAML::Node origin = root["origin"];
  if (!origin || !origin.IsSequence() || origin.size() != 3)
    return R::Fail(
        FileError(yaml_path, origin ? origin.Mark().line + 1 : 0, "'origin' must be [x, y, yaw]"));
  double o[3];
  for (std::size_t i = 0; i < 3; ++i)
    if (!origin[i].IsScalar() || !YAML::convert<double>::decode(origin[i], o[i]) ||
        !std::isfinite(o[i]))
      return R::Fail(
          FileError(yaml_path, origin.Mark().line + 1, "'origin' must be three finite numbers"));
  if (o[2] != 0.0)
    return R::Fail(FileError(yaml_path, origin.Mark().line + 1,
                             "a rotated map (yaw other than 0) is not supported"));
  double occupied = 0.65, free = 0.196;
  for (auto [key, value] : {std::pair{"occupied_thresh", &occupied}, {"free_thresh", &free}}) {
    const Result<double> read = Number(yaml_path, root, key);
    if (!read.ok()) return R::Fail(read.error);
    *value = *read.value;
  }
  if (!(0 <= free && free < occupied && occupied <= 1))
    return R::Fail(FileError(yaml_path, 0, "need 0 <= free_thresh < occupied_thresh <= 1"));
  bool negate = false;
  if (const YAML::Node n = root["negate"]; n) {
    int value = 0;
    if (!n.IsScalar() || !YAML::convert<int>::decode(n, value) || (value != 0 && value != 1))
      return R::Fail(FileError(yaml_path, n.Mark().line + 1, "'negate' must be 0 or 1"));
    negate = value == 1;
  }
  std::string mode = "trinary";
  if (const YAML::Node m = root["mode"]; m) {
    mode = m.IsScalar() ? m.Scalar() : "";
    if (mode != "trinary" && mode != "scale" && mode != "raw")
      return R::Fail(
          FileError(yaml_path, m.Mark().line + 1, "'mode' must be trinary, scale or raw"));
  }
  std::filesystem::path image_path = image_key.Scalar();
  if (image_path.is_relative())
    image_path = std::filesystem::path(yaml_path).parent_path() / image_path;
  Result<cv::Mat> image = internal::ReadGreyImage(image_path.string());
  if (!image.ok()) return R::Fail(image.error);
  const cv::Mat& pixels = *image.value;
  OccupancyGrid grid({o[0], o[1]}, *resolution.value, pixels.cols, pixels.rows);
  const auto logit = [](double p) {
    p = std::clamp(p, 0.01, 0.99);
    return static_cast<float>(std::log(p / (1 - p)));
  };
  for (int row = 0; row < pixels.rows; ++row) {
    for (int x = 0; x < pixels.cols; ++x) {
      const int v = pixels.at<unsigned char>(row, x);
      const int y = pixels.rows - 1 - row;
      if (mode == "raw") {  // the value is the occupancy in per cent, 255 unknown
        if (v <= 100) grid.Set(x, y, logit(v / 100.0));
        continue;
      }
      const double p = negate ? v / 255.0 : (255 - v) / 255.0;
      if (p > occupied) {
        grid.Set(x, y, logit(mode == "trinary" ? 1.0 : p));
      } else if (p < free) {
        grid.Set(x, y, logit(mode == "trinary" ? 0.0 : p));
      } else if (mode == "scale") {
        grid.Set(x, y, logit(p));  // observed, undecided
      }
    }
  }
  return R::Ok(std::move(grid));
}

kernel::Status SaveOccupancyGridPicture(const OccupancyGrid& grid,
                                        const estimation::OccupancyGridOptions& thresholds,
                                        const std::string& title, const kernel::Trajectory& path,
                                        const std::vector<std::string>& files) {
  const kernel::Box2 area{
      grid.origin(),
      grid.origin() + grid.resolution_m() * Eigen::Vector2d(grid.width(), grid.height())};
  FigureOptions options;
  options.title = title;
  options.margin_m = 0.0;
  // Whole pixels per cell, the picture about 1600 px on its long side (Figure caps at 4000).
  const int cells = std::max(grid.width(), grid.height());
  options.pixels_per_meter = std::max(1, 1600 / std::max(cells, 1)) / grid.resolution_m();
  Figure figure(area, options);
  std::vector<Rgb8> pixels(static_cast<std::size_t>(grid.width()) *
                           static_cast<std::size_t>(grid.height()));
  bool undecided = false;
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      std::uint8_t v = kUnknownPixel;
      switch (grid.State(x, y, thresholds.occupied_threshold, thresholds.free_threshold)) {
        case CellState::kOccupied:
          v = 0;
          break;
        case CellState::kFree:
          v = 255;
          break;
        case CellState::kUnknown:
          if (grid.observed(x, y)) {
            v = static_cast<std::uint8_t>(std::lround(255 * (1 - grid.Probability(x, y))));
            undecided = true;
          }
          break;
      }
      pixels[static_cast<std::size_t>(grid.height() - 1 - y) *
                 static_cast<std::size_t>(grid.width()) +
             static_cast<std::size_t>(x)] = {v, v, v};
    }
  }
  figure.DrawRaster(pixels, grid.width(), grid.height(), area);
  figure.AddLegend(fmt::format("occupied (p > {:g})", thresholds.occupied_threshold), {0, 0, 0});
  figure.AddLegend(fmt::format("free (p < {:g})", thresholds.free_threshold), {1, 1, 1});
  figure.AddLegend("unknown",
                   {kUnknownPixel / 255.0, kUnknownPixel / 255.0, kUnknownPixel / 255.0});
  if (undecided) figure.AddLegend("observed, undecided (grey by p)", {0.5, 0.5, 0.5});
  std::vector<Eigen::Vector2d> positions;
  for (const kernel::StampedPose& p : path) positions.push_back(p.pose.translation());
  // Not black (the walls) nor blue (ground truth in every splam picture).
  figure.DrawPolyline(positions, Rgb{0.9, 0.25, 0.1}, 1.5, "estimate");
  std::vector<kernel::Status> errors;
  for (const std::string& file : files) errors.push_back(figure.Save(file));
  return kernel::FirstError(errors);
}

}  // namespace splam::io
