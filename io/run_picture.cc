#include "io/run_picture.h"

#include "kernel/spline_extraction.h"

#include <map>

#include "estimation/evaluation/metrics.h"
#include "io/plot.h"
#include "io/render.h"
#include "io/simulation_log.h"
#include "kernel/angle.h"

namespace splam::io {

std::vector<Eigen::Vector2d> ScanPointsInWorld(const io::CarmenLog& log, int every) {
  std::map<double, kernel::Pose2> truth;
  for (const io::TruePoseMessage* m : log.TruePoses())
    truth[m->stamp.ipc_timestamp_s] = m->true_pose;
  std::vector<Eigen::Vector2d> points;
  const auto lasers = log.Lasers();
  for (std::size_t i = 0; i < lasers.size(); i += static_cast<std::size_t>(std::max(every, 1))) {
    const io::LaserMessage& m = *lasers[i];
    kernel::Pose2 world_T_laser = m.laser_pose;
    if (const auto it = truth.find(m.stamp.ipc_timestamp_s); it != truth.end()) {
      world_T_laser = it->second * m.robot_pose.Between(m.laser_pose);
    }
    for (const Eigen::Vector2d& p : m.scan.HitPoints()) points.push_back(world_T_laser * p);
  }
  return points;
}

kernel::Status SaveRunPicture(const RunPicture& picture, const std::vector<std::string>& paths) {
  kernel::Box2 area;
  if (picture.world != nullptr) area.Extend(picture.world->Bounds());
  auto extend = [&](const io::Trajectory& t) {
    for (const io::StampedPose& p : t) area.Extend(p.pose.translation());
  };
  extend(picture.truth);
  for (const auto& [label, t] : picture.estimates) extend(t);
  for (const Eigen::Vector2d& p : picture.scan_points) area.Extend(p);
  for (const auto& [a, b] : picture.map_segments) area.Extend(a), area.Extend(b);
  for (const auto& curve : picture.map_curves)
    for (const Eigen::Vector2d& p : curve) area.Extend(p);
  if (area.IsEmpty()) extend(picture.odometry);
  if (area.IsEmpty()) area = kernel::Box2{Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, 1)};

  io::FigureOptions options;
  options.title = picture.title;
  options.pixels_per_meter = picture.pixels_per_meter;
  io::Figure figure(area, options);
  if (!picture.scan_points.empty())
    figure.DrawPoints(picture.scan_points, io::palette::kScan, 0.9, "laser hits");
  if (picture.world != nullptr) {
    figure.DrawWorld(*picture.world, picture.world_color);
    for (const sim::Walker& w : picture.world->people)
      figure.DrawPolyline(w.path, io::palette::kPeople, 1.0, "people's walks", /*dashed=*/true);
  }
  for (const auto& [a, b] : picture.map_segments)
    figure.DrawPolyline({a, b}, io::palette::kMap, 2.5, "map lines");
  for (const auto& curve : picture.map_curves)
    figure.DrawPolyline(curve, io::palette::kMap, 2.5, "map splines");
  figure.DrawPoints(picture.map_control_points, io::palette::kMap, 1.5, "control points");
  figure.DrawMarkers(picture.map_inflections, io::Figure::Marker::kCircle, io::palette::kMap, 5.0,
                     "inflection points");
  figure.DrawMarkers(picture.map_corners, io::Figure::Marker::kDiamond, io::palette::kMap, 5.0,
                     "map corners");
  for (const auto& [a, b] : picture.graph_loops)
    figure.DrawPolyline({a, b}, io::palette::kGraph, 0.8, "loop closures");
  for (const auto& [a, b] : picture.dropped_loops)
    figure.DrawPolyline({a, b}, io::palette::kDropped, 0.8, "closures dropped");
  figure.DrawPoints(picture.graph_nodes, io::palette::kGraph, 1.5, "keyframes");
  figure.DrawMarkers(picture.consistent_scans, io::Figure::Marker::kCircle, io::palette::kTrue, 3.0,
                     "scans that agree with other passes");
  figure.DrawMarkers(picture.inconsistent_scans, io::Figure::Marker::kDiamond,
                     io::palette::kDropped, 7.0, "scans that contradict other passes");
  figure.DrawPath(io::Poses(picture.odometry), io::palette::kOdometry, 1.5, "odometry");
  figure.DrawPath(io::Poses(picture.before_optimization), io::palette::kOnline, 1.5,
                  "before optimisation");
  // The estimates on top: where they leave the truth is what a reader looks for.
  figure.DrawPath(io::Poses(picture.truth), io::palette::kTrue, 1.5, "ground truth");
  for (const auto& [label, t] : picture.estimates)
    figure.DrawPath(io::Poses(t), io::palette::kEstimate, 1.5, label);
  if (picture.robot_radius_m > 0.0) {
    const io::Trajectory& last = !picture.truth.empty() ? picture.truth : picture.odometry;
    if (!last.empty())
      figure.DrawRobot(last.back().pose, picture.robot_radius_m, io::palette::kTrue);
  }
  for (const std::string& path : paths) {
    if (kernel::Status error = figure.Save(path); !error.ok()) return error;
  }
  return {};
}

// Writes x, y and theta errors over time of each trajectory against the truth.
kernel::Status SaveErrorPlot(
    const std::string& title, const kernel::Trajectory& truth,
    const std::vector<std::tuple<std::string, io::Rgb, kernel::Trajectory>>& runs,
    const std::vector<std::string>& paths) {
  std::vector<io::PlotPanel> panels = {
      {"x error (m)", {}}, {"y error (m)", {}}, {"theta error (deg)", {}}};
  for (const auto& [label, color, trajectory] : runs) {
    const evaluation::TrajectoryError e = evaluation::CompareToTruth(truth, trajectory);
    std::vector<double> deg;
    for (double a : e.error_theta_rad) deg.push_back(kernel::RadToDeg(a));
    panels[0].series.push_back({label, color, e.time_s, e.error_x_m});
    panels[1].series.push_back({label, color, e.time_s, e.error_y_m});
    panels[2].series.push_back({label, color, e.time_s, deg});
  }
  io::PlotOptions options;
  options.title = title;
  options.x_label = "time (s)";
  return io::SavePlot(panels, options, paths);
}

void DrawMap(const estimation::SlamMap& map, RunPicture* picture) {
  for (const estimation::MapLine& l : map.lines) picture->map_segments.push_back({l.start, l.end});
  for (const estimation::MapCorner& c : map.corners) picture->map_corners.push_back(c.position);
  for (const estimation::MapSpline& s : map.splines) {
    const kernel::SplineCurve curve = kernel::DescribeCurve(s.spline, map.spline_features);
    picture->map_curves.push_back(curve.samples);
    for (const Eigen::Vector2d& p : s.spline.control_points())
      picture->map_control_points.push_back(p);
    for (const kernel::CurveFeature& f : curve.features) {
      (f.type == kernel::FeatureType::kCorner ? picture->map_corners : picture->map_inflections)
          .push_back(f.position);
    }
  }
  for (const kernel::Pose2& k : map.keyframes) picture->graph_nodes.push_back(k.translation());
  for (const auto& [a, b] : map.loop_edges) {
    picture->graph_loops.emplace_back(map.keyframes[static_cast<std::size_t>(a)].translation(),
                                      map.keyframes[static_cast<std::size_t>(b)].translation());
  }
  for (const estimation::LoopSearch& s : map.loop_searches) {
    if (s.outcome != estimation::LoopSearch::Outcome::kUnconfirmed &&
        s.outcome != estimation::LoopSearch::Outcome::kUndone)
      continue;
    picture->dropped_loops.emplace_back(
        map.keyframes[static_cast<std::size_t>(s.target)].translation(),
        map.keyframes[static_cast<std::size_t>(s.query)].translation());
  }
}

}  // namespace splam::io
