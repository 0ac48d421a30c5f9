// Tutorial: from one laser scan to geometry. Segments, cubic B-splines with their control
// polygons, inflection points (circles) and corners (diamonds), and straight lines with their
// corners, drawn to SVG and PNG.
//
//   example_features --world complex --pose 9 5.5 0.3 --out complex_scan
//   example_features --log ../shared/datasets/intel.clf --index 500 --out intel_scan
//
// writes <out>-splines.{svg,png} and <out>-lines.{svg,png}.
#include <CLI/CLI.hpp>
#include <cstdio>

#include "io/carmen.h"
#include "io/render.h"
#include "io/world_file.h"
#include "kernel/lines.h"
#include "kernel/spline_extraction.h"
#include "sim/laser.h"
#include "sim/ray_caster.h"

namespace {

using splam::kernel::Pose2;
namespace io = splam::io;
namespace kernel = splam::kernel;

constexpr io::Rgb kRaw{0.6, 0.6, 0.6};
constexpr io::Rgb kSpline{0.10, 0.35, 0.85};
constexpr io::Rgb kControl{0.55, 0.70, 0.95};
constexpr io::Rgb kInflection{0.10, 0.65, 0.20};
constexpr io::Rgb kCorner{0.85, 0.15, 0.15};
constexpr io::Rgb kLine{0.0, 0.0, 0.0};
constexpr io::Rgb kSegmentColors[] = {{0.95, 0.45, 0.05}, {0.55, 0.25, 0.75}, {0.0, 0.6, 0.6}};

struct Input {
  kernel::Scan scan;
  Pose2 world_T_sensor;
  std::optional<splam::sim::World> world;
  std::string title;
};

int Fail(const std::string& message) {
  std::fprintf(stderr, "example_features: %s\n", message.c_str());
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"One scan to B-splines with features and to lines"};
  std::string world_name, log_path, out = "features", laser = "urg04lx";
  std::vector<double> pose = {9.0, 5.5, 0.3};
  int index = 0;
  app.add_option("--world", world_name, "Simulate the scan in this world (built-in name or file)");
  app.add_option("--pose", pose, "Sensor pose x y theta for --world")->expected(3);
  app.add_option("--laser", laser, "urg04lx or lms200")
      ->check(CLI::IsMember({"urg04lx", "lms200"}));
  app.add_option("--log", log_path, "Take the scan from this CARMEN log");
  app.add_option("--index", index, "Index of the scan in the log")->check(CLI::NonNegativeNumber);
  app.add_option("--out", out, "Prefix of the output pictures");
  CLI11_PARSE(app, argc, argv);

  // 1. One scan: simulated in a world, or read from a log.
  Input input;
  if (!log_path.empty()) {
    const io::CarmenReadResult read = io::ReadCarmenLog(log_path);
    if (!read.log.ok()) return Fail(read.log.error);
    const auto lasers = read.log.value->Lasers();
    if (static_cast<std::size_t>(index) >= lasers.size()) {
      return Fail(log_path + " has " + std::to_string(lasers.size()) + " scans; --index " +
                  std::to_string(index) + " is out of range");
    }
    input.scan = lasers[index]->scan;
    input.world_T_sensor = lasers[index]->laser_pose;
    input.title = log_path + " scan " + std::to_string(index);
  } else {
    io::Result<splam::sim::World> world =
        io::LoadWorld(world_name.empty() ? "complex" : world_name);
    if (!world.ok()) return Fail(world.error);
    input.world = std::move(world.value);
    input.world_T_sensor = Pose2(pose[0], pose[1], pose[2]);
    const splam::sim::RayCaster caster(*input.world);
    const splam::sim::LaserOptions options = laser == "lms200"
                                                 ? splam::sim::LaserOptions::Lms200()
                                                 : splam::sim::LaserOptions::Urg04lx();
    kernel::Random random(1);
    input.scan = splam::sim::SimulateLaser(caster, options, input.world_T_sensor, 0.0, &random);
    input.title = input.world->name + " (" + options.model + ") from (" +
                  std::to_string(pose[0]).substr(0, 4) + ", " +
                  std::to_string(pose[1]).substr(0, 4) + ")";
  }

  // 2. Geometry in the sensor frame: B-spline curves with features, and lines.
  const kernel::SplineExtractionOptions spline_options;
  const std::vector<kernel::SplineCurve> curves = kernel::ExtractCurves(input.scan, spline_options);
  const kernel::LineExtraction lines = kernel::ExtractLines(input.scan);
  int inflections = 0, corners = 0;
  for (const kernel::SplineCurve& c : curves) {
    for (const kernel::CurveFeature& f : c.features)
      (f.type == kernel::FeatureType::kCorner ? corners : inflections)++;
  }
  std::printf(
      "%s: %zu hits, %zu curves, %d inflection points, %d corners; %zu lines, %zu line corners\n",
      input.title.c_str(), input.scan.HitIndices().size(), curves.size(), inflections, corners,
      lines.lines.size(), lines.corners.size());

  // 3. Pictures in the world frame (the log's odometric frame for real data).
  const Pose2& T = input.world_T_sensor;
  const std::vector<Eigen::Vector2d> raw = T * input.scan.HitPoints();
  kernel::Box2 area;
  for (const Eigen::Vector2d& p : raw) area.Extend(p);
  area.Extend(T.translation());
  if (area.IsEmpty()) return Fail("the scan has no hits");
  auto start_figure = [&](const std::string& what) {
    io::FigureOptions options;
    options.title = input.title + ": " + what;
    options.pixels_per_meter = 120.0;
    options.max_pixels = 1600;
    auto figure = std::make_unique<io::Figure>(area, options);
    if (input.world) figure->DrawWorld(*input.world, io::Rgb{0.8, 0.8, 0.8}, "world");
    figure->DrawPoints(raw, kRaw, 1.2, "raw points");
    figure->DrawRobot(T, 0.267, io::palette::kTrue);
    return figure;
  };

  auto splines = start_figure("segments, B-splines, features");
  for (std::size_t i = 0; i < curves.size(); ++i) {
    splines->DrawPoints(T * curves[i].points, kSegmentColors[i % 3], 1.6,
                        i < 3 ? "segment " + std::to_string(i + 1) : "");
  }
  std::vector<Eigen::Vector2d> inflection_points, corner_points;
  for (const kernel::SplineCurve& c : curves) {
    splines->DrawPolyline(T * c.spline.control_points(), kControl, 1.0, "control polygon", true);
    splines->DrawPolyline(T * c.samples, kSpline, 2.0, "B-spline");
    for (const kernel::CurveFeature& f : c.features) {
      (f.type == kernel::FeatureType::kCorner ? corner_points : inflection_points)
          .push_back(T * f.position);
    }
  }
  splines->DrawMarkers(inflection_points, io::Figure::Marker::kCircle, kInflection, 6.0,
                       "inflection");
  splines->DrawMarkers(corner_points, io::Figure::Marker::kDiamond, kCorner, 7.0, "corner");

  auto line_figure = start_figure("lines (RANSAC + TLS) and corners");
  for (const kernel::LineFeature& l : lines.lines)
    line_figure->DrawPolyline({T * l.start, T * l.end}, kLine, 2.5, "line");
  std::vector<Eigen::Vector2d> line_corners;
  for (const kernel::LineCorner& c : lines.corners) line_corners.push_back(T * c.position);
  line_figure->DrawMarkers(line_corners, io::Figure::Marker::kDiamond, kCorner, 7.0, "corner");

  for (const auto& [figure, name] :
       {std::pair{splines.get(), "-splines"}, std::pair{line_figure.get(), "-lines"}}) {
    for (const char* ext : {".svg", ".png"}) {
      if (const kernel::Status error = figure->Save(out + name + ext); !error.ok())
        return Fail(error.message());
      std::printf("wrote %s%s%s\n", out.c_str(), name, ext);
    }
  }
  return 0;
}
