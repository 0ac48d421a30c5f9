#include "runtime/slam_localization.h"

#include <utility>

#include "estimation/exploration_nodes.h"

namespace splam::runtime {

SlamLocalization::SlamLocalization(std::string method,
                                   std::shared_ptr<const estimation::SlamOptions> options,
                                   const kernel::LocalRegionOptions& region)
    : method_(std::move(method)), options_(std::move(options)), region_(region) {}

kernel::Status SlamLocalization::Start(const exploration::RobotDescription& robot,
                                       const kernel::Pose2& start,
                                       const exploration::Perception& first) {
  auto made = estimation::SlamRegistry::Global().Make(method_, options_.get(), {start, region_});
  if (!made.ok()) return made.status();
  driver_.emplace(std::move(*made.value));
  driver_->SetOdometryOrigin(first.odometry_pose);
  driver_->RecordSteps(record_steps_);
  robot_T_laser_ = robot.robot_T_laser;
  return {};
}

kernel::Pose2 SlamLocalization::Update(const exploration::Perception& perception) {
  driver_->Step(perception.odometry_pose, &perception.scan, robot_T_laser_);
  if (record_steps_) step_times_.push_back(perception.time_s);
  return driver_->method().pose();
}

void SlamLocalization::AtNode(const kernel::LocalSafeRegion& lsr) {
  if (estimation::ExplorationNodes* nodes = estimation::NodesOf(driver_->method()))
    nodes->AtNode(lsr);
}

std::vector<kernel::Pose2> SlamLocalization::NodePoses() const {
  const estimation::ExplorationNodes* nodes =
      driver_ ? estimation::NodesOf(driver_->method()) : nullptr;
  return nodes != nullptr ? nodes->NodePoses() : std::vector<kernel::Pose2>{};
}

std::optional<Eigen::Matrix3d> SlamLocalization::PoseCovariance() const {
  if (!driver_) return std::nullopt;
  return driver_->method().PoseCovariance();
}

std::vector<std::optional<double>> SlamLocalization::RevisitInformation(
    const std::vector<int>& nodes, const std::vector<double>& path_m) const {
  const estimation::ExplorationNodes* method =
      driver_ ? estimation::NodesOf(driver_->method()) : nullptr;
  return method != nullptr ? method->RevisitInformation(nodes, path_m)
                           : Localization::RevisitInformation(nodes, path_m);
}

}  // namespace splam::runtime
