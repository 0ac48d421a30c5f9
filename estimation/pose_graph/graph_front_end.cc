#include "estimation/pose_graph/graph_front_end.h"

#include <fmt/core.h>

#include <algorithm>
#include <cassert>
#include <cmath>

#include "estimation/pose_graph/scan_view.h"
#include "kernel/angle.h"

namespace splam::estimation {
namespace {

// How much farther than its keyframes' outline a submap's grid reaches at most, for the keyframes
// inserted into it (FrontEndOptions::Advanced::submap_insert_keyframes), m.
constexpr double kMaxSubmapRoom_m = 5.0;

}  // namespace

FrontEndRegistration RegisterFrontEnd(const std::vector<OrientedPoint>& points,
                                      const DistanceGrid& field,
                                      const std::function<const LikelihoodPyramid&()>& scores,
                                      const kernel::Pose2& predicted,
                                      const kernel::Pose2& odometry_since,
                                      const FrontEndOptions& options) {
  FrontEndRegistration out;
  RegistrationResult& r = out.result;
  r = RegisterPoints(points, field, predicted, options.registration);
  if (options.odometry_prior) {
    // The odometry increment (its covariance from the noise model) is either right, the prior of
    // the fused registration, or an outlier (a slip, a glitch) and the scan alone stands
    // (OdometryIsInlier). Where the scan leaves a direction loose (a corridor's axis, a smooth
    // arc's length), the scan alone's optimum wanders along it at a cost a few units below the
    // fused pose's, and the odometry holds it. When the scan alone fails its test, the fused
    // pose still stands if it passes: a scan of one smooth wall slid 0.43 m along it, beyond
    // max_correction_m, and the recovery search below then took the slid pose (it fits as well).
    const Eigen::Matrix3d odometry = options.odometry.Covariance(odometry_since);
    RegistrationResult fused =
        RegisterPoints(points, field, predicted, options.registration, &odometry);
    if (r.accepted ? OdometryIsInlier(fused, r, options.advanced.odometry_outlier_probability)
                   : fused.accepted)
      r = std::move(fused);
  }
  const bool suspect = r.accepted && r.misfit_fraction > options.advanced.verify_misfit_fraction;
  if ((r.accepted && !suspect) || options.recovery_window_m <= 0) return out;
  // The odometry can be off by more than the registration's basin (wheel slip, a bump, a fast
  // turn): a correlative search around the prediction finds the basin, the registration refines
  // it. It replaces a failed registration when at least as many points lie near the map, a
  // suspect one only when more do and fewer contradict it.
  out.searched = true;
  const CorrelativeOptions search{.angular_step_rad = options.advanced.recovery_step_rad};
  const CorrelativeMatch match = SearchCorrelative(
      Positions(Thinned(points, options.grid_resolution_m)), scores(), predicted,
      options.recovery_window_m, options.recovery_window_rad,
      options.registration.min_inlier_fraction, options.advanced.recovery_ambiguity_ratio, search);
  if (!match.found) return out;
  // Nor when another heading fits about as well (a distinct peak within the loop closure's
  // ambiguity_ratio of the best) and the points do not tell the two apart (TellsApart): a scan
  // of a few points fits some wall at many headings. Exploring `complex` with SRT, a scan of 24
  // points, turning on the spot into unmapped space, failed its registration, and the search
  // took a pose 84 deg off the odometry's (score 0.63, a rival 131 deg from it 0.62); the run
  // ended 3.0 m off. Peaks at one heading (a corridor's axis: 133 such recoveries on MIT Killian
  // Court) are left to the registration and its odometry prior.
  if (match.second_score > 0 &&
      std::abs(kernel::WrapAngle(match.second_pose.theta() - match.pose.theta())) >
          search.distinct_rad &&
      !TellsApart(field, points, match.pose, match.second_pose, options.registration,
                  options.normal_max_gap_m, options.advanced.recovery_tell_apart_alpha))
    return out;
  RegistrationOptions wide = options.registration;
  wide.max_correction_m = options.recovery_window_m + wide.max_correction_m;
  wide.max_correction_rad = options.recovery_window_rad + wide.max_correction_rad;
  RegistrationResult recovered = RegisterPoints(points, field, match.pose, wide);
  if (!recovered.accepted || recovered.inlier_fraction < r.inlier_fraction) return out;
  // Nor when more of its points contradict what the submap saw free than the registration's did,
  // by more than a right pose leaves so (verify_misfit_fraction): however many points it puts
  // near the map, it is a wrong basin. Beside a round hall's wall, whose rotations about the
  // hall's centre all fit it, a registration with 49 % of its points near the map (one short of
  // the test) and none contradicting was replaced by a pose 16 deg and 0.67 m off that left 18 %
  // of the scan where the submap had seen free space (REG + graph in `halls`, seed 3: 0.53 m
  // RMSE). The scan then falls back to the odometry. Against the registration's own misfit, not
  // an absolute bound: mit-csail's odometry turns 10-70 deg wrong, and its right recoveries leave
  // up to 8 % contradicting where the registration left 4.5 % (an absolute 5 % cut three of them
  // and the log ended 0.28 m off).
  if (recovered.misfit_fraction - r.misfit_fraction > options.advanced.verify_misfit_fraction)
    return out;
  if (suspect && !(recovered.inlier_fraction > r.inlier_fraction &&
                   recovered.misfit_fraction < r.misfit_fraction))
    return out;
  recovered.covariance +=
      Diagonal(options.registration.prior_sigma_m, options.registration.prior_sigma_rad);
  r = std::move(recovered);
  out.recovered = true;
  return out;
}

Eigen::Matrix3d EdgeCovariance(const EdgeModel& model, double distance_m, double turn_rad) {
  return Diagonal(model.sigma_m + model.per_m * distance_m,
                  model.sigma_rad + model.per_rad * std::abs(turn_rad));
}

Eigen::Matrix3d KeyframeEdgeCovariance(const EdgeModel& model, const Keyframes& keyframes, int to) {
  assert(to >= 1 && to < static_cast<int>(keyframes.size()));
  const Keyframe& prev = keyframes[static_cast<std::size_t>(to - 1)];
  const Keyframe& kf = keyframes[static_cast<std::size_t>(to)];
  return EdgeCovariance(model, kf.travelled_m - prev.travelled_m,
                        prev.pose.Between(kf.pose).theta());
}

GraphFrontEnd::GraphFrontEnd(const kernel::Pose2& start, const FrontEndOptions& options,
                             Keyframes* keyframes, bool hit_views)
    : options_(options), keyframes_(keyframes), hit_views_(hit_views), pose_(start) {}

void GraphFrontEnd::Predict(const kernel::Pose2& odometry_increment) {
  pose_ = pose_ * odometry_increment;
  since_update_ = since_update_ * odometry_increment;
  travelled_m_ += odometry_increment.translation().norm();
}

GraphFrontEnd::PreparedScan GraphFrontEnd::Prepare(const kernel::Scan& scan,
                                                   const kernel::Pose2& robot_T_laser) const {
  PreparedScan prepared;
  prepared.reading = scan.Clipped(UsableRange(scan));
  prepared.points = ScanPoints(prepared.reading, robot_T_laser);
  return prepared;
}

std::optional<GraphFrontEnd::PreparedScan> GraphFrontEnd::Register(
    const kernel::Scan& scan, const kernel::Pose2& robot_T_laser) {
  if (!health_.ok()) return std::nullopt;
  PreparedScan prepared = Prepare(scan, robot_T_laser);
  registered_ = false;
  const kernel::Pose2 predicted = pose_;
  if (!keyframes_->empty()) {
    UpdateSubmap();
    if (!health_.ok()) return std::nullopt;
    const long recovered_before = counts_.recovered;
    const RegistrationResult r = RegisterScan(prepared.points);
    ++counts_.registrations;
    registered_ = r.accepted;
    recovered_since_keyframe_ |= r.accepted && counts_.recovered > recovered_before;
    if (r.accepted)
      pose_ = r.pose;
    else
      ++counts_.fallbacks;
  }
  if (registered_) LeaveOutMoving(robot_T_laser, predicted, true, &prepared);
  since_update_ = kernel::Pose2();
  return prepared;
}

std::optional<GraphFrontEnd::PreparedScan> GraphFrontEnd::Place(const kernel::Scan& scan,
                                                                const kernel::Pose2& robot_T_laser,
                                                                const kernel::Pose2& pose) {
  if (!health_.ok()) return std::nullopt;
  pose_ = pose;
  PreparedScan prepared = Prepare(scan, robot_T_laser);
  registered_ = false;
  LeaveOutMoving(robot_T_laser, pose_, false, &prepared);
  since_update_ = kernel::Pose2();
  return prepared;
}

void GraphFrontEnd::LeaveOutMoving(const kernel::Pose2& robot_T_laser,
                                   const kernel::Pose2& predicted, bool register_again,
                                   PreparedScan* scan) {
  // At the registered pose: at the prediction, a slip of the odometry puts the view beside
  // static things in the keyframes' scans.
  if (!options_.moving.enabled) return;
  const std::vector<std::size_t> moving = MovingBeams(scan->reading, robot_T_laser);
  if (moving.empty()) return;
  scan->reading = WithoutBeams(scan->reading, moving);
  scan->points = ScanPoints(scan->reading, robot_T_laser);
  if (!register_again) return;
  const kernel::Pose2 first = pose_;
  pose_ = predicted;
  const RegistrationResult again = RegisterScan(scan->points);
  pose_ = again.accepted ? again.pose : first;
}

bool GraphFrontEnd::Settle(const kernel::Pose2& pose) {
  pose_ = pose;
  if (std::isfinite(pose_.x() + pose_.y() + pose_.theta())) return true;
  health_ = kernel::Status::Error("the pose estimate is not finite");
  return false;
}

bool GraphFrontEnd::KeyframeDue() const {
  if (keyframes_->empty() || force_keyframe_) return true;
  const kernel::Pose2 motion = keyframes_->back().pose.Between(pose_);
  return motion.translation().norm() >= options_.keyframe_distance_m ||
         std::abs(motion.theta()) >= options_.keyframe_angle_rad;
}

Keyframe GraphFrontEnd::MakeKeyframe(PreparedScan scan, const kernel::Pose2& robot_T_laser,
                                     int scan_index, bool* robust_edge) {
  force_keyframe_ = false;
  *robust_edge = options_.advanced.robust_recovery_edges && recovered_since_keyframe_;
  recovered_since_keyframe_ = false;
  Keyframe kf;
  kf.pose = pose_;
  kf.travelled_m = travelled_m_;
  kf.scan = scan_index;
  kf.data = std::make_unique<Keyframe::Data>();
  kf.data->reading = std::move(scan.reading);
  kf.data->robot_T_laser = robot_T_laser;
  kf.in_map = std::none_of(keyframes_->begin(), keyframes_->end(), [&](const Keyframe& o) {
    return o.in_map && Within(o.pose, kf.pose, options_.map_spacing_m, options_.map_spacing_rad);
  });
  FillKeyframe(std::move(scan.points), &kf);
  return kf;
}

void GraphFrontEnd::KeyframeAdded(int k) {
  if (k < options_.moving_keyframes) return;
  const auto& data = (*keyframes_)[static_cast<std::size_t>(k - options_.moving_keyframes)].data;
  if (!data) return;
  data->reading = {};
  BeamRanges().swap(data->candidates);
}

std::vector<OrientedPoint> GraphFrontEnd::ScanPoints(const kernel::Scan& scan,
                                                     const kernel::Pose2& robot_T_laser) const {
  return OrientTowards(robot_T_laser * scan.HitPoints(), robot_T_laser.translation(),
                       options_.normal_max_gap_m, options_.advanced.line_tolerance_m);
}

double GraphFrontEnd::UsableRange(const kernel::Scan& scan) const {
  return options_.max_range_m > 0 ? options_.max_range_m : scan.max_range_m;
}

std::vector<std::size_t> GraphFrontEnd::MovingBeams(const kernel::Scan& scan,
                                                    const kernel::Pose2& robot_T_laser) {
  const ScopedTimer timer(&times_.moving_ms);
  const kernel::Pose2 world_T_laser = pose_ * robot_T_laser;
  std::vector<std::size_t> moving;
  const BeamRanges candidates = ForegroundObjects(scan, options_.moving);
  const std::size_t n = keyframes_->size();
  for (std::size_t i = n - std::min<std::size_t>(n, options_.moving_keyframes); i < n; ++i) {
    Keyframe& kf = (*keyframes_)[i];
    if (!kf.data || kf.data->reading.ranges_m.empty()) continue;
    Keyframe::Data& d = *kf.data;
    const kernel::Pose2 world_T_kf_laser = kf.pose * d.robot_T_laser;
    const std::vector<std::size_t> here = SeenThroughBeams(
        scan, candidates, world_T_laser, d.reading, world_T_kf_laser, options_.moving);
    moving.insert(moving.end(), here.begin(), here.end());
    const std::vector<std::size_t> there = SeenThroughBeams(
        d.reading, d.candidates, world_T_kf_laser, scan, world_T_laser, options_.moving);
    if (there.empty()) continue;
    d.reading = WithoutBeams(d.reading, there);
    FillKeyframe(ScanPoints(d.reading, d.robot_T_laser), &kf);
    moving_beams_ += static_cast<long>(there.size());
    submap_dirty_ = true;
  }
  std::sort(moving.begin(), moving.end());
  moving.erase(std::unique(moving.begin(), moving.end()), moving.end());
  moving_beams_ += static_cast<long>(moving.size());
  return moving;
}

void GraphFrontEnd::FillKeyframe(std::vector<OrientedPoint> points, Keyframe* kf) {
  Keyframe::Data& d = *kf->data;
  if (kf->in_map) {
    map_curves_ -= d.curves.size();
    for (const auto& c : d.curves) map_control_points_ -= c.spline.control_points().size();
  }
  d.curves.clear();
  d.raster.clear();
  if (options_.moving.enabled) d.candidates = ForegroundObjects(d.reading, options_.moving);
  for (const auto& curve : kernel::ExtractCurves(d.reading, options_.extraction)) {
    d.curves.push_back(kernel::Transformed(curve, d.robot_T_laser));
    if (!options_.advanced.raster_curves) continue;
    const auto samples = OrientTowards(d.curves.back().samples, d.robot_T_laser.translation(),
                                       options_.grid_resolution_m);
    d.raster.insert(d.raster.end(), samples.begin(), samples.end());
  }
  if (options_.advanced.raster_points || d.raster.empty()) {
    d.raster.insert(d.raster.end(), points.begin(), points.end());
    const std::vector<OrientedPoint> fill =
        FillLinkedGaps(points, options_.normal_max_gap_m, options_.advanced.line_tolerance_m,
                       options_.grid_resolution_m / 2);
    d.raster.insert(d.raster.end(), fill.begin(), fill.end());
  }
  // Curves are sampled every centimetre; a few samples per cell place it as well.
  d.raster = Thinned(d.raster, options_.grid_resolution_m / 2);
  d.points = std::move(points);
  d.rasters = {};  // the view changes
  d.seen =
      ScanView(d.reading, d.robot_T_laser, UsableRange(d.reading), options_.advanced.seen_margin_m);
  if (hit_views_)
    d.seen_by_hits = ScanView(d.reading, d.robot_T_laser, UsableRange(d.reading),
                              options_.advanced.seen_margin_m, false);
  if (kf->in_map) {
    map_curves_ += d.curves.size();
    for (const auto& c : d.curves) map_control_points_ += c.spline.control_points().size();
  } else {
    // Rasterised; with their centimetre samples they were most of a keyframe's memory.
    std::vector<kernel::SplineCurve>().swap(d.curves);
  }
}

void GraphFrontEnd::UpdateSubmap() {
  const int last = static_cast<int>(keyframes_->size()) - 1;
  if (!submap_dirty_ && submap_last_ == last) return;
  const ScopedTimer timer(&times_.submap_ms);
  const bool mask = options_.advanced.mask_unseen;
  const double resolution = options_.grid_resolution_m;
  if (!submap_dirty_ && options_.advanced.submap_insert_keyframes > 0 &&
      last - submap_first_ <
          options_.submap_keyframes + options_.advanced.submap_insert_keyframes) {
    bool fits = true;
    for (int i = submap_last_ + 1; i <= last && fits; ++i) {
      fits = submap_.Insert(
          WorldRaster(*keyframes_, {i}),
          mask ? ViewsOf(*keyframes_, {i}, 0, resolution, options_.advanced.seen_margin_m)
               : std::vector<const ViewCells*>{});
      submap_inserts_ += fits;
    }
    if (fits) {
      submap_last_ = last;
      submap_scores_.reset();
      return;
    }
  }
  const int first = std::max(0, last - options_.submap_keyframes + 1);
  // The keyframes that left the submap keep no raster of their view for it.
  for (int i = submap_first_; i < first; ++i)
    if (const auto& data = (*keyframes_)[static_cast<std::size_t>(i)].data) data->rasters[0] = {};
  std::vector<int> recent;
  for (int i = first; i <= last; ++i) recent.push_back(i);
  submap_ = DistanceGrid::Build(
      WorldRaster(*keyframes_, recent), resolution, options_.truncation_m,
      options_.truncation_m +
          std::min(options_.advanced.submap_insert_keyframes * options_.keyframe_distance_m,
                   kMaxSubmapRoom_m),
      mask ? ViewsOf(*keyframes_, recent, 0, resolution, options_.advanced.seen_margin_m)
           : std::vector<const ViewCells*>{},
      options_.advanced.signed_distance, {});
  ++submap_builds_;
  submap_first_ = first;
  submap_last_ = last;
  submap_scores_.reset();
  submap_dirty_ = false;
  if (submap_.too_large())
    health_ = kernel::Status::Error(fmt::format(
        "the submap's keyframes spread over {:.0f} m x {:.0f} m, more than a distance grid of {} "
        "cells holds at {} m (an odometry jump of that size?)",
        submap_.extent().x(), submap_.extent().y(), DistanceGrid::kMaxCells,
        options_.grid_resolution_m));
}

RegistrationResult GraphFrontEnd::RegisterScan(const std::vector<OrientedPoint>& points) {
  const ScopedTimer timer(&times_.registration_ms);
  const FrontEndRegistration r = RegisterFrontEnd(
      points, submap_,
      [this]() -> const LikelihoodPyramid& {
        if (!submap_scores_)
          submap_scores_ =
              std::make_unique<LikelihoodPyramid>(submap_, options_.advanced.recovery_sigma_m, 3);
        return *submap_scores_;
      },
      pose_, since_update_, options_);
  counts_.recovery_searches += r.searched;
  counts_.recovered += r.recovered;
  return r.result;
}

}  // namespace splam::estimation
