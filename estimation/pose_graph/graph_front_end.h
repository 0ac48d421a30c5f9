#ifndef SPLAM_ESTIMATION_POSE_GRAPH_GRAPH_FRONT_END_H_
#define SPLAM_ESTIMATION_POSE_GRAPH_GRAPH_FRONT_END_H_

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "estimation/pose_graph/correlative_matcher.h"
#include "estimation/pose_graph/distance_grid.h"
#include "estimation/pose_graph/graph_slam_options.h"
#include "estimation/pose_graph/keyframes.h"
#include "estimation/pose_graph/scan_registration.h"
#include "estimation/slam_map.h"
#include "kernel/pose2.h"
#include "kernel/scan.h"
#include "kernel/status.h"

namespace splam::estimation {

// The graph SLAM front end's registration of a scan's points (robot frame) against a field
// (world frame) from the predicted pose: the scan alone and with the odometry increment since
// the last scan as its prior (the fused pose unless the odometry is an outlier); when that fails
// its test or looks suspect (misfit above advanced.verify_misfit_fraction), a correlative search
// over the recovery window on `scores` (made on first need) and a wide registration from its best
// pose, taken when it fits at least as well. GraphFrontEnd registers against its submap,
// MapLocalizer against a saved map.
struct FrontEndRegistration {
  RegistrationResult result;
  bool searched = false;   // the recovery search ran
  bool recovered = false;  // and its pose was taken
};
FrontEndRegistration RegisterFrontEnd(const std::vector<OrientedPoint>& points,
                                      const DistanceGrid& field,
                                      const std::function<const LikelihoodPyramid&()>& scores,
                                      const kernel::Pose2& predicted,
                                      const kernel::Pose2& odometry_since,
                                      const FrontEndOptions& options);

// The front-end edge model's covariance for distance_m of travel and a turn of turn_rad.
Eigen::Matrix3d EdgeCovariance(const EdgeModel& model, double distance_m, double turn_rad);
// That model for the edge from keyframe `to` - 1 to `to`, at their present poses and travel.
Eigen::Matrix3d KeyframeEdgeCovariance(const EdgeModel& model, const Keyframes& keyframes, int to);

// The front end of the graph SLAM (after Cartographer's LocalTrajectoryBuilder2D): scans in,
// keyframes out. Every scan is registered against a submap rasterised from the last keyframes
// (RegisterFrontEnd), moving objects are left out of it and of those keyframes, and the scan
// makes a keyframe every keyframe_distance_m or keyframe_angle_rad. It appends its keyframes
// to a store it shares with the loop closer and the back end, which move them; it reads and
// edits only the last max(submap_keyframes, moving_keyframes) of them.
//
// One step: Register (or Place, for a scan localised by another method), Settle at the pose
// the step ends at, and, when KeyframeDue, MakeKeyframe and KeyframeAdded once it is stored.
class GraphFrontEnd {
 public:
  // `keyframes` outlives the front end. `hit_views`: each keyframe also keeps the view of its
  // beams that returned (Keyframe::Data::seen_by_hits), which a loop closer scoring where the
  // target's returning beams passed reads (LoopCloser::NeedsHitViews).
  GraphFrontEnd(const kernel::Pose2& start, const FrontEndOptions& options, Keyframes* keyframes,
                bool hit_views = false);

  void Predict(const kernel::Pose2& odometry_increment);

  // A scan as the front end keeps it: clipped to the usable range, its moving objects read as
  // NaN, and its points (robot frame, with normals).
  struct PreparedScan {
    kernel::Scan reading;
    std::vector<OrientedPoint> points;
  };
  // Registers the scan against the submap from the predicted pose; pose() is then the
  // registered pose (the prediction when the registration fell back to it: registered()
  // false). nullopt when the front end has stopped (health()).
  std::optional<PreparedScan> Register(const kernel::Scan& scan,
                                       const kernel::Pose2& robot_T_laser);
  // The same for a scan that another method localised at `pose`: no registration.
  std::optional<PreparedScan> Place(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser,
                                    const kernel::Pose2& pose);
  // Ends the step at `pose` (pose(), or another method's correction of it): the next
  // prediction starts from it. False, and the front end stops (health()), when it is not finite.
  bool Settle(const kernel::Pose2& pose);
  // Whether the scan just settled makes a keyframe: the first, a forced one (ForceKeyframe), or
  // keyframe_distance_m or keyframe_angle_rad from the last.
  bool KeyframeDue() const;
  // The next scan makes a keyframe.
  void ForceKeyframe() { force_keyframe_ = true; }
  // The keyframe the settled scan makes at pose(); scan_index: its index in input order;
  // *robust_edge: whether the front-end edge into it gets the closures' robust loss (a
  // recovery placed a scan since the last keyframe, advanced.robust_recovery_edges).
  Keyframe MakeKeyframe(PreparedScan scan, const kernel::Pose2& robot_T_laser, int scan_index,
                        bool* robust_edge);
  // Keyframe k, made by MakeKeyframe, is now the store's last: the one that has left the last
  // moving_keyframes drops its reading.
  void KeyframeAdded(int k);
  // The keyframes have moved (an optimisation): the submap is built anew.
  void MapMoved() { submap_dirty_ = true; }

  const kernel::Pose2& pose() const { return pose_; }
  // The pose, for a back end that moves it with the newest keyframe when it optimises.
  kernel::Pose2* mutable_pose() { return &pose_; }
  double travelled_m() const { return travelled_m_; }
  kernel::Status health() const { return health_; }

  bool registered() const { return registered_; }
  const RegistrationCounts& registration_counts() const { return counts_; }
  long moving_beams() const { return moving_beams_; }
  long submap_builds() const { return submap_builds_; }
  long submap_inserts() const { return submap_inserts_; }
  std::size_t num_map_curves() const { return map_curves_; }
  std::size_t num_map_control_points() const { return map_control_points_; }
  // Wall time, ms.
  struct Times {
    double registration_ms = 0, moving_ms = 0, submap_ms = 0;
  };
  const Times& times() const { return times_; }

 private:
  // The scan clipped to the usable range, and its points.
  PreparedScan Prepare(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser) const;
  // Leaves out of the scan (at pose_) the objects that the last keyframes saw through; when
  // there are some and `register_again`, registers it again from `predicted` without them.
  void LeaveOutMoving(const kernel::Pose2& robot_T_laser, const kernel::Pose2& predicted,
                      bool register_again, PreparedScan* scan);
  // The keyframe's points, curves, raster and view from its reading (points: already computed).
  void FillKeyframe(std::vector<OrientedPoint> points, Keyframe* kf);
  // The scan's points (robot frame, with normals).
  std::vector<OrientedPoint> ScanPoints(const kernel::Scan& scan,
                                        const kernel::Pose2& robot_T_laser) const;
  // The beams of `scan` (clipped, at pose_, registered) on objects that the last
  // moving_keyframes keyframes' scans saw through, sorted; takes out of those keyframes the
  // objects that `scan` sees through.
  std::vector<std::size_t> MovingBeams(const kernel::Scan& scan,
                                       const kernel::Pose2& robot_T_laser);
  // Beams longer than this are not used: max_range_m, or the laser's range when it is 0.
  double UsableRange(const kernel::Scan& scan) const;
  // Brings the submap up to the last keyframe: inserts the new keyframes or builds it anew (see
  // advanced.submap_insert_keyframes).
  void UpdateSubmap();
  // Registers a scan at the predicted pose against the submap (see recovery_window_m).
  RegistrationResult RegisterScan(const std::vector<OrientedPoint>& points);

  FrontEndOptions options_;
  Keyframes* keyframes_;
  bool hit_views_;
  kernel::Pose2 pose_;
  double travelled_m_ = 0.0;
  kernel::Pose2 since_update_;  // odometry since the last registered scan
  DistanceGrid submap_;
  std::unique_ptr<LikelihoodPyramid> submap_scores_;  // of submap_
  bool submap_dirty_ = true;                          // to be built anew
  int submap_first_ = 0, submap_last_ = -1;           // its first and last keyframe
  long submap_builds_ = 0, submap_inserts_ = 0;
  bool force_keyframe_ = false;
  bool recovered_since_keyframe_ = false;  // a recovery search placed a scan since the last one
  bool registered_ = false;
  RegistrationCounts counts_;
  long moving_beams_ = 0;
  std::size_t map_curves_ = 0, map_control_points_ = 0;
  Times times_;
  kernel::Status health_;
};

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_POSE_GRAPH_GRAPH_FRONT_END_H_
