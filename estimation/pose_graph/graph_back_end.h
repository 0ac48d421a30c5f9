#ifndef SPLAM_ESTIMATION_POSE_GRAPH_GRAPH_BACK_END_H_
#define SPLAM_ESTIMATION_POSE_GRAPH_GRAPH_BACK_END_H_

#include <Eigen/Core>
#include <vector>

#include "estimation/pose_graph/graph_slam_options.h"
#include "estimation/pose_graph/keyframes.h"
#include "estimation/pose_graph/loop_closer.h"
#include "estimation/pose_graph/pose_graph.h"
#include "estimation/slam_map.h"
#include "kernel/pose2.h"

namespace splam::estimation {

// The back end of the graph SLAM (after Cartographer's PoseGraph2D and OptimizationProblem2D):
// the pose graph over the keyframes (node k is keyframe k; each carries its keyframe's
// trajectory), the optimisation schedule (closures that agree with the graph wait in it
// unoptimised, advanced.deferred_optimization_fraction, meanwhile optimising the last
// advanced.local_optimization_keyframes) and the trimming and merging of redundant keyframes
// (trim_spacing_m, merge_trimmed_keyframes). Every optimisation writes the keyframes' poses and
// moves the robot's pose it is given with the newest keyframe.
class GraphBackEnd {
 public:
  // `keyframes` outlives the back end. `closures`: a loop closer reads the keyframes that have
  // left the submap and adds closures (then a keyframe is trimmed only beside one that keeps its
  // data, and merged into it).
  GraphBackEnd(const BackEndOptions& options, Keyframes* keyframes, bool closures);

  // The store's last keyframe k is new: its node, and the front-end edge from keyframe k - 1
  // (none for the first) with this covariance, with the closures' robust loss when `robust`.
  void AddKeyframe(const Eigen::Matrix3d& edge_covariance, bool robust);
  // Drops keyframe j's data when an earlier keyframe that still holds its own lies within
  // trim_spacing_m and trim_spacing_rad (with `closures`; without, whenever it is not a map
  // keyframe), and queues it to be merged into that one (merge_trimmed_keyframes). j must have
  // left every window that reads keyframe data (TrimmedKeyframe). Nothing when trim_spacing_m
  // is 0.
  void Trim(int j);
  // Adds the closures accepted (tags: the caller's names for them, returned in the report):
  // without an optimisation when they agree with the graph as it is and it has grown by less
  // than advanced.deferred_optimization_fraction since its last whole optimisation (then the last
  // advanced.local_optimization_keyframes are optimised); otherwise optimises the whole graph and
  // removes every closure added since its last whole optimisation that then disagrees with it
  // (whitened squared residual above max_chi2), optimising again from where it was.
  // `waiting`: closures still to be decided, whose keyframes are not merged; *pose moves with
  // the newest keyframe.
  ClosureReport AddClosures(const std::vector<PoseGraphEdge>& closures,
                            const std::vector<int>& tags, const std::vector<PoseGraphEdge>& waiting,
                            kernel::Pose2* pose);
  // The data has ended: the closures that wait unoptimised are checked by a whole
  // optimisation; without any, the graph is optimised once more when `optimize`.
  ClosureReport Finish(bool optimize, kernel::Pose2* pose);

  const PoseGraph& graph() const { return graph_; }
  long trimmed_keyframes() const { return trimmed_; }
  // Flushes whose closures were added without an optimisation (deferred_optimization_fraction).
  long deferred_optimizations() const { return deferred_optimizations_; }
  const std::vector<PoseGraphSummary>& optimizations() const { return optimizations_; }
  double optimization_ms() const { return optimization_ms_; }

 private:
  // Optimises the keyframes from first_free on (all: 0), then moves *pose with the newest.
  void Optimize(int first_free, kernel::Pose2* pose);
  // Adds `closures` and optimises the whole graph; then removes the closures that disagree with
  // it (those added and those that waited in it unoptimised) and optimises again from where it
  // was.
  ClosureReport AddAndOptimize(const std::vector<PoseGraphEdge>& closures,
                               const std::vector<int>& tags,
                               const std::vector<PoseGraphEdge>& waiting, kernel::Pose2* pose);
  // The first keyframe that a local optimisation for these closures frees: the last
  // local_optimization_keyframes keyframes and each closure's newer one (0: the whole graph).
  int LocalWindow(const std::vector<PoseGraphEdge>& closures) const;
  // Whether closures that each agree with the graph (whitened squared residuals summing to chi2)
  // wait unoptimised: the graph has grown by less than deferred_optimization_fraction since its
  // last whole optimisation, and with those waiting already they still agree with it as a whole.
  bool DeferOptimization(double chi2, int closures) const;
  // Merges the queued keyframes that may be merged; called after a whole optimisation, when
  // every closure in the graph has been checked against it.
  void MergeTrimmed(const std::vector<PoseGraphEdge>& waiting);

  BackEndOptions options_;
  Keyframes* keyframes_;
  bool closures_;
  PoseGraph graph_;
  long trimmed_ = 0;
  int optimized_nodes_ = 0;  // the graph's nodes at its last whole optimisation
  // Keyframes trimmed for an earlier one beside it, with that one: merged after a whole
  // optimisation (MergeTrimmed), when no closure still waiting for confirmation reaches them and
  // the graph ties them to that one; dropped (kept as nodes) after two such checks.
  struct QueuedMerge {
    int keyframe, into;
    int checks = 0;
  };
  std::vector<QueuedMerge> merge_queue_;
  // The closures added since then without an optimisation: their edges (indices, ascending),
  // their tags and the sum of their whitened squared residuals.
  std::vector<int> deferred_edges_, deferred_tags_;
  double deferred_chi2_ = 0.0;
  long deferred_optimizations_ = 0;
  std::vector<PoseGraphSummary> optimizations_;
  double optimization_ms_ = 0.0;
};

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_POSE_GRAPH_GRAPH_BACK_END_H_
