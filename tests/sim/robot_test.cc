#include "sim/robot.h"

#include <gtest/gtest.h>

#include <cmath>

#include "kernel/angle.h"

namespace splam::sim {
namespace {

TEST(UnicycleIncrement, StraightAndArc) {
  const kernel::Pose2 straight = UnicycleIncrement(0.5, 0.0, 2.0);
  EXPECT_DOUBLE_EQ(straight.x(), 1.0);
  EXPECT_DOUBLE_EQ(straight.y(), 0.0);
  // A quarter circle of radius 1.
  const kernel::Pose2 arc = UnicycleIncrement(kernel::kPi / 2, kernel::kPi / 2, 1.0);
  EXPECT_NEAR(arc.x(), 1.0, 1e-12);
  EXPECT_NEAR(arc.y(), 1.0, 1e-12);
  EXPECT_NEAR(arc.theta(), kernel::kPi / 2, 1e-12);
  // Turning in place.
  const kernel::Pose2 spin = UnicycleIncrement(0.0, 1.0, 0.5);
  EXPECT_EQ(spin.translation(), Eigen::Vector2d::Zero());
  EXPECT_DOUBLE_EQ(spin.theta(), 0.5);
}

TEST(UnicycleIncrement, ManySmallStepsEqualOneBigStep) {
  kernel::Pose2 pose;
  for (int i = 0; i < 1000; ++i) pose = pose * UnicycleIncrement(0.3, 0.7, 0.001);
  EXPECT_LT(kernel::MaxAbsDifference(pose, UnicycleIncrement(0.3, 0.7, 1.0)), 1e-12);
}

TEST(CorruptIncrement, NoiselessIsExactAndNoiseScalesWithMotion) {
  kernel::Random random(1);
  const kernel::Pose2 u(0.1, 0.0, 0.05);
  EXPECT_LT(
      kernel::MaxAbsDifference(CorruptIncrement(u, OdometryNoiseOptions::Noiseless(), &random), u),
      0.0 + 1e-300);
  EXPECT_LT(
      kernel::MaxAbsDifference(CorruptIncrement(kernel::Pose2(), OdometryNoiseOptions(), &random),
                               kernel::Pose2()),
      1e-300);

  const OdometryNoiseOptions o;
  double sx = 0, sy = 0, sth = 0;
  const int n = 50000;
  for (int i = 0; i < n; ++i) {
    const kernel::Pose2 noisy = CorruptIncrement(u, o, &random);
    sx += std::pow(noisy.x() - u.x(), 2);
    sy += std::pow(noisy.y() - u.y(), 2);
    sth += std::pow(noisy.theta() - u.theta(), 2);
  }
  EXPECT_NEAR(std::sqrt(sx / n), o.forward_per_m * 0.1, 0.02 * o.forward_per_m * 0.1);
  EXPECT_NEAR(std::sqrt(sy / n), o.lateral_per_m * 0.1, 0.02 * o.lateral_per_m * 0.1);
  const double sigma_th = o.rotation_per_rad * 0.05 + o.rotation_per_m * 0.1;
  EXPECT_NEAR(std::sqrt(sth / n), sigma_th, 0.02 * sigma_th);
}

TEST(RobotOptions, ValidateAndDefaults) {
  EXPECT_TRUE(RobotOptions().Validate().ok());
  EXPECT_NEAR(RobotOptions().radius_m, 0.267, 1e-12);
  RobotOptions r;
  r.radius_m = -1;
  EXPECT_FALSE(r.Validate().ok());
  OdometryNoiseOptions o;
  o.lateral_per_m = -0.1;
  EXPECT_FALSE(o.Validate().ok());
}

}  // namespace
}  // namespace splam::sim
