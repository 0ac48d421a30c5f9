#include "apps/slam_methods.h"

#include <fmt/core.h>

#include <algorithm>

#include "io/map_export.h"

namespace splam::apps {
namespace {

// map.txt and map.dxf of a spline map; the errors, if any.
std::vector<std::string> WriteSplineMap(const std::string& dir,
                                        const std::vector<estimation::MapSpline>& splines) {
  return {io::WriteSplineMapText(dir + "/map.txt", splines),
          io::WriteSplineMapDxf(dir + "/map.dxf", splines)};
}

// What every EKF-SLAM filter answers the same way.
template <class Filter, class Options>
class FilterMethod : public SlamMethod {
 public:
  FilterMethod(const kernel::Pose2& pose, const Eigen::Matrix3d& covariance, const Options& options)
      : slam_(pose, covariance, options) {}
  void Predict(const kernel::Pose2& u) override { slam_.Predict(u); }
  kernel::Pose2 pose() const override { return slam_.pose(); }
  std::optional<Eigen::Matrix3d> pose_covariance() const override {
    return slam_.pose_covariance();
  }
  std::size_t MapSize() const override {
    return static_cast<std::size_t>(slam_.state().size() - 3) / 2;
  }
  bool healthy() const override { return slam_.healthy(); }
  std::string health() const override { return slam_.health(); }

 protected:
  Filter slam_;
};

class LineSlam : public FilterMethod<estimation::EkfLineSlam, estimation::EkfLineSlamOptions> {
 public:
  using FilterMethod::FilterMethod;
  void Update(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser) override {
    const estimation::UpdateReport r = slam_.Update(scan, robot_T_laser);
    totals_.line_observations += r.line_observations;
    totals_.corner_observations += r.corner_observations;
    totals_.associated += r.associated;
    totals_.new_landmarks += r.new_landmarks;
    totals_.ambiguous += r.ambiguous;
    totals_.too_small += r.too_small;
  }
  std::string MapDescription() const override {
    return fmt::format("{} lines, {} corners", slam_.num_lines(), slam_.num_corners());
  }
  void DrawMap(RunPicture* picture) const override {
    for (const estimation::MapLine& l : slam_.MapLines())
      picture->map_segments.push_back({l.start, l.end});
    for (const estimation::MapCorner& c : slam_.MapCorners())
      picture->map_corners.push_back(c.position);
  }
  std::vector<std::string> WriteMap(const std::string& dir) const override {
    const auto lines = slam_.MapLines();
    const auto corners = slam_.MapCorners();
    return {io::WriteLineMapText(dir + "/map.txt", lines, corners),
            io::WriteLineMapDxf(dir + "/map.dxf", lines, corners)};
  }
  nlohmann::ordered_json Statistics() const override {
    return {{"map", {{"lines", slam_.num_lines()}, {"corners", slam_.num_corners()}}},
            {"associations",
             {{"line_observations", totals_.line_observations},
              {"corner_observations", totals_.corner_observations},
              {"accepted", totals_.associated},
              {"new_landmarks", totals_.new_landmarks},
              {"rejected_ambiguous", totals_.ambiguous},
              {"rejected_too_small", totals_.too_small}}}};
  }

 private:
  estimation::UpdateReport totals_;
};

class BSplineSlam
    : public FilterMethod<estimation::EkfBSplineSlam, estimation::EkfBSplineSlamOptions> {
 public:
  using FilterMethod::FilterMethod;
  void Update(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser) override {
    const estimation::BSplineUpdateReport r = slam_.Update(scan, robot_T_laser);
    observed_ += r.observed_curves;
    matched_ += r.matched_curves;
    beams_used_ += r.beams_used;
    beams_rejected_ += r.beams_rejected;
    created_ += static_cast<int>(r.created.size());
    extended_ += static_cast<int>(r.extended.size());
    ignored_ += r.ignored_curves;
    for (const auto& a : r.associations) with_features_ += a.used_features && !a.beams.empty();
  }
  std::string MapDescription() const override {
    return fmt::format("{} splines, {} control points", slam_.num_splines(),
                       slam_.num_control_points());
  }
  std::size_t MapCurves() const override { return slam_.num_splines(); }
  std::vector<estimation::MapSpline> MapSplines() const override { return slam_.MapSplines(); }
  void DrawMap(RunPicture* picture) const override {
    DrawSplineMap(slam_.MapSplines(), slam_.options().extraction, picture);
  }
  std::vector<std::string> WriteMap(const std::string& dir) const override {
    return WriteSplineMap(dir, slam_.MapSplines());
  }
  nlohmann::ordered_json Statistics() const override {
    return {
        {"map", {{"splines", slam_.num_splines()}, {"control_points", slam_.num_control_points()}}},
        {"associations",
         {{"method", slam_.options().association},
          {"observed_curves", observed_},
          {"matched_curves", matched_},
          {"matches_with_paired_features", with_features_},
          {"beams_used", beams_used_},
          {"beams_rejected", beams_rejected_},
          {"new_splines", created_},
          {"extensions", extended_},
          {"ignored_curves", ignored_}}}};
  }

 private:
  long observed_ = 0, matched_ = 0, beams_used_ = 0, beams_rejected_ = 0;
  int created_ = 0, extended_ = 0, ignored_ = 0, with_features_ = 0;
};

// Topological B-spline SLAM: no covariance; the map is curves with their control points.
class TopologicalSlamMethod : public SlamMethod {
 public:
  TopologicalSlamMethod(const kernel::Pose2& pose,
                        const estimation::TopologicalSlamOptions& options)
      : slam_(pose, options) {}
  void Predict(const kernel::Pose2& u) override { slam_.Predict(u); }
  void Update(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser) override {
    const estimation::TopologicalUpdateReport r = slam_.Update(scan, robot_T_laser);
    observed_ += r.observed_curves;
    associated_ += r.associated_curves;
    verified_ += r.verified_curves;
    localized_ += r.localized;
    fallbacks_ += r.used_fallback;
    failed_ += r.associated_curves > 0 && !r.localized;
    created_ += r.added_curves;
    extended_ += r.extended_curves;
  }
  kernel::Pose2 pose() const override { return slam_.pose(); }
  std::optional<Eigen::Matrix3d> pose_covariance() const override { return std::nullopt; }
  bool healthy() const override { return slam_.healthy(); }
  std::string health() const override { return slam_.health(); }
  std::size_t MapSize() const override { return slam_.num_control_points(); }
  std::size_t MapCurves() const override { return slam_.num_curves(); }
  std::vector<estimation::MapSpline> MapSplines() const override { return slam_.MapSplines(); }
  void AtNode(const kernel::LocalSafeRegion& lsr) override { slam_.SetLocalRegion(lsr); }
  std::string MapDescription() const override {
    return fmt::format("{} curves, {} control points", slam_.num_curves(),
                       slam_.num_control_points());
  }
  void DrawMap(RunPicture* picture) const override {
    DrawSplineMap(slam_.MapSplines(), slam_.options().extraction, picture);
  }
  std::vector<std::string> WriteMap(const std::string& dir) const override {
    return WriteSplineMap(dir, slam_.MapSplines());
  }
  nlohmann::ordered_json Statistics() const override {
    return {
        {"map", {{"curves", slam_.num_curves()}, {"control_points", slam_.num_control_points()}}},
        {"associations",
         {{"method", "curvature"},
          {"observed_curves", observed_},
          {"associated_curves", associated_},
          {"verified_curves", verified_},
          {"localized_scans", localized_},
          {"fallback_to_single_curves", fallbacks_},
          {"failed_localizations", failed_},
          {"new_curves", created_},
          {"extensions", extended_}}}};
  }

 private:
  estimation::TopologicalSlam slam_;
  long observed_ = 0, associated_ = 0, verified_ = 0;
  int localized_ = 0, fallbacks_ = 0, failed_ = 0, created_ = 0, extended_ = 0;
};

}  // namespace

std::unique_ptr<SlamMethod> MakeSlamMethod(const SlamSettings& settings, const kernel::Pose2& start,
                                           std::string* problem) {
  const Eigen::Matrix3d start_covariance = Eigen::Vector3d(1e-6, 1e-6, 1e-8).asDiagonal();
  const estimation::OdometryNoiseModel odometry =
      estimation::OdometryNoiseModel().Scaled(settings.odometry_noise_scale);
  if (settings.method == "ekf-lines") {
    estimation::EkfLineSlamOptions options;
    options.odometry = odometry;
    options.extraction.range_sigma_m = settings.range_sigma_m;
    options.extraction.range_sigma_fraction = settings.range_sigma_fraction;
    if ((*problem = options.Validate()).empty())
      return std::make_unique<LineSlam>(start, start_covariance, options);
  } else if (settings.method == "ekf-bspline") {
    estimation::EkfBSplineSlamOptions options;
    options.odometry = odometry;
    options.association = settings.association;
    options.max_curve_range_m = settings.max_curve_range_m;
    options.range_sigma_floor_m = settings.beam_sigma_floor_m;
    options.range_sigma_fraction = settings.range_sigma_fraction;
    if ((*problem = options.Validate()).empty())
      return std::make_unique<BSplineSlam>(start, start_covariance, options);
  } else if (settings.method == "topological") {
    estimation::TopologicalSlamOptions options;
    options.max_curve_range_m = settings.max_curve_range_m;
    if ((*problem = options.Validate()).empty())
      return std::make_unique<TopologicalSlamMethod>(start, options);
  } else {
    *problem =
        "unknown SLAM method '" + settings.method + "' (ekf-lines, ekf-bspline, topological)";
  }
  return nullptr;
}

double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const std::size_t k =
      std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

nlohmann::ordered_json TimeByMapSize(const std::vector<double>& ms,
                                     const std::vector<std::size_t>& map_size) {
  nlohmann::ordered_json bins = nlohmann::ordered_json::array();
  if (ms.empty()) return bins;
  const std::size_t top = *std::max_element(map_size.begin(), map_size.end()) + 1;
  const std::size_t width = (top + 7) / 8;
  for (std::size_t lo = 0; lo < top; lo += width) {
    std::vector<double> in;
    for (std::size_t i = 0; i < ms.size(); ++i) {
      if (map_size[i] >= lo && map_size[i] < lo + width) in.push_back(ms[i]);
    }
    if (in.empty()) continue;
    bins.push_back({{"map_size_from", lo},
                    {"map_size_to", lo + width - 1},
                    {"scans", in.size()},
                    {"median_ms", Percentile(in, 0.5)}});
  }
  return bins;
}

nlohmann::ordered_json ErrorJson(const estimation::TrajectoryError& e) {
  return {{"matched_poses", e.matched},
          {"rmse_position_m", e.rmse_position_m},
          {"max_position_m", e.max_position_m},
          {"rmse_heading_rad", e.rmse_heading_rad},
          {"max_heading_rad", e.max_heading_rad}};
}

double MeanDistanceToObstacles(const sim::RayCaster& caster,
                               const std::vector<estimation::MapSpline>& splines) {
  constexpr double kCap = 2.0;  // m
  double sum = 0.0;
  std::size_t n = 0;
  for (const estimation::MapSpline& s : splines) {
    for (const Eigen::Vector2d& p : s.spline.ResampleByArcLength(0.05)) {
      const sim::RayHit near = caster.Nearest(p, kCap);
      sum += near.obstacle >= 0 ? near.range_m : kCap;
      ++n;
    }
  }
  return n > 0 ? sum / static_cast<double>(n) : 0.0;
}

void DrawSplineMap(const std::vector<estimation::MapSpline>& splines,
                   const kernel::SplineExtractionOptions& features, RunPicture* picture) {
  for (const estimation::MapSpline& s : splines) {
    const kernel::SplineCurve curve = kernel::DescribeCurve(s.spline, features);
    picture->map_curves.push_back(curve.samples);
    for (const Eigen::Vector2d& p : s.spline.control_points())
      picture->map_control_points.push_back(p);
    for (const kernel::CurveFeature& f : curve.features) {
      (f.type == kernel::FeatureType::kCorner ? picture->map_corners : picture->map_inflections)
          .push_back(f.position);
    }
  }
}

}  // namespace splam::apps
