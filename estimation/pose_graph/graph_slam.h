#ifndef SPLAM_ESTIMATION_POSE_GRAPH_GRAPH_SLAM_H_
#define SPLAM_ESTIMATION_POSE_GRAPH_GRAPH_SLAM_H_

#include <Eigen/Core>
#include <deque>
#include <memory>
#include <optional>
#include <vector>

#include "estimation/map_spline.h"
#include "estimation/pose_graph/graph_back_end.h"
#include "estimation/pose_graph/graph_front_end.h"
#include "estimation/pose_graph/graph_slam_options.h"
#include "estimation/pose_graph/keyframes.h"
#include "estimation/pose_graph/loop_closer.h"
#include "estimation/pose_graph/pose_graph.h"
#include "kernel/pose2.h"
#include "kernel/scan.h"
#include "kernel/status.h"

namespace splam::estimation {

// Graph SLAM on curve maps: keyframes keep their scan's B-spline curves and points; every scan
// is registered against a submap rasterised from the curves of recent keyframes; each new
// keyframe searches earlier ones for a loop closure; a Ceres pose graph over the keyframes is
// optimised when closures are accepted and re-anchors the map. It composes three parts over one
// store of keyframes (docs/graph_slam_toolkit.md): a GraphFrontEnd (scans in, keyframes out), a
// LoopCloser (closures between keyframes, accepted by a ClosureAcceptance) and a GraphBackEnd
// (the pose graph, its optimisation schedule, trimming and merging).
class GraphSlam {
 public:
  using Keyframe = estimation::Keyframe;

  // `acceptance` null: the built-in AgreementAcceptance.
  GraphSlam(const kernel::Pose2& start, const GraphSlamOptions& options,
            std::unique_ptr<ClosureAcceptance> acceptance = nullptr);
  // A loop search may be running on `this`.
  GraphSlam(const GraphSlam&) = delete;
  GraphSlam& operator=(const GraphSlam&) = delete;

  void Predict(const kernel::Pose2& odometry_increment);
  // Registers the scan (GraphFrontEnd::Register), then AddScan.
  void Update(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser);
  // The step by parts, for a method that steers the front end (the topological SLAM corrects
  // its registered pose against its curve map, or localises the scan itself): it calls
  // front_end().Register or Place, then Settle at the pose the step ends at, then AddScan with
  // the scan it got. The submap is then built at the poses it settled.
  GraphFrontEnd& front_end() { return front_end_; }
  // The scan the front end has settled: a keyframe when due (the previous keyframe's closures
  // go into the back end first, and its own loop search starts), and the trajectory's record.
  void AddScan(GraphFrontEnd::PreparedScan scan, const kernel::Pose2& robot_T_laser);
  // An exploration node at the current estimate: the next scan makes a keyframe, to which the
  // node is anchored, so that the node moves with the keyframe when the graph is optimised.
  void MarkNode();
  // The nodes marked so far, where the graph now puts them.
  std::vector<kernel::Pose2> NodePoses() const;
  // The data has ended: optimises the pending closures and the whole graph once more.
  void Finish();

  // Uncertainty (PoseGraph::JointCovariance: poses (x, y, theta) in the world frame, the first
  // keyframe held, closures still waiting for confirmation not counted). Keyframe k's marginal
  // covariance; nullopt when k is not a keyframe.
  std::optional<Eigen::Matrix3d> KeyframeCovariance(int k) const;
  // The current pose's: the newest keyframe's moved to the pose, plus TravelCovariance for the
  // path since. nullopt before the first keyframe.
  std::optional<Eigen::Matrix3d> PoseCovariance() const;
  // The front-end edges' model (FrontEndOptions::edge) over path_m of straight travel: one edge per
  // keyframe_distance_m, independent.
  Eigen::Matrix3d TravelCovariance(double path_m) const;
  // Expected information of a revisit (active loop closing) to each marked node: the robot drives
  // path_m[i] to nodes[i] (TravelCovariance) and a loop closure registers it against the node's
  // keyframe (covariance: the loop edges' floor, loop.sigma_floor_m and _rad) there;
  // InformationGain(PoseCovariance(), CovarianceAfterRevisit(...)), nats, negative when the
  // drive costs more than the closure gives. nullopt for a node not yet anchored to a keyframe,
  // or all of them when the graph has no covariance (nothing marked, a single keyframe).
  std::vector<std::optional<double>> RevisitInformation(const std::vector<int>& nodes,
                                                        const std::vector<double>& path_m) const;

  const kernel::Pose2& pose() const { return front_end_.pose(); }
  const GraphSlamOptions& options() const { return options_; }
  const Keyframes& keyframes() const { return keyframes_; }
  const PoseGraph& graph() const { return back_end_.graph(); }
  // The parts.
  const GraphFrontEnd& front_end() const { return front_end_; }
  const LoopCloser& loop_closer() const { return loop_closer_; }
  const GraphBackEnd& back_end() const { return back_end_; }
  // Every scan's pose as now estimated (its keyframe's optimised pose times the offset).
  std::vector<kernel::Pose2> Trajectory() const;
  std::vector<MapSpline> MapSplines() const;
  std::size_t num_map_curves() const { return front_end_.num_map_curves(); }
  std::size_t num_map_control_points() const { return front_end_.num_map_control_points(); }
  long trimmed_keyframes() const { return back_end_.trimmed_keyframes(); }
  // Keyframes whose nodes were merged into earlier ones (merge_trimmed_keyframes).
  long merged_keyframes() const { return graph().num_nodes() - graph().num_live_nodes(); }
  // Submaps built anew, and keyframes inserted into one (submap_insert_keyframes).
  long submap_builds() const { return front_end_.submap_builds(); }
  long submap_inserts() const { return front_end_.submap_inserts(); }
  // Flushes whose closures were added without an optimisation
  // (BackEndOptions::Advanced::deferred_optimization_fraction).
  long deferred_optimizations() const { return back_end_.deferred_optimizations(); }

  // Whether the last scan's registration stood (Update; false after a fallback to odometry, and
  // after GraphFrontEnd::Place).
  bool registered() const { return front_end_.registered(); }
  const LoopClosureCounts& loops() const { return loop_closer_.counts(); }
  // Beams of scans and keyframes left out as moving objects (MovingObjectOptions).
  long moving_beams() const { return front_end_.moving_beams(); }
  // Every loop-closure search, in order.
  std::vector<LoopSearch> loop_searches() const { return loop_closer_.searches(); }
  const std::vector<PoseGraphSummary>& optimizations() const { return back_end_.optimizations(); }
  // Wall time spent in each part, ms. The loop search may run beside the others
  // (background_loop_search); loop_wait_ms is how long the front end waited for it.
  struct Times {
    double registration_ms = 0, keyframe_ms = 0, moving_ms = 0, submap_ms = 0, loop_search_ms = 0,
           loop_wait_ms = 0, optimization_ms = 0;
  };
  Times times() const;
  kernel::Status health() const { return front_end_.health(); }

 private:
  // The scan makes a keyframe: the previous keyframe's closures go into the graph first, then
  // the keyframe, its node and edge, the trimming of the keyframe that has left every window,
  // and its loop search.
  void AddKeyframe(GraphFrontEnd::PreparedScan scan, const kernel::Pose2& robot_T_laser);
  // Lets the closures the acceptance takes into the back end (`final`: the data has ended);
  // `travelled_m`: the travel at the keyframe whose search found the latest closures.
  void FlushClosures(bool final, double travelled_m);
  // The back end's report: recorded by the loop closer; the submap follows an optimisation.
  void Apply(const ClosureReport& report, std::size_t added, double travelled_m);

  GraphSlamOptions options_;
  Keyframes keyframes_;
  GraphFrontEnd front_end_;
  GraphBackEnd back_end_;
  LoopCloser loop_closer_;  // last: destroyed first, waiting for its search
  // A marked node: keyframe_T_node of its keyframe, or (keyframe -1, until the next keyframe is
  // made) its pose in the world.
  struct NodeAnchor {
    int keyframe = -1;
    kernel::Pose2 pose;
  };
  std::vector<NodeAnchor> nodes_;
  // Every scan's pose, as the run's record (Trajectory): keyframe^-1 * scan pose, in floats (a
  // scan lies within metres of its keyframe: micrometres), 16 bytes a scan; in a deque, which
  // grows by blocks where a vector would double.
  struct ScanAnchor {
    int keyframe;
    float x, y, theta;
  };
  std::deque<ScanAnchor> scans_;
  double keyframe_ms_ = 0.0;
};

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_POSE_GRAPH_GRAPH_SLAM_H_
