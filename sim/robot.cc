#include "sim/robot.h"

#include <cmath>

namespace splam::sim {

kernel::Status RobotOptions::Validate() const {
  if (!(radius_m > 0.0)) return kernel::Status::Error("robot radius_m must be positive");
  if (!(max_linear_speed_mps > 0.0) || !(max_angular_speed_radps > 0.0)) {
    return kernel::Status::Error("robot speed limits must be positive");
  }
  return kernel::Status::Ok();
}

kernel::Status OdometryNoiseOptions::Validate() const {
  if (!(forward_per_m >= 0.0) || !(lateral_per_m >= 0.0) || !(rotation_per_rad >= 0.0) ||
      !(rotation_per_m >= 0.0)) {
    return kernel::Status::Error("odometry noise coefficients must be >= 0");
  }
  return kernel::Status::Ok();
}

kernel::Pose2 CorruptIncrement(const kernel::Pose2& increment, const OdometryNoiseOptions& options,
                               kernel::Random* random) {
  const double d = increment.translation().norm();
  const double dx = increment.x() + random->Gaussian(options.forward_per_m * d);
  const double dy = increment.y() + random->Gaussian(options.lateral_per_m * d);
  const double dth =
      increment.theta() + random->Gaussian(options.rotation_per_rad * std::abs(increment.theta()) +
                                           options.rotation_per_m * d);
  return kernel::Pose2(dx, dy, dth);
}

void RobotOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Field("radius_m", &radius_m, "the robot is a disc of this radius, m");
  v.Field("max_linear_speed_mps", &max_linear_speed_mps, "|v| limit, m/s");
  v.Field("max_angular_speed_radps", &max_angular_speed_radps, "|w| limit, rad/s");
}

void OdometryNoiseOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Field("forward_per_m", &forward_per_m, "forward error sigma per m travelled");
  v.Field("lateral_per_m", &lateral_per_m, "sideways error sigma per m travelled");
  v.Field("rotation_per_rad", &rotation_per_rad, "heading error sigma per rad turned");
  v.Field("rotation_per_m", &rotation_per_m, "heading error sigma per m travelled, rad/m");
}

}  // namespace splam::sim
