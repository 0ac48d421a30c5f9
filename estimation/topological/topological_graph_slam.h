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
  // The topological SLAM: every scan is localised and mapped against its curve map, with its
  // corrected poses fed back to its scan matcher (scan_matching_feedback; see
  // TopologicalDefaults). Its scan_matching section is not used: the graph below is its scan
  // matcher.
  TopologicalSlamOptions topological = TopologicalDefaults();
  // The graph SLAM behind it: the scan matcher that predicts every scan (registration, submap,
  // odometry test, recovery search), and the keyframes, loop closure and pose graph.
  GraphSlamOptions graph;

  // The topological SLAM's defaults with scan_matching_feedback: behind a back end whose closures
  // move the curve map, the scan matcher may follow the map (see TopologicalSlamOptions).
  static TopologicalSlamOptions TopologicalDefaults();
  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

// The topological B-spline SLAM with the graph SLAM behind it. One graph SLAM is both the
// topological SLAM's scan matcher and its back end: it registers every scan against its submap
// (the prediction), the topological SLAM corrects the pose against its curve map, and the scan
// becomes a keyframe at the corrected pose (GraphFrontEnd::Settle, then GraphSlam::AddScan; every
// keyframe_distance_m or keyframe_angle_rad, and at every exploration node). The graph searches
// every new keyframe for loop closures and optimises; its submap then follows the optimised
// keyframes, and so does the topological map: every map curve moves rigidly with the keyframe it
// was created at (new = K_new K_old^-1 old), and the pose with its keyframe. A curve extended by
// splices from later keyframes moves with the first. With the odometry's prediction (no scan
// matcher) a graph of its own takes the localised poses as keyframes (GraphFrontEnd::Place).
// Until session 41 the scan matcher was a second graph SLAM without loop closure, whose submap
// the optimisations did not move; one graph measured the same (REG explorations, seeds 1-10:
// `complex` 0.058 against 0.057 m mean position RMSE, `halls` 0.091 against 0.090 m; intel
// 0.0197 against 0.0185 m, mit-csail 0.0292 against 0.0300 m) in one registration per scan
// instead of two (intel 15.0 s against 17.1 s, 249 against 298 MB).
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
  // a graph of its own, fed the localised poses (GraphFrontEnd::Place).
  std::unique_ptr<GraphSlam> own_graph_;
  std::vector<int> curve_keyframe_;            // the keyframe each map curve was created at
  std::vector<kernel::Pose2> keyframe_poses_;  // each keyframe's pose when the map last followed
};

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_TOPOLOGICAL_TOPOLOGICAL_GRAPH_SLAM_H_
