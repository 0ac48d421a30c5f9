#ifndef SPLAM_ESTIMATION_POSE_GRAPH_MAP_LOCALIZER_H_
#define SPLAM_ESTIMATION_POSE_GRAPH_MAP_LOCALIZER_H_

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "estimation/pose_graph/distance_grid.h"
#include "estimation/pose_graph/graph_slam.h"
#include "estimation/slam_state.h"
#include "kernel/pose2.h"
#include "kernel/scan.h"

// Localisation in a saved map (graph SLAM's pure localisation): each scan is registered, as the
// graph SLAM's front end registers it against its submap, against a distance field of the map's
// scans near the robot, with the odometry increment as the prior (FrontEndOptions::registration,
// odometry, recovery_window_*). The map never changes. The first scan is searched for over
// MapLocalizationOptions' initial window around the start pose (branch-and-bound correlative
// search), so the start need only be roughly known. One of the first scans then confirms the
// start by a search of the whole map (GlobalLocalizer), which relocalises a start that was wrong.
namespace splam::estimation {

class GlobalLocalizer;

// The scan's hits (robot frame) with the normals of their outlines, as the graph SLAM takes them:
// beams beyond max_range_m (0: the laser's maximum) left out.
std::vector<OrientedPoint> MapScanPoints(const kernel::Scan& scan,
                                         const kernel::Pose2& robot_T_laser,
                                         const FrontEndOptions& options);

class MapLocalizer {
 public:
  // `map` must not be empty; `start` is the first pose in the map's frame.
  MapLocalizer(std::vector<MapScan> map, const kernel::Pose2& start, const FrontEndOptions& options,
               const MapLocalizationOptions& localization);
  ~MapLocalizer();
  MapLocalizer(const MapLocalizer&) = delete;
  MapLocalizer& operator=(const MapLocalizer&) = delete;

  void Predict(const kernel::Pose2& odometry_increment);
  void Update(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser);
  const kernel::Pose2& pose() const { return pose_; }

  const RegistrationCounts& registration_counts() const { return counts_; }
  long grid_builds() const { return grid_builds_; }  // local fields built
  bool found_start() const { return found_start_; }  // the first scan's search succeeded
  // The start was confirmed by a global search (GlobalLocalizer) of one of the first scans, and
  // whether that search moved it (the start given was wrong: the kidnapped robot).
  bool start_confirmed() const { return confirmed_; }
  bool relocalized() const { return relocalized_; }
  // The pose after each Update; the ones before a relocalisation moved with it.
  const std::vector<kernel::Pose2>& poses() const { return poses_; }

 private:
  void UpdateGrid();
  // Registers the scan against the local field (the first one searched for near the start).
  void Track(const std::vector<OrientedPoint>& points);
  // Until the start is confirmed (every confirm_every_scans-th of the first confirm_scans
  // scans): where the scan lies in the whole map; an unambiguous fix elsewhere relocalises.
  void ConfirmStart(const std::vector<OrientedPoint>& points);
  RegistrationResult Register(const std::vector<OrientedPoint>& points);

  std::vector<MapScan> map_;
  std::vector<std::vector<OrientedPoint>> world_points_;  // per map scan, world frame
  FrontEndOptions options_;
  MapLocalizationOptions localization_;
  kernel::Pose2 pose_;
  kernel::Pose2 since_update_;  // odometry since the last scan
  DistanceGrid grid_;
  std::unique_ptr<LikelihoodPyramid> scores_;  // of grid_
  Eigen::Vector2d grid_center_ = Eigen::Vector2d::Zero();
  bool grid_built_ = false;
  bool first_ = true;
  bool found_start_ = false;
  std::unique_ptr<GlobalLocalizer> global_;  // made at the first confirmation
  int scans_ = 0;
  bool confirmed_ = false, relocalized_ = false;
  std::vector<kernel::Pose2> poses_;
  RegistrationCounts counts_;
  long grid_builds_ = 0;
};

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_POSE_GRAPH_MAP_LOCALIZER_H_
