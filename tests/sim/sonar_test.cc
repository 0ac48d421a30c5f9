#include "sim/sonar.h"

#include <gtest/gtest.h>

#include <cmath>

#include "kernel/angle.h"
#include "kernel/scan.h"

namespace splam::sim {
namespace {

TEST(SonarOptions, PioneerRingHas16SensorsAndCoversTheBack) {
  const auto ring = SonarOptions::PioneerRing();
  ASSERT_EQ(ring.size(), 16u);
  int rear = 0;
  for (const auto& p : ring) {
    if (std::abs(p.theta()) >= kernel::DegToRad(130) - 1e-9) ++rear;
  }
  EXPECT_EQ(rear, 6);  // -130, -150, -170, 170, 150, 130
  EXPECT_TRUE(SonarOptions().Validate().ok());
  SonarOptions bad;
  bad.rays_per_cone = 0;
  EXPECT_FALSE(bad.Validate().ok());
}

TEST(SimulateSonar, ReadsTheNearestEchoInTheCone) {
  World w;
  w.obstacles.push_back(kernel::Circle2{{0, 0}, 2.0});
  const RayCaster caster(w);
  SonarOptions o;
  o.noise_fraction = 0.0;
  o.noise_floor_m = 0.0;
  kernel::Random random(1);
  const auto ranges = SimulateSonar(caster, o, kernel::Pose2(), &random);
  ASSERT_EQ(ranges.size(), 16u);
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    // Mounted at distance d from the centre along roughly its heading: about 2 - d.
    const double d = o.robot_T_sonar[i].translation().norm();
    EXPECT_GT(ranges[i], 2.0 - d - 0.05);
    EXPECT_LT(ranges[i], 2.0 - d * 0.5 + 0.05);
  }
  w.obstacles[0] = kernel::Circle2{{0, 0}, 20.0};
  const RayCaster far(w);
  for (double r : SimulateSonar(far, o, kernel::Pose2(), &random))
    EXPECT_EQ(r, kernel::Scan::kNoReturn);
}

TEST(SimulateSonar, ConeSeesAnObstacleOffTheAxis) {
  World w;
  w.obstacles.push_back(kernel::Circle2{{2.0, 0.4}, 0.2});  // seen from 5.7 to 16.9 deg
  const RayCaster caster(w);
  SonarOptions o;
  o.robot_T_sonar = {kernel::Pose2()};
  o.noise_fraction = o.noise_floor_m = 0.0;
  kernel::Random random(2);
  EXPECT_LT(SimulateSonar(caster, o, kernel::Pose2(), &random)[0], 2.1);
  o.cone_half_angle_rad = 0.0;
  o.rays_per_cone = 1;
  EXPECT_EQ(SimulateSonar(caster, o, kernel::Pose2(), &random)[0], kernel::Scan::kNoReturn);
}

}  // namespace
}  // namespace splam::sim
