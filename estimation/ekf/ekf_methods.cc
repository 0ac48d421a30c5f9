#include "estimation/ekf/ekf_methods.h"

#include <fmt/core.h>

#include "estimation/ekf/ekf_bspline_slam.h"
#include "estimation/ekf/ekf_line_slam.h"

namespace splam::estimation {
namespace {

// The EKFs start with a small covariance at the known start pose.
Eigen::Matrix3d StartCovariance() { return Eigen::Vector3d(1e-6, 1e-6, 1e-8).asDiagonal(); }

// What every EKF-SLAM filter answers the same way.
template <class Filter, class Options>
class FilterMethod : public SlamMethod {
 public:
  FilterMethod(const Options& options, const SlamContext& context)
      : slam_(context.start, StartCovariance(), options) {}
  void Predict(const kernel::Pose2& u) override { slam_.Predict(u); }
  kernel::Pose2 pose() const override { return slam_.pose(); }
  std::optional<Eigen::Matrix3d> PoseCovariance() const override { return slam_.pose_covariance(); }
  std::size_t MapSize() const override {
    return static_cast<std::size_t>(slam_.state().size() - 3) / 2;
  }
  kernel::Status health() const override { return slam_.health(); }

 protected:
  Filter slam_;
};

class LineSlam : public FilterMethod<EkfLineSlam, EkfLineSlamOptions> {
 public:
  using FilterMethod::FilterMethod;
  void Update(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser) override {
    const UpdateReport r = slam_.Update(scan, robot_T_laser);
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
  SlamMap Map() const override {
    SlamMap map;
    map.lines = slam_.MapLines();
    map.corners = slam_.MapCorners();
    return map;
  }
  SlamStatistics Statistics() const override {
    SlamStatistics s;
    s.map = {{"lines", static_cast<long>(slam_.num_lines())},
             {"corners", static_cast<long>(slam_.num_corners())}};
    s.associations = {{"line_observations", totals_.line_observations},
                      {"corner_observations", totals_.corner_observations},
                      {"accepted", totals_.associated},
                      {"new_landmarks", totals_.new_landmarks},
                      {"rejected_ambiguous", totals_.ambiguous},
                      {"rejected_too_small", totals_.too_small}};
    return s;
  }

 private:
  UpdateReport totals_;
};

class BSplineSlam : public FilterMethod<EkfBSplineSlam, EkfBSplineSlamOptions> {
 public:
  using FilterMethod::FilterMethod;
  void Update(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser) override {
    const BSplineUpdateReport r = slam_.Update(scan, robot_T_laser);
    observed_ += r.observed_curves;
    matched_ += r.matched_curves;
    beams_used_ += r.beams_used;
    beams_rejected_ += r.beams_rejected;
    created_ += static_cast<long>(r.created.size());
    extended_ += static_cast<long>(r.extended.size());
    ignored_ += r.ignored_curves;
    for (const auto& a : r.associations) with_features_ += a.used_features && !a.beams.empty();
  }
  std::string MapDescription() const override {
    return fmt::format("{} splines, {} control points", slam_.num_splines(),
                       slam_.num_control_points());
  }
  std::size_t MapCurves() const override { return slam_.num_splines(); }
  SlamMap Map() const override {
    SlamMap map;
    map.splines = slam_.MapSplines();
    map.spline_features = slam_.options().extraction;
    return map;
  }
  SlamStatistics Statistics() const override {
    SlamStatistics s;
    s.association = slam_.options().association;
    s.map = {{"splines", static_cast<long>(slam_.num_splines())},
             {"control_points", static_cast<long>(slam_.num_control_points())}};
    s.associations = {{"observed_curves", observed_},
                      {"matched_curves", matched_},
                      {"matches_with_paired_features", with_features_},
                      {"beams_used", beams_used_},
                      {"beams_rejected", beams_rejected_},
                      {"new_splines", created_},
                      {"extensions", extended_},
                      {"ignored_curves", ignored_}};
    return s;
  }

 private:
  long observed_ = 0, matched_ = 0, beams_used_ = 0, beams_rejected_ = 0;
  long created_ = 0, extended_ = 0, ignored_ = 0, with_features_ = 0;
};

}  // namespace

void AddEkfMethods(kernel::Registry<SlamMethodInfo>* registry) {
  registry->Add(MakeSlamMethodInfo<EkfLineSlamOptions>(
      "ekf-lines", "EKF-SLAM with line and corner landmarks (paper 001, SPEC §2-6)",
      [](const EkfLineSlamOptions& o, const SlamContext& c) {
        return std::make_unique<LineSlam>(o, c);
      },
      [](const SensorNoise& noise, EkfLineSlamOptions* o) {
        o->odometry = OdometryNoiseModel().Scaled(noise.odometry_noise_scale);
        o->extraction.range_sigma_m = noise.range_sigma_m;
        o->extraction.range_sigma_fraction = noise.range_sigma_fraction;
      }));
  registry->Add(MakeSlamMethodInfo<EkfBSplineSlamOptions>(
      "ekf-bspline",
      "EKF-SLAM with B-spline obstacles (Pedraza et al. 2009; paper 000's curvature association)",
      [](const EkfBSplineSlamOptions& o, const SlamContext& c) {
        return std::make_unique<BSplineSlam>(o, c);
      },
      [](const SensorNoise& noise, EkfBSplineSlamOptions* o) {
        o->odometry = OdometryNoiseModel().Scaled(noise.odometry_noise_scale);
        o->range_sigma_floor_m = noise.beam_sigma_floor_m;
        o->range_sigma_fraction = noise.range_sigma_fraction;
      }));
}

}  // namespace splam::estimation
