#include "sim/laser.h"

#include <gtest/gtest.h>

#include <cmath>

#include "kernel/angle.h"

namespace splam::sim {
namespace {

using kernel::DegToRad;
using kernel::Pose2;

World RoundRoom(double radius) {
  World w;
  w.obstacles.push_back(kernel::Circle2{{0, 0}, radius});
  return w;
}

TEST(LaserOptions, PublishedModels) {
  const LaserOptions urg = LaserOptions::Urg04lx();
  EXPECT_EQ(urg.num_beams, 667);
  EXPECT_NEAR(kernel::RadToDeg((urg.num_beams - 1) * urg.angular_step_rad), 239.76, 1e-9);
  EXPECT_NEAR(urg.start_angle_rad, -0.5 * (urg.num_beams - 1) * urg.angular_step_rad, 1e-15);
  EXPECT_EQ(urg.max_range_m, 4.0);
  EXPECT_EQ(urg.min_range_m, 0.02);
  EXPECT_EQ(urg.noise_fraction, 0.01);
  EXPECT_TRUE(urg.Validate().ok());
  const LaserOptions lms = LaserOptions::Lms200(0.5);
  EXPECT_EQ(lms.num_beams, 361);
  EXPECT_EQ(lms.max_range_m, 8.0);
  EXPECT_EQ(lms.noise_floor_m, 0.01);
  EXPECT_EQ(LaserOptions::Lms200(1.0).num_beams, 181);
  EXPECT_NEAR(lms.start_angle_rad, -kernel::kPi / 2, 1e-15);
}

TEST(LaserOptions, ValidateCatchesNonsense) {
  LaserOptions o = LaserOptions::Urg04lx();
  o.num_beams = 0;
  EXPECT_FALSE(o.Validate().ok());
  o = LaserOptions::Urg04lx();
  o.max_range_m = 0.01;
  EXPECT_FALSE(o.Validate().ok());
  o = LaserOptions::Urg04lx();
  o.dropout_probability = 2;
  EXPECT_FALSE(o.Validate().ok());
}

TEST(SimulateLaser, NoiselessRangesAreExact) {
  const RayCaster caster(RoundRoom(3.0));
  LaserOptions o = LaserOptions::Urg04lx();
  o.noise_fraction = 0.0;
  kernel::Random random(1);
  std::vector<int> obstacles;
  const kernel::Scan scan = SimulateLaser(caster, o, Pose2(0, 0, 0.3), 1.5, &random, &obstacles);
  ASSERT_EQ(scan.size(), 667u);
  EXPECT_EQ(scan.timestamp_s, 1.5);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    EXPECT_NEAR(scan.ranges_m[i], 3.0, 1e-12);
    EXPECT_EQ(obstacles[i], 0);
  }
}

TEST(SimulateLaser, BeamsPointWhereTheScanSays) {
  // A wall at x = 2 in front of the robot: beam at angle a reads 2 / cos(a).
  World w;
  w.obstacles.push_back(Polyline{{{2, -10}, {2, 10}}, false});
  const RayCaster caster(w);
  LaserOptions o = LaserOptions::Lms200(1.0);
  o.noise_floor_m = 0.0;
  kernel::Random random(1);
  const kernel::Scan scan = SimulateLaser(caster, o, Pose2(), 0.0, &random);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const double a = scan.BeamAngle(i);
    if (std::abs(std::cos(a)) > 2.0 / 8.0 + 1e-6) {
      EXPECT_NEAR(scan.ranges_m[i], 2.0 / std::cos(a), 1e-9) << i;
    } else {
      EXPECT_TRUE(scan.IsNoReturn(i)) << i;  // beyond 8 m
    }
  }
}

TEST(SimulateLaser, NoiseIsOnePercentOfTheRange) {
  const RayCaster caster(RoundRoom(3.0));
  const LaserOptions o = LaserOptions::Urg04lx();
  kernel::Random random(2);
  double sum = 0, sum2 = 0;
  int n = 0;
  for (int k = 0; k < 30; ++k) {
    const kernel::Scan scan = SimulateLaser(caster, o, Pose2(), 0.0, &random);
    for (double r : scan.ranges_m) {
      sum += r - 3.0;
      sum2 += (r - 3.0) * (r - 3.0);
      ++n;
    }
  }
  EXPECT_NEAR(sum / n, 0.0, 0.002);
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.03, 0.002);
}

TEST(SimulateLaser, FarObstaclesReadNoReturnAndLaserMountIsApplied) {
  const RayCaster caster(RoundRoom(6.0));
  LaserOptions o = LaserOptions::Urg04lx();
  kernel::Random random(3);
  for (double r : SimulateLaser(caster, o, Pose2(), 0.0, &random).ranges_m)
    EXPECT_EQ(r, kernel::Scan::kNoReturn);
  // Mounted 3 m ahead, a 4 m laser sees the wall 3 m ahead of itself.
  o.robot_T_laser = Pose2(3.0, 0.0, 0.0);
  o.noise_fraction = 0.0;
  const kernel::Scan scan = SimulateLaser(caster, o, Pose2(), 0.0, &random);
  EXPECT_NEAR(scan.ranges_m[333], 3.0, 1e-12);
}

TEST(SimulateLaser, DropoutAndTooCloseReadings) {
  const RayCaster caster(RoundRoom(2.0));
  LaserOptions o = LaserOptions::Urg04lx();
  o.dropout_probability = 1.0;
  kernel::Random random(4);
  for (double r : SimulateLaser(caster, o, Pose2(), 0.0, &random).ranges_m)
    EXPECT_EQ(r, kernel::Scan::kNoReturn);
  o.dropout_probability = 0.0;
  o.min_range_m = 2.5;
  o.max_range_m = 4.0;
  for (double r : SimulateLaser(caster, o, Pose2(), 0.0, &random).ranges_m)
    EXPECT_TRUE(std::isnan(r));
}

}  // namespace
}  // namespace splam::sim
