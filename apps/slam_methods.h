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
#include "estimation/topological_slam.h"
#include "kernel/pose2.h"
#include "kernel/scan.h"

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
};

std::unique_ptr<SlamMethod> MakeLineSlam(const kernel::Pose2& initial_pose,
                                         const Eigen::Matrix3d& initial_covariance,
                                         const estimation::EkfLineSlamOptions& options);
std::unique_ptr<SlamMethod> MakeBSplineSlam(const kernel::Pose2& initial_pose,
                                            const Eigen::Matrix3d& initial_covariance,
                                            const estimation::EkfBSplineSlamOptions& options);
std::unique_ptr<SlamMethod> MakeTopologicalSlam(const kernel::Pose2& initial_pose,
                                                const estimation::TopologicalSlamOptions& options);

// The map splines drawn as paper 000 Figs. 13 and 16 do: curves, control points (small dots),
// inflection points (circles) and corners (diamonds).
void DrawSplineMap(const std::vector<estimation::MapSpline>& splines,
                   const kernel::SplineExtractionOptions& features, RunPicture* picture);

}  // namespace splam::apps

#endif  // SPLAM_APPS_SLAM_METHODS_H_
