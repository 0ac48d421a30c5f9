#include "estimation/pose_graph/global_localizer.h"

#include <cassert>
#include <cmath>

#include "estimation/pose_graph/correlative_matcher.h"
#include "estimation/pose_graph/keyframes.h"
#include "estimation/pose_graph/map_localizer.h"
#include "estimation/pose_graph/scan_registration.h"
#include "estimation/pose_graph/scan_view.h"
#include "kernel/angle.h"

namespace splam::estimation {

std::vector<OrientedPoint> StretchPoints(const std::vector<MapScan>& scans,
                                         const FrontEndOptions& front_end) {
  std::vector<OrientedPoint> points;
  if (scans.empty()) return points;
  const kernel::Pose2 last_inverse = scans.back().pose.Inverse();
  for (const MapScan& s : scans) {
    const std::vector<OrientedPoint> placed =
        Placed(last_inverse * s.pose, MapScanPoints(s.scan, s.robot_T_laser, front_end));
    points.insert(points.end(), placed.begin(), placed.end());
  }
  return points;
}

GlobalLocalizer::GlobalLocalizer(const std::vector<MapScan>& map, const FrontEndOptions& front_end,
                                 const GlobalLocalizationOptions& options)
    : front_end_(front_end), options_(options) {
  assert(!map.empty());
  std::vector<OrientedPoint> points;
  std::vector<std::vector<Eigen::Vector2d>> seen, seen_by_hits;
  const double margin = front_end_.advanced.seen_margin_m;
  for (const MapScan& s : map) {
    const std::vector<OrientedPoint> placed =
        Placed(s.pose, MapScanPoints(s.scan, s.robot_T_laser, front_end_));
    points.insert(points.end(), placed.begin(), placed.end());
    const double range = front_end_.max_range_m > 0
                             ? std::min(front_end_.max_range_m, s.scan.max_range_m)
                             : s.scan.max_range_m;
    seen.push_back(s.pose * ScanView(s.scan, s.robot_T_laser, range, margin));
    seen_by_hits.push_back(s.pose * ScanView(s.scan, s.robot_T_laser, range, margin, false));
  }
  grid_ = DistanceGrid::Build(Thinned(points, options_.resolution_m / 2), options_.resolution_m,
                              front_end_.truncation_m, front_end_.truncation_m, seen, false, margin,
                              seen_by_hits);
  pyramid_ =
      std::make_unique<LikelihoodPyramid>(grid_, options_.sigma_m, options_.levels,
                                          options_.seen_free_score, 3 * options_.resolution_m);
}

GlobalLocalizer::~GlobalLocalizer() = default;

GlobalFix GlobalLocalizer::Locate(const kernel::Scan& scan,
                                  const kernel::Pose2& robot_T_laser) const {
  return Locate(MapScanPoints(scan, robot_T_laser, front_end_));
}

GlobalFix GlobalLocalizer::Locate(const std::vector<OrientedPoint>& points) const {
  GlobalFix fix;
  std::vector<OrientedPoint> query;
  for (const OrientedPoint& p : Thinned(points, options_.resolution_m))
    if (p.point.norm() <= options_.max_range_m) query.push_back(p);
  if (query.size() < static_cast<std::size_t>(front_end_.registration.min_points) ||
      grid_.empty()) {
    fix.refused = "points";
    return fix;
  }
  // The whole field: a window about its centre that reaches every cell, every heading.
  const Eigen::Vector2d size(grid_.cols() * grid_.resolution(), grid_.rows() * grid_.resolution());
  const kernel::Pose2 centre(grid_.origin() + size / 2, 0.0);
  const CorrelativeMatch match =
      SearchCorrelative(Positions(query), *pyramid_, centre, size.maxCoeff() / 2, kernel::kPi,
                        options_.min_score, options_.ambiguity_ratio);
  fix.evaluated = match.evaluated;
  fix.score = match.score;
  fix.second_score = match.second_score;
  fix.second_pose = match.second_pose;
  fix.pose = match.pose;
  if (!match.found) {
    fix.refused = "score";
    return fix;
  }
  if (match.second_score > 0 &&
      !TellsApart(grid_, query, match.pose, match.second_pose, front_end_.registration,
                  front_end_.normal_max_gap_m, options_.tell_apart_alpha)) {
    fix.refused = "ambiguous";
    return fix;
  }
  RegistrationOptions fine = front_end_.registration;
  fine.max_correction_m = std::max(fine.max_correction_m, 2 * options_.resolution_m);
  const RegistrationResult r = RegisterPoints(points, grid_, match.pose, fine);
  if (!r.accepted) {
    fix.refused = "registration";
    return fix;
  }
  fix.found = true;
  fix.pose = r.pose;
  return fix;
}

}  // namespace splam::estimation
