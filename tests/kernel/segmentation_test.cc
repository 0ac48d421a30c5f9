#include "kernel/segmentation.h"

#include <gtest/gtest.h>

#include <cmath>

#include "kernel/angle.h"

namespace splam::kernel {
namespace {

// A scan at 0.5 deg of the given range function.
template <class F>
Scan MakeScan(F range_of_angle) {
  Scan s;
  s.start_angle_rad = -kPi / 2;
  s.angular_step_rad = DegToRad(0.5);
  s.max_range_m = 8.0;
  for (int i = 0; i < 361; ++i) s.ranges_m.push_back(range_of_angle(s.BeamAngle(i)));
  return s;
}

// A wall at x = 2 for angles < 0 and a wall at x = 4 for angles >= 0: a depth jump at 0.
Scan TwoWalls() {
  return MakeScan([](double a) {
    if (std::abs(a) > 1.2) return Scan::kNoReturn;
    return (a < 0 ? 2.0 : 4.0) / std::cos(a);
  });
}

TEST(SegmentScan, DietmayerSplitsAtDepthJumps) {
  const auto segments = SegmentScan(TwoWalls());
  ASSERT_EQ(segments.size(), 2u);
  for (const auto& p : segments[0].points) EXPECT_NEAR(p.x(), 2.0, 1e-9);
  for (const auto& p : segments[1].points) EXPECT_NEAR(p.x(), 4.0, 1e-9);
  EXPECT_EQ(segments[0].beams.front() + segments[0].points.size() - 1, segments[0].beams.back());
}

TEST(SegmentScan, NoReturnAndInvalidReadingsNeverJoinSegments) {
  Scan s = MakeScan([](double a) { return 2.0 / std::cos(std::clamp(a, -1.0, 1.0)); });
  s.ranges_m[180] = Scan::kNoReturn;
  s.ranges_m[200] = NAN;
  s.ranges_m[220] = -1.0;
  const auto segments = SegmentScan(s);
  ASSERT_EQ(segments.size(), 4u);
  EXPECT_EQ(segments[0].beams.back(), 179u);
  EXPECT_EQ(segments[1].beams.front(), 181u);
  EXPECT_EQ(segments[1].beams.back(), 199u);
  for (const auto& seg : segments) {
    for (std::size_t b : seg.beams) EXPECT_TRUE(s.IsHit(b));
  }
}

TEST(SegmentScan, MinimumLengthAndPointsFilter) {
  Scan s =
      MakeScan([](double a) { return std::abs(a - 0.3) < DegToRad(2.1) ? 3.0 : Scan::kNoReturn; });
  // 9 points over about 0.22 m: below the default 0.25 m.
  EXPECT_TRUE(SegmentScan(s).empty());
  SegmentationOptions o;
  o.min_length_m = 0.1;
  EXPECT_EQ(SegmentScan(s, o).size(), 1u);
  o.min_points = 20;
  EXPECT_TRUE(SegmentScan(s, o).empty());
}

TEST(SegmentScan, PedrazaSplitsSharpCornersDietmayerKeepsThem) {
  // A right-angled corner: wall y = 2 (x from -2 to 2) meeting wall x = 2.
  const Scan corner = MakeScan([](double a) {
    const double to_y = std::sin(a) > 0 ? 2.0 / std::sin(a) : 1e9;
    const double to_x = std::cos(a) > 0 ? 2.0 / std::cos(a) : 1e9;
    const double r = std::min(to_x, to_y);
    return r < 6.0 && a > -0.5 ? r : Scan::kNoReturn;
  });
  EXPECT_EQ(SegmentScan(corner).size(), 1u);
  SegmentationOptions pedraza;
  pedraza.method = SegmentationMethod::kPedraza;
  const auto parts = SegmentScan(corner, pedraza);
  ASSERT_EQ(parts.size(), 2u);
  // The split is at the corner (2, 2).
  EXPECT_LT((parts[0].points.back() - Eigen::Vector2d(2, 2)).norm(), 0.1);
  EXPECT_LT((parts[1].points.front() - Eigen::Vector2d(2, 2)).norm(), 0.1);
  // Pedraza's spacing test also splits at the depth jump.
  EXPECT_EQ(SegmentScan(TwoWalls(), pedraza).size(), 2u);
}

TEST(SegmentScan, EmptyAndBlindScansGiveNoSegments) {
  EXPECT_TRUE(SegmentScan(Scan()).empty());
  EXPECT_TRUE(SegmentScan(MakeScan([](double) { return NAN; })).empty());
  EXPECT_TRUE(SegmentScan(MakeScan([](double) { return Scan::kNoReturn; })).empty());
}

TEST(SegmentationOptions, Validate) {
  EXPECT_TRUE(SegmentationOptions().Validate().ok());
  SegmentationOptions o;
  o.pedraza_eta = 0.5;
  EXPECT_FALSE(o.Validate().ok());
}

}  // namespace
}  // namespace splam::kernel
