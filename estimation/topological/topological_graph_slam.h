#ifndef SPLAM_ESTIMATION_TOPOLOGICAL_TOPOLOGICAL_GRAPH_SLAM_H_
#define SPLAM_ESTIMATION_TOPOLOGICAL_TOPOLOGICAL_GRAPH_SLAM_H_

#include <memory>
#include <vector>

#include "estimation/pose_graph/graph_slam.h"
#include "estimation/topological/topological_slam.h"
#include "kernel/local_safe_region.h"
#include "kernel/options.h"
#include "kernel/pose2.h"
#include "kernel/scan.h"
#include "kernel/status.h"

namespace splam::estimation {

struct TopologicalGraphSlamOptions {
  // The front end: every scan is localised and mapped by the topological SLAM, here with its
  // corrected poses fed back to its scan matcher (scan_matching_feedback; see TopologicalDefaults).
  TopologicalSlamOptions topological = TopologicalDefaults();
  // The back end: keyframes, loop closure and the pose graph of the graph SLAM. Its
  // scan-to-submap registration (registration, odometry_prior, recovery_*) is not used.
  GraphSlamOptions graph;

  // The topological SLAM's defaults with scan_matching_feedback: behind a back end whose closures
  // move the curve map, the scan matcher may follow the map. REG explorations, seeds 1-10 in
  // `complex`: 0.057 m mean position RMSE against 0.074 m without; `halls` seeds 1-3: 0.023,
  // 0.110, 0.031 m against 0.062, 0.079, 0.159 m; intel 0.0185 m against 0.0207 m, mit-csail
  // 0.0300 m against 0.0307 m (relations metric).
  static TopologicalSlamOptions TopologicalDefaults();
  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

// The topological B-spline SLAM with the graph SLAM's back end behind it:
// the topological SLAM localises every scan against its curve map; the poses it finds become the
// graph's keyframes (every keyframe_distance_m or keyframe_angle_rad, and at every exploration
// node), with edges between consecutive keyframes; the graph searches every new keyframe for loop
// closures and optimises. After each optimisation the topological map follows the graph: every
// map curve moves rigidly with the keyframe it was created at (new = K_new K_old^-1 old), and the
// pose with its keyframe. A curve extended by splices from later keyframes moves with the first.
class TopologicalGraphSlam {
 public:
  TopologicalGraphSlam(const kernel::Pose2& start, const TopologicalGraphSlamOptions& options);

  void Predict(const kernel::Pose2& odometry_increment);
  TopologicalUpdateReport Update(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser);
  // An exploration node: the topological SLAM's local region, and a keyframe it is anchored to.
  void SetLocalRegion(const kernel::LocalSafeRegion& region);
  // The data has ended: the graph optimises once more and the map follows.
  void Finish();

  kernel::Pose2 pose() const { return topological_.pose(); }
  const TopologicalSlam& topological() const { return topological_; }
  const GraphSlam& graph() const {
    return topological_.scan_matcher() ? *topological_.scan_matcher() : *own_graph_;
  }
  kernel::Status health() const;
  bool healthy() const { return health().ok(); }

 private:
  // Moves the topological map and pose to the graph's optimised keyframes.
  void FollowGraph();

  GraphSlam& graph() {
    return topological_.scan_matcher() ? *topological_.scan_matcher() : *own_graph_;
  }

  TopologicalSlam topological_;
  // With the odometry's prediction the topological SLAM has no scan matcher: the back end is
  // a graph of its own, fed the localised poses (GraphSlam::UpdateAt).
  std::unique_ptr<GraphSlam> own_graph_;
  std::vector<int> curve_keyframe_;            // the keyframe each map curve was created at
  std::vector<kernel::Pose2> keyframe_poses_;  // each keyframe's pose when the map last followed
};

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_TOPOLOGICAL_TOPOLOGICAL_GRAPH_SLAM_H_
