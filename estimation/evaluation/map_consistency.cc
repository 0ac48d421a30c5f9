#include "estimation/evaluation/map_consistency.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "estimation/pose_graph/distance_grid.h"
#include "estimation/pose_graph/graph_slam.h"
#include "estimation/pose_graph/scan_view.h"

namespace splam::evaluation {

using estimation::DistanceGrid;
using estimation::OrientedPoint;
using estimation::OrientTowards;
using estimation::ScanView;
using estimation::SeenFreeMisfitFraction;

kernel::Status ConsistencyOptions::Validate() const {
  if (!(scan_spacing_m > 0) || !(reference_radius_m > 0) || !(min_path_gap_m >= 0) ||
      max_references < 1 || !(max_range_m > 0) || !(resolution_m > 0) || !(seen_margin_m >= 0) ||
      !(inlier_distance_m > 0) || !(inconsistent_share >= 0 && inconsistent_share <= 1) ||
      !(flag_share >= 0 && flag_share <= 1))
    return kernel::Status::Error(
        "consistency: spacings, radius, range, resolution and inlier distance must be positive, "
        "max_references >= 1, inconsistent_share and flag_share in [0, 1]");
  return kernel::Status::Ok();
}

ConsistencyReport CheckMapConsistency(const std::vector<PlacedScan>& scans,
                                      const ConsistencyOptions& options) {
  // The scans checked (and used as references), one per scan_spacing_m of travel, with their
  // hits (world frame, oriented) and views.
  struct Sample {
    int index;
    double travelled;
    std::vector<OrientedPoint> points;
    std::vector<Eigen::Vector2d> view;
  };
  std::vector<Sample> samples;
  double travelled = 0.0, last = -1e300;
  for (std::size_t i = 0; i < scans.size(); ++i) {
    if (i > 0) travelled += (scans[i].pose.translation() - scans[i - 1].pose.translation()).norm();
    if (scans[i].scan == nullptr || travelled - last < options.scan_spacing_m) continue;
    last = travelled;
    const kernel::Scan clipped = scans[i].scan->Clipped(options.max_range_m);
    const kernel::Pose2 world_T_laser = scans[i].pose * scans[i].robot_T_laser;
    samples.push_back(
        {static_cast<int>(i), travelled,
         OrientTowards(world_T_laser * clipped.HitPoints(), world_T_laser.translation(), 0.3),
         scans[i].pose * ScanView(clipped, scans[i].robot_T_laser, options.max_range_m,
                                  options.seen_margin_m)});
  }
  ConsistencyReport report;
  double sum = 0.0;
  for (const Sample& s : samples) {
    if (s.points.empty()) continue;
    const Eigen::Vector2d at = scans[static_cast<std::size_t>(s.index)].pose.translation();
    std::vector<std::pair<double, const Sample*>> near;
    for (const Sample& r : samples) {
      const double d = (scans[static_cast<std::size_t>(r.index)].pose.translation() - at).norm();
      if (d <= options.reference_radius_m &&
          std::abs(r.travelled - s.travelled) >= options.min_path_gap_m)
        near.emplace_back(d, &r);
    }
    if (near.empty()) continue;
    std::sort(near.begin(), near.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    if (static_cast<int>(near.size()) > options.max_references)
      near.resize(static_cast<std::size_t>(options.max_references));
    std::vector<OrientedPoint> outline;
    std::vector<std::vector<Eigen::Vector2d>> views;
    for (const auto& [d, r] : near) {
      outline.insert(outline.end(), r->points.begin(), r->points.end());
      views.push_back(r->view);
    }
    const DistanceGrid grid =
        DistanceGrid::Build(outline, options.resolution_m, 2 * options.inlier_distance_m,
                            2 * options.inlier_distance_m, views, false, options.seen_margin_m);
    const double share = SeenFreeMisfitFraction(grid, s.points, options.inlier_distance_m);
    report.checked.push_back({s.index, at, static_cast<int>(near.size()), share});
    sum += share;
    report.inconsistent += share > options.inconsistent_share;
  }
  report.scans_checked = static_cast<int>(report.checked.size());
  if (report.scans_checked > 0) {
    report.mean_contradicting = sum / report.scans_checked;
    report.inconsistent_share = static_cast<double>(report.inconsistent) / report.scans_checked;
    report.flagged = report.inconsistent_share > options.flag_share;
  }
  return report;
}

}  // namespace splam::evaluation
