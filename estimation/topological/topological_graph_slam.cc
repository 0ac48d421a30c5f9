#include "estimation/topological/topological_graph_slam.h"

namespace splam::estimation {

using kernel::Pose2;

TopologicalSlamOptions TopologicalGraphSlamOptions::TopologicalDefaults() {
  TopologicalSlamOptions o;
  o.scan_matching_feedback = true;
  return o;
}

void TopologicalGraphSlamOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Nested("topological", "front end: the topological SLAM", &topological);
  v.Nested("graph", "back end: keyframes, loop closure, pose graph (its registration unused)",
           &graph);
}

kernel::Status TopologicalGraphSlamOptions::Validate() const {
  if (kernel::Status e = topological.Validate(); !e.ok()) return e;
  return graph.Validate();
}

TopologicalGraphSlam::TopologicalGraphSlam(const Pose2& start,
                                           const TopologicalGraphSlamOptions& options)
    : topological_(start, options.topological), graph_(start, options.graph) {}

kernel::Status TopologicalGraphSlam::health() const {
  if (!topological_.healthy()) return topological_.health();
  return graph_.health();
}

void TopologicalGraphSlam::Predict(const Pose2& odometry_increment) {
  topological_.Predict(odometry_increment);
  graph_.Predict(odometry_increment);
}

TopologicalUpdateReport TopologicalGraphSlam::Update(const kernel::Scan& scan,
                                                     const Pose2& robot_T_laser) {
  const TopologicalUpdateReport report = topological_.Update(scan, robot_T_laser);
  const Pose2 localised = topological_.pose();
  const std::size_t optimizations = graph_.optimizations().size();
  graph_.UpdateAt(scan, robot_T_laser, localised);
  // New keyframes were made at the localised pose (an optimisation in this update may have
  // moved them since: FollowGraph applies that too).
  keyframe_poses_.resize(graph_.keyframes().size(), localised);
  const int newest = static_cast<int>(graph_.keyframes().size()) - 1;
  curve_keyframe_.resize(topological_.num_curves(), newest);
  if (graph_.optimizations().size() != optimizations) FollowGraph();
  return report;
}

void TopologicalGraphSlam::SetLocalRegion(const kernel::LocalSafeRegion& region) {
  topological_.SetLocalRegion(region);
  graph_.MarkNode();
}

void TopologicalGraphSlam::Finish() {
  const std::size_t optimizations = graph_.optimizations().size();
  graph_.Finish();
  if (graph_.optimizations().size() != optimizations) FollowGraph();
}

void TopologicalGraphSlam::FollowGraph() {
  const std::vector<GraphSlam::Keyframe>& keyframes = graph_.keyframes();
  std::vector<Pose2> correction(keyframes.size());
  for (std::size_t k = 0; k < keyframes.size(); ++k) {
    correction[k] = keyframes[k].pose * keyframe_poses_[k].Inverse();
    keyframe_poses_[k] = keyframes[k].pose;
  }
  topological_.Reanchor(
      [&](int curve) { return correction[static_cast<std::size_t>(curve_keyframe_[curve])]; },
      graph_.pose());
}

}  // namespace splam::estimation
