#include "exploration/localization.h"

#include <cassert>

namespace splam::exploration {

kernel::Status GroundTruthLocalization::Start(const RobotDescription& /*robot*/,
                                              const kernel::Pose2& /*start*/,
                                              const Perception& first) {
  if (!first.true_pose)
    return kernel::Status::Error(
        "ground-truth localisation needs a robot that reports its true pose");
  return {};
}

kernel::Pose2 GroundTruthLocalization::Update(const Perception& perception) {
  assert(perception.true_pose.has_value());
  return *perception.true_pose;
}

kernel::Status OdometryLocalization::Start(const RobotDescription& /*robot*/,
                                           const kernel::Pose2& start, const Perception& first) {
  world_T_odometry_ = start * first.odometry_pose.Inverse();
  return {};
}

kernel::Pose2 OdometryLocalization::Update(const Perception& perception) {
  return world_T_odometry_ * perception.odometry_pose;
}

}  // namespace splam::exploration
