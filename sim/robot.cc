#include "sim/robot.h"

#include <cmath>

namespace splam::sim {

std::string RobotOptions::Validate() const {
  if (!(radius_m > 0.0)) return "robot radius_m must be positive";
  if (!(max_linear_speed_mps > 0.0) || !(max_angular_speed_radps > 0.0)) {
    return "robot speed limits must be positive";
  }
  return "";
}

std::string OdometryNoiseOptions::Validate() const {
  if (!(forward_per_m >= 0.0) || !(lateral_per_m >= 0.0) || !(rotation_per_rad >= 0.0) ||
      !(rotation_per_m >= 0.0)) {
    return "odometry noise coefficients must be >= 0";
  }
  return "";
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

}  // namespace splam::sim
