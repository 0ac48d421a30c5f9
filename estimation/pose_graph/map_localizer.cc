#include "estimation/pose_graph/map_localizer.h"

#include <cassert>
#include <cmath>
#include <utility>

#include "estimation/pose_graph/correlative_matcher.h"
#include "estimation/pose_graph/global_localizer.h"
#include "estimation/pose_graph/keyframes.h"
#include "estimation/pose_graph/scan_registration.h"

namespace splam::estimation {
std::vector<OrientedPoint> MapScanPoints(const kernel::Scan& scan,
                                         const kernel::Pose2& robot_T_laser,
                                         const FrontEndOptions& options) {
  const double range = options.max_range_m > 0 ? options.max_range_m : scan.max_range_m;
  return OrientTowards(robot_T_laser * scan.Clipped(range).HitPoints(), robot_T_laser.translation(),
                       options.normal_max_gap_m, options.advanced.line_tolerance_m);
}

MapLocalizer::MapLocalizer(std::vector<MapScan> map, const kernel::Pose2& start,
                           const FrontEndOptions& options,
                           const MapLocalizationOptions& localization)
    : map_(std::move(map)), options_(options), localization_(localization), pose_(start) {
  assert(!map_.empty());
  for (const MapScan& s : map_)
    world_points_.push_back(Placed(s.pose, MapScanPoints(s.scan, s.robot_T_laser, options_)));
}

MapLocalizer::~MapLocalizer() = default;

void MapLocalizer::Predict(const kernel::Pose2& odometry_increment) {
  pose_ = pose_ * odometry_increment;
  since_update_ = since_update_ * odometry_increment;
}

// The field of the map scans within map_radius_m of the robot, built again once the robot is
// rebuild_distance_m from where it was built (or none was near then).
void MapLocalizer::UpdateGrid() {
  const MapLocalizationOptions& o = localization_;
  if (grid_built_ && (pose_.translation() - grid_center_).norm() < o.rebuild_distance_m) return;
  std::vector<OrientedPoint> points;
  for (std::size_t i = 0; i < map_.size(); ++i) {
    if ((map_[i].pose.translation() - pose_.translation()).norm() > o.map_radius_m) continue;
    points.insert(points.end(), world_points_[i].begin(), world_points_[i].end());
  }
  grid_center_ = pose_.translation();
  grid_built_ = !points.empty();
  if (!grid_built_) return;
  grid_ = DistanceGrid::Build(points, options_.grid_resolution_m, options_.truncation_m,
                              options_.truncation_m + localization_.rebuild_distance_m);
  scores_ = std::make_unique<LikelihoodPyramid>(grid_, localization_.sigma_m, localization_.levels);
  ++grid_builds_;
}

RegistrationResult MapLocalizer::Register(const std::vector<OrientedPoint>& points) {
  const FrontEndRegistration r = RegisterFrontEnd(
      points, grid_, [this]() -> const LikelihoodPyramid& { return *scores_; }, pose_,
      since_update_, options_);
  counts_.recovery_searches += r.searched;
  counts_.recovered += r.recovered;
  return r.result;
}

void MapLocalizer::Update(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser) {
  const std::vector<OrientedPoint> points = MapScanPoints(scan, robot_T_laser, options_);
  Track(points);
  ConfirmStart(points);
  poses_.push_back(pose_);
}

void MapLocalizer::ConfirmStart(const std::vector<OrientedPoint>& points) {
  const MapLocalizationOptions& o = localization_;
  const int scan = scans_++;
  if (confirmed_ || scan >= o.confirm_scans || scan % o.confirm_every_scans != 0) return;
  if (!global_) global_ = std::make_unique<GlobalLocalizer>(map_, options_, o.global);
  const GlobalFix fix = global_->Locate(points);
  if (!fix.found) return;  // ambiguous here: the next try sees other walls
  confirmed_ = true;
  const CorrelativeOptions distinct;
  if (Within(pose_, fix.pose, distinct.distinct_m, distinct.distinct_rad)) return;
  // The best pose in the whole map by a margin is elsewhere: the start given was wrong, and the
  // start search took a look-alike place or none. The scans so far move with the fix.
  const kernel::Pose2 correction = fix.pose * pose_.Inverse();
  for (kernel::Pose2& p : poses_) p = correction * p;
  pose_ = fix.pose;
  found_start_ = relocalized_ = true;
  grid_built_ = false;  // built anew around the fix
}

void MapLocalizer::Track(const std::vector<OrientedPoint>& points) {
  UpdateGrid();
  if (!grid_built_) {  // no map near: dead reckoning until the robot comes back into it
    ++counts_.fallbacks;
    since_update_ = kernel::Pose2();
    return;
  }
  ++counts_.registrations;
  RegistrationResult r = Register(points);
  if (first_) {
    // A start pose off by more than the registration's basin: where in the initial window the
    // first scan fits the map best. Only then: along a corridor the best score can lie a metre
    // from a start that was right.
    first_ = false;
    found_start_ = r.accepted;
    const MapLocalizationOptions& o = localization_;
    if (!r.accepted) {
      const CorrelativeMatch match =
          SearchCorrelative(Positions(points), *scores_, pose_, o.initial_window_m,
                            o.initial_window_rad, options_.registration.min_inlier_fraction, 1.0);
      if (match.found) {
        RegistrationOptions wide = options_.registration;
        wide.max_correction_m += o.initial_window_m;
        wide.max_correction_rad += o.initial_window_rad;
        r = RegisterPoints(points, grid_, match.pose, wide);
        found_start_ = r.accepted;
      }
    }
  }
  if (r.accepted)
    pose_ = r.pose;
  else
    ++counts_.fallbacks;
  since_update_ = kernel::Pose2();
}

}  // namespace splam::estimation
