#include "kernel/scan.h"

#include <gtest/gtest.h>

#include <cmath>

#include "kernel/angle.h"
#include "kernel/random.h"

namespace splam::kernel {
namespace {

Scan MakeScan() {
  Scan s;
  s.start_angle_rad = -kPi / 2;
  s.angular_step_rad = kPi / 2;
  s.min_range_m = 0.1;
  s.max_range_m = 10.0;
  //            hit   no-return      NaN  negative  below min  at max  hit
  s.ranges_m = {1.0, Scan::kNoReturn, NAN, -1.0, 0.05, 10.0, 2.0};
  return s;
}

TEST(Scan, ClassifiesReadings) {
  const Scan s = MakeScan();
  EXPECT_TRUE(s.IsHit(0));
  EXPECT_FALSE(s.IsHit(1));
  EXPECT_TRUE(s.IsNoReturn(1));
  EXPECT_FALSE(s.IsHit(2));
  EXPECT_FALSE(s.IsNoReturn(2));
  EXPECT_FALSE(s.IsHit(3));
  EXPECT_FALSE(s.IsHit(4));
  EXPECT_FALSE(s.IsHit(5));
  EXPECT_TRUE(s.IsHit(6));
}

TEST(Scan, BeamAnglesAndFieldOfView) {
  const Scan s = MakeScan();
  EXPECT_DOUBLE_EQ(s.BeamAngle(0), -kPi / 2);
  EXPECT_DOUBLE_EQ(s.BeamAngle(2), kPi / 2);
  EXPECT_DOUBLE_EQ(s.FieldOfView(), 3 * kPi);
  EXPECT_EQ(Scan().FieldOfView(), 0.0);
}

TEST(Scan, HitPointsSkipEverythingButHits) {
  const Scan s = MakeScan();
  const auto points = s.HitPoints();
  ASSERT_EQ(points.size(), 2u);
  EXPECT_NEAR(points[0].x(), 0.0, 1e-15);
  EXPECT_NEAR(points[0].y(), -1.0, 1e-15);
  // Beam 6 at -pi/2 + 6 * pi/2 = 5 pi/2 -> straight ahead-left (0, 2).
  EXPECT_NEAR(points[1].x(), 0.0, 1e-14);
  EXPECT_NEAR(points[1].y(), 2.0, 1e-14);
  EXPECT_EQ(s.HitIndices(), (std::vector<std::size_t>{0, 6}));
  for (const auto& p : points) EXPECT_TRUE(p.allFinite());
}

TEST(Scan, EmptyScanHasNoPoints) {
  Scan s;
  EXPECT_TRUE(s.HitPoints().empty());
  EXPECT_EQ(s.size(), 0u);
}

TEST(PolarCartesian, PropertyRoundTrip) {
  Random random(3);
  for (int i = 0; i < 1000; ++i) {
    const Polar polar{random.Uniform(0.01, 80.0), random.Uniform(-kPi + 1e-9, kPi)};
    const Polar back = CartesianToPolar(PolarToCartesian(polar));
    EXPECT_NEAR(back.range_m, polar.range_m, 1e-12);
    EXPECT_NEAR(WrapAngle(back.angle_rad - polar.angle_rad), 0.0, 1e-12);
  }
  EXPECT_EQ(CartesianToPolar({0, 0}).range_m, 0.0);
  EXPECT_EQ(CartesianToPolar({0, 0}).angle_rad, 0.0);
}

}  // namespace
}  // namespace splam::kernel
