#include "kernel/angle.h"

#include <gtest/gtest.h>

#include <cmath>

#include "kernel/random.h"

namespace splam::kernel {
namespace {

TEST(WrapAngle, KeepsValuesInsideTheRange) {
  EXPECT_DOUBLE_EQ(WrapAngle(0.5), 0.5);
  EXPECT_DOUBLE_EQ(WrapAngle(-0.5), -0.5);
  EXPECT_DOUBLE_EQ(WrapAngle(kPi), kPi);
}

TEST(WrapAngle, MapsMinusPiToPi) { EXPECT_DOUBLE_EQ(WrapAngle(-kPi), kPi); }

TEST(WrapAngle, WrapsLargeAngles) {
  EXPECT_NEAR(WrapAngle(3.0 * kPi / 2.0), -kPi / 2.0, 1e-15);
  EXPECT_NEAR(WrapAngle(-3.0 * kPi / 2.0), kPi / 2.0, 1e-15);
  EXPECT_NEAR(WrapAngle(100.0), 100.0 - 16.0 * 2.0 * kPi, 1e-12);
}

TEST(WrapAngle, PropertyResultInRangeAndSameDirection) {
  Random random(11);
  for (int i = 0; i < 1000; ++i) {
    const double a = random.Uniform(-1000.0, 1000.0);
    const double w = WrapAngle(a);
    EXPECT_GT(w, -kPi);
    EXPECT_LE(w, kPi);
    EXPECT_NEAR(std::cos(w), std::cos(a), 1e-9);
    EXPECT_NEAR(std::sin(w), std::sin(a), 1e-9);
  }
}

TEST(WrapAngle, NanStaysNan) { EXPECT_TRUE(std::isnan(WrapAngle(NAN))); }

TEST(DegToRad, RoundTrips) {
  EXPECT_DOUBLE_EQ(DegToRad(180.0), kPi);
  EXPECT_DOUBLE_EQ(RadToDeg(DegToRad(37.5)), 37.5);
}

}  // namespace
}  // namespace splam::kernel
