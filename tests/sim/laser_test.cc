#include "sim/laser.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

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

// A person in front of a wall: the beams that meet the disc read its near side and report no
// world obstacle; the others read the wall.
TEST(SimulateLaser, PeopleAreSeenInFrontOfTheWalls) {
  const RayCaster caster(RoundRoom(10.0));
  LaserOptions o = LaserOptions::Lms200(1.0);
  o.max_range_m = 20.0;
  o.noise_floor_m = 0.0;
  kernel::Random random(1);
  std::vector<int> obstacles;
  const std::vector<kernel::Circle2> people = {{{4.0, 0.0}, 0.25}};
  const kernel::Scan scan =
      SimulateLaser(caster, o, Pose2(0, 0, 0), 0.0, &random, &obstacles, people);
  const int ahead = 90;  // the beam at 0 rad
  EXPECT_NEAR(scan.ranges_m[ahead], 3.75, 1e-9);
  EXPECT_EQ(obstacles[ahead], -1);
  int on_person = 0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const double bearing = scan.BeamAngle(i);
    const bool hits = std::abs(4.0 * std::sin(bearing)) < 0.25 && std::cos(bearing) > 0.0;
    on_person += hits;
    if (hits) {
      EXPECT_GE(scan.ranges_m[i], 3.75 - 1e-9) << i;
      EXPECT_LT(scan.ranges_m[i], 4.0) << i;
    } else {
      EXPECT_NEAR(scan.ranges_m[i], 10.0, 1e-9) << i;
    }
    EXPECT_EQ(obstacles[i], hits ? -1 : 0) << i;
  }
  EXPECT_EQ(on_person, 7);  // |bearing| < asin(0.25 / 4) = 3.6 deg at 1 deg
}

// A pane of glass across the room: the beams that meet it read no return (not the wall behind
// it) and report no obstacle; the robot still collides with it; the others read the wall.
TEST(SimulateLaser, GlassReadsNoReturnButStopsTheRobot) {
  World w = RoundRoom(10.0);
  w.obstacles.push_back(Polyline{{{4.0, -1.0}, {4.0, 1.0}}, false});
  w.glass = {1};
  ASSERT_TRUE(w.Validate().ok());
  const RayCaster caster(w);
  EXPECT_TRUE(caster.IsGlass(1));
  EXPECT_FALSE(caster.IsGlass(0));
  EXPECT_TRUE(caster.Collides({4.1, 0.0}, 0.2));
  LaserOptions o = LaserOptions::Lms200(1.0);
  o.max_range_m = 20.0;
  o.noise_floor_m = 0.0;
  kernel::Random random(1);
  std::vector<int> obstacles;
  const kernel::Scan scan = SimulateLaser(caster, o, Pose2(0, 0, 0), 0.0, &random, &obstacles);
  int on_glass = 0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const double bearing = scan.BeamAngle(i);
    const bool glass = std::cos(bearing) > 0.0 && std::abs(4.0 * std::tan(bearing)) <= 1.0;
    on_glass += glass;
    if (glass) {
      EXPECT_TRUE(scan.IsNoReturn(i)) << i;
      EXPECT_EQ(obstacles[i], -1) << i;
    } else {
      EXPECT_NEAR(scan.ranges_m[i], 10.0, 1e-9) << i;
      EXPECT_EQ(obstacles[i], 0) << i;
    }
  }
  EXPECT_EQ(on_glass, 29);  // |bearing| <= atan(1 / 4) = 14.04 deg at 1 deg
  w.glass = {2};
  EXPECT_EQ(w.Validate().message(), "glass obstacle 2 does not exist (2 obstacles)");
}

// An interlacing laser cycles through its phases: sweep k starts (k mod n) / n of a step later,
// drops a beam when shifted, and every beam stays within the unshifted field of view.
TEST(LaserOptions, PropertyInterlacedSweepsStayInTheFieldOfView) {
  LaserOptions o = LaserOptions::Lms200(1.0);
  o.interlace_phases = 4;
  ASSERT_TRUE(o.Validate().ok());
  const double last = o.start_angle_rad + (o.num_beams - 1) * o.angular_step_rad;
  for (long long k = 0; k < 12; ++k) {
    const LaserOptions s = o.Sweep(k);
    EXPECT_NEAR(s.start_angle_rad, o.start_angle_rad + static_cast<double>(k % 4) * DegToRad(0.25),
                1e-12);
    EXPECT_EQ(s.num_beams, k % 4 == 0 ? 181 : 180);
    EXPECT_LE(s.start_angle_rad + (s.num_beams - 1) * s.angular_step_rad, last + 1e-12);
  }
  o.interlace_phases = 0;
  EXPECT_FALSE(o.Validate().ok());
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
