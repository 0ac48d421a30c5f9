#ifndef SPLAM_APPS_SLAM_METHODS_H_
#define SPLAM_APPS_SLAM_METHODS_H_

#include <Eigen/Core>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "apps/run_picture.h"
#include "estimation/ekf_bspline_slam.h"
#include "estimation/ekf_line_slam.h"
#include "estimation/metrics.h"
#include "estimation/topological_slam.h"
#include "kernel/local_safe_region.h"
#include "kernel/pose2.h"
#include "kernel/scan.h"
#include "sim/ray_caster.h"

namespace splam::apps {

// A SLAM method as `splam slam` drives it: filter steps, then the map as files, picture and
// statistics.
class SlamMethod {
 public:
  virtual ~SlamMethod() = default;
  virtual void Predict(const kernel::Pose2& odometry_increment) = 0;
  virtual void Update(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser) = 0;
  virtual kernel::Pose2 pose() const = 0;
  // The pose covariance; methods without one (topological) return nullopt.
  virtual std::optional<Eigen::Matrix3d> pose_covariance() const = 0;
  virtual bool healthy() const = 0;
  virtual std::string health() const = 0;
  // Number of 2-vectors in the state besides the pose: landmarks, or control points.
  virtual std::size_t MapSize() const = 0;
  // "12 lines, 3 corners"
  virtual std::string MapDescription() const = 0;
  virtual void DrawMap(RunPicture* picture) const = 0;
  // Writes map.txt and map.dxf into dir; the errors, if any.
  virtual std::vector<std::string> WriteMap(const std::string& dir) const = 0;
  // Map size and association counts for summary.json.
  virtual nlohmann::ordered_json Statistics() const = 0;
  // Map curves and control points (0 for line maps).
  virtual std::size_t MapCurves() const { return 0; }
  // The map as spline curves (world frame) when it is one; empty otherwise.
  virtual std::vector<estimation::MapSpline> MapSplines() const { return {}; }
  // A new exploration node with its local safe region (placed at the estimate). The topological
  // SLAM associates against the curves in the newest node's LSR and extends its map there.
  virtual void AtNode(const kernel::LocalSafeRegion& /*lsr*/) {}
};

// What MakeSlamMethod needs besides the start pose: the method and the sensors' noise.
struct SlamSettings {
  std::string method = "topological";     // "ekf-lines", "ekf-bspline" or "topological"
  std::string association = "curvature";  // ekf-bspline: "curvature" or "pedraza"
  double max_curve_range_m = 0.0;         // B-spline methods; 0: the laser's range
  double odometry_noise_scale = 1.0;      // times the simulator's odometry noise model
  double range_sigma_m = 0.003;           // line fitting: sigma = this + fraction * range
  double range_sigma_fraction = 0.01;     // (defaults: Hokuyo URG-04LX)
  double beam_sigma_floor_m = 0.0;        // ekf-bspline beam model: floor + fraction * range
};

// The method of `settings`, starting at `start` (EKFs with a small covariance); nullptr with
// *problem set for an unknown method or invalid options.
std::unique_ptr<SlamMethod> MakeSlamMethod(const SlamSettings& settings, const kernel::Pose2& start,
                                           std::string* problem);

// The q-quantile (0..1) of v by nth_element; 0 for an empty v.
double Percentile(std::vector<double> v, double q);
// Median time per step in 8 equal bins of the map size (landmarks, control points or curves).
nlohmann::ordered_json TimeByMapSize(const std::vector<double>& ms,
                                     const std::vector<std::size_t>& map_size);
// A trajectory error as summary.json and report.json write it.
nlohmann::ordered_json ErrorJson(const estimation::TrajectoryError& e);

// Map accuracy: the mean distance from points 5 cm apart along the map curves to the nearest true
// obstacle (capped at 2 m), metres; 0 for an empty map.
double MeanDistanceToObstacles(const sim::RayCaster& caster,
                               const std::vector<estimation::MapSpline>& splines);

// The map splines drawn as paper 000 Figs. 13 and 16 do: curves, control points (small dots),
// inflection points (circles) and corners (diamonds).
void DrawSplineMap(const std::vector<estimation::MapSpline>& splines,
                   const kernel::SplineExtractionOptions& features, RunPicture* picture);

}  // namespace splam::apps

#endif  // SPLAM_APPS_SLAM_METHODS_H_
