#include "estimation/topological/topological_graph_slam.h"

namespace splam::estimation {

using kernel::Pose2;

TopologicalSlamOptions TopologicalGraphSlamOptions::TopologicalDefaults() {
  TopologicalSlamOptions o;
  o.scan_matching_feedback = true;
  return o;
}

void TopologicalGraphSlamOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Nested("topological", "the topological SLAM (its scan_matching section unused)", &topological);
  v.Nested("graph", "scan matcher and back end: registration, keyframes, loop closure, pose graph",
           &graph);
}

kernel::Status TopologicalGraphSlamOptions::Validate() const {
  if (kernel::Status e = topological.Validate(); !e.ok()) return e;
  return graph.Validate();
}

namespace {

// The topological SLAM's options with the back end's graph as its scan matcher.
TopologicalSlamOptions WithGraphAsScanMatcher(TopologicalSlamOptions topological,
                                              const GraphSlamOptions& graph) {
  topological.scan_matching = graph;
  return topological;
}

}  // namespace

TopologicalGraphSlam::TopologicalGraphSlam(const Pose2& start,
                                           const TopologicalGraphSlamOptions& options)
    : topological_(start, WithGraphAsScanMatcher(options.topological, options.graph)) {
  if (topological_.healthy() && !topological_.scan_matcher())
    own_graph_ = std::make_unique<GraphSlam>(start, options.graph);
}

kernel::Status TopologicalGraphSlam::health() const {
  // A healthy topological SLAM has a scan matcher or an own graph.
  if (!topological_.healthy()) return topological_.health();
  return graph().health();
}

void TopologicalGraphSlam::Predict(const Pose2& odometry_increment) {
  topological_.Predict(odometry_increment);
  if (own_graph_) own_graph_->Predict(odometry_increment);
}

TopologicalUpdateReport TopologicalGraphSlam::Update(const kernel::Scan& scan,
                                                     const Pose2& robot_T_laser) {
  if (!healthy()) return {};
  const std::size_t optimizations = graph().optimizations().size();
  const TopologicalUpdateReport report = topological_.Update(scan, robot_T_laser);
  const Pose2 localised = topological_.pose();
  if (own_graph_) {
    GraphFrontEnd& front_end = own_graph_->front_end();
    std::optional<GraphFrontEnd::PreparedScan> placed =
        front_end.Place(scan, robot_T_laser, localised);
    if (placed && front_end.Settle(localised))
      own_graph_->AddScan(std::move(*placed), robot_T_laser);
  }
  // New keyframes were made at the localised pose (an optimisation in this update may have
  // moved them since: FollowGraph applies that too).
  keyframe_poses_.resize(graph().keyframes().size(), localised);
  const int newest = static_cast<int>(graph().keyframes().size()) - 1;
  curve_keyframe_.resize(topological_.num_curves(), newest);
  if (graph().optimizations().size() != optimizations) FollowGraph();
  return report;
}

void TopologicalGraphSlam::SetLocalRegion(const kernel::LocalSafeRegion& region) {
  if (!healthy()) return;
  topological_.SetLocalRegion(region);
  graph().MarkNode();
}

void TopologicalGraphSlam::Finish() {
  if (!healthy()) return;
  const std::size_t optimizations = graph().optimizations().size();
  graph().Finish();
  if (graph().optimizations().size() != optimizations) FollowGraph();
}

void TopologicalGraphSlam::FollowGraph() {
  const std::vector<GraphSlam::Keyframe>& keyframes = graph().keyframes();
  std::vector<Pose2> correction(keyframes.size());
  for (std::size_t k = 0; k < keyframes.size(); ++k) {
    correction[k] = keyframes[k].pose * keyframe_poses_[k].Inverse();
    keyframe_poses_[k] = keyframes[k].pose;
  }
  topological_.Reanchor(
      [&](int curve) { return correction[static_cast<std::size_t>(curve_keyframe_[curve])]; },
      graph().pose());
}

}  // namespace splam::estimation
