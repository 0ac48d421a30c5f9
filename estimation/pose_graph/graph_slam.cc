#include "estimation/pose_graph/graph_slam.h"

#include <algorithm>
#include <utility>

#include "estimation/pose_graph/pose_graph_uncertainty.h"

namespace splam::estimation {

GraphSlam::GraphSlam(const kernel::Pose2& start, const GraphSlamOptions& options,
                     std::unique_ptr<ClosureAcceptance> acceptance)
    : options_(options),
      front_end_(start, options.front_end, &keyframes_, LoopCloser::NeedsHitViews(options.loop)),
      back_end_(options.back_end, &keyframes_, options.loop.enabled),
      loop_closer_(options.loop, LoopCloser::FrontEndOf(options.front_end), &keyframes_,
                   &back_end_.graph(), std::move(acceptance)) {}

void GraphSlam::Predict(const kernel::Pose2& odometry_increment) {
  front_end_.Predict(odometry_increment);
}

void GraphSlam::Update(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser) {
  std::optional<GraphFrontEnd::PreparedScan> prepared = front_end_.Register(scan, robot_T_laser);
  if (prepared && front_end_.Settle(front_end_.pose()))
    AddScan(std::move(*prepared), robot_T_laser);
}

void GraphSlam::AddScan(GraphFrontEnd::PreparedScan scan, const kernel::Pose2& robot_T_laser) {
  if (front_end_.KeyframeDue()) AddKeyframe(std::move(scan), robot_T_laser);
  const int k = static_cast<int>(keyframes_.size()) - 1;
  const kernel::Pose2 offset = keyframes_.back().pose.Between(pose());
  scans_.push_back({k, static_cast<float>(offset.x()), static_cast<float>(offset.y()),
                    static_cast<float>(offset.theta())});
}

void GraphSlam::AddKeyframe(GraphFrontEnd::PreparedScan scan, const kernel::Pose2& robot_T_laser) {
  // The previous keyframe's closures go in first: their optimisation moves the pose with that
  // keyframe, and the new keyframe then stands where the corrected graph puts it.
  if (const std::optional<double> travelled = loop_closer_.Collect())
    FlushClosures(false, *travelled);
  std::optional<ScopedTimer> timer(&keyframe_ms_);
  bool robust_edge = false;
  keyframes_.push_back(front_end_.MakeKeyframe(std::move(scan), robot_T_laser,
                                               static_cast<int>(scans_.size()), &robust_edge));
  const int k = static_cast<int>(keyframes_.size()) - 1;
  back_end_.AddKeyframe(k > 0 ? KeyframeEdgeCovariance(options_.front_end.edge, keyframes_, k)
                              : Eigen::Matrix3d::Identity(),
                        robust_edge);
  for (NodeAnchor& node : nodes_)
    if (node.keyframe < 0) node = {k, keyframes_.back().pose.Between(node.pose)};
  front_end_.KeyframeAdded(k);
  back_end_.Trim(TrimmedKeyframe(options_, k));
  timer.reset();
  loop_closer_.Start(k, front_end_.travelled_m());
}

void GraphSlam::FlushClosures(bool final, double travelled_m) {
  const LoopCloser::Accepted accepted = loop_closer_.Decide(final);
  if (accepted.closures.empty()) return;
  Apply(back_end_.AddClosures(accepted.closures, accepted.tags, loop_closer_.waiting(),
                              front_end_.mutable_pose()),
        accepted.closures.size(), travelled_m);
}

void GraphSlam::Apply(const ClosureReport& report, std::size_t added, double travelled_m) {
  loop_closer_.Record(report, added, travelled_m);
  if (report.moved) front_end_.MapMoved();
}

void GraphSlam::Finish() {
  if (const std::optional<double> travelled = loop_closer_.Collect())
    FlushClosures(false, *travelled);
  FlushClosures(true, front_end_.travelled_m());
  Apply(back_end_.Finish(loop_closer_.counts().accepted > 0, front_end_.mutable_pose()), 0,
        front_end_.travelled_m());
}

GraphSlam::Times GraphSlam::times() const {
  const GraphFrontEnd::Times& f = front_end_.times();
  return {f.registration_ms,
          keyframe_ms_,
          f.moving_ms,
          f.submap_ms,
          loop_closer_.search_ms(),
          loop_closer_.wait_ms(),
          back_end_.optimization_ms()};
}

std::vector<kernel::Pose2> GraphSlam::Trajectory() const {
  std::vector<kernel::Pose2> poses;
  poses.reserve(scans_.size());
  for (const ScanAnchor& s : scans_)
    poses.push_back(keyframes_[static_cast<std::size_t>(s.keyframe)].pose *
                    kernel::Pose2(s.x, s.y, s.theta));
  return poses;
}

void GraphSlam::MarkNode() {
  nodes_.push_back({-1, pose()});
  front_end_.ForceKeyframe();
}

std::vector<kernel::Pose2> GraphSlam::NodePoses() const {
  std::vector<kernel::Pose2> poses;
  poses.reserve(nodes_.size());
  for (const NodeAnchor& node : nodes_)
    poses.push_back(node.keyframe < 0
                        ? node.pose
                        : keyframes_[static_cast<std::size_t>(node.keyframe)].pose * node.pose);
  return poses;
}

std::optional<Eigen::Matrix3d> GraphSlam::KeyframeCovariance(int k) const {
  if (k < 0 || k >= back_end_.graph().num_nodes()) return std::nullopt;
  const auto joint = back_end_.graph().JointCovariance({k}, options_.back_end.pose_graph);
  if (!joint) return std::nullopt;
  return Eigen::Matrix3d(*joint);
}

Eigen::Matrix3d GraphSlam::TravelCovariance(double path_m) const {
  const FrontEndOptions& f = options_.front_end;
  return std::max(path_m, 0.0) / f.keyframe_distance_m *
         EdgeCovariance(f.edge, f.keyframe_distance_m, 0.0);
}

std::optional<Eigen::Matrix3d> GraphSlam::PoseCovariance() const {
  if (keyframes_.empty()) return std::nullopt;
  const int last = static_cast<int>(keyframes_.size()) - 1;
  const auto at_keyframe = KeyframeCovariance(last);
  if (!at_keyframe) return std::nullopt;
  const Keyframe& kf = keyframes_.back();
  const Eigen::Matrix3d j = CompositionJacobian(pose().translation() - kf.pose.translation());
  return Eigen::Matrix3d(j * *at_keyframe * j.transpose() +
                         TravelCovariance(front_end_.travelled_m() - kf.travelled_m));
}

std::vector<std::optional<double>> GraphSlam::RevisitInformation(
    const std::vector<int>& nodes, const std::vector<double>& path_m) const {
  std::vector<std::optional<double>> information(nodes.size());
  if (keyframes_.empty() || nodes.size() != path_m.size()) return information;
  const int last = static_cast<int>(keyframes_.size()) - 1;
  std::vector<int> keyframes;  // of the anchored nodes
  std::vector<std::size_t> which;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const int node = nodes[i];
    if (node < 0 || node >= static_cast<int>(nodes_.size())) continue;
    const int k = nodes_[static_cast<std::size_t>(node)].keyframe;
    if (k < 0) continue;
    keyframes.push_back(k);
    which.push_back(i);
  }
  const auto joints =
      back_end_.graph().JointCovariancesWith(last, keyframes, options_.back_end.pose_graph);
  if (!joints) return information;
  // The current pose c from the newest keyframe: rows of c are J times the keyframe's.
  const Keyframe& newest = keyframes_.back();
  const Eigen::Matrix3d j = CompositionJacobian(pose().translation() - newest.pose.translation());
  const Eigen::Matrix3d since = TravelCovariance(front_end_.travelled_m() - newest.travelled_m);
  const Eigen::Matrix3d closure =
      Diagonal(options_.loop.sigma_floor_m, options_.loop.sigma_floor_rad);
  for (std::size_t n = 0; n < keyframes.size(); ++n) {
    Eigen::Matrix<double, 6, 6> joint = (*joints)[n];
    joint.topLeftCorner<3, 3>() = j * joint.topLeftCorner<3, 3>() * j.transpose() + since;
    joint.topRightCorner<3, 3>() = j * joint.topRightCorner<3, 3>();
    joint.bottomLeftCorner<3, 3>() = joint.topRightCorner<3, 3>().transpose();
    const Eigen::Vector2d displacement =
        keyframes_[static_cast<std::size_t>(keyframes[n])].pose.translation() -
        pose().translation();
    const Eigen::Matrix3d after =
        CovarianceAfterRevisit(joint, displacement, TravelCovariance(path_m[which[n]]), closure);
    information[which[n]] = InformationGain(joint.topLeftCorner<3, 3>(), after);
  }
  return information;
}

std::vector<MapSpline> GraphSlam::MapSplines() const {
  std::vector<MapSpline> splines;
  for (const Keyframe& kf : keyframes_) {
    if (!kf.in_map) continue;
    for (const auto& c : kf.data->curves)
      splines.push_back({static_cast<int>(splines.size()), c.spline.Transformed(kf.pose), 1});
  }
  return splines;
}

}  // namespace splam::estimation
