#include "kernel/spline_extraction.h"

#include <gtest/gtest.h>

#include "kernel/angle.h"

namespace splam::kernel {
namespace {

TEST(ExtractCurves, CurvesFollowTheirSegments) {
  // A scan of a circle of radius 2 around the sensor with a gap: two arcs.
  Scan scan;
  scan.start_angle_rad = -2.0;
  scan.angular_step_rad = DegToRad(0.36);
  scan.max_range_m = 4.0;
  for (int i = 0; i < 667; ++i) scan.ranges_m.push_back(i > 300 && i < 320 ? Scan::kNoReturn : 2.0);
  const auto curves = ExtractCurves(scan);
  ASSERT_EQ(curves.size(), 2u);
  for (const SplineCurve& c : curves) {
    EXPECT_EQ(c.points.size(), c.beams.size());
    for (const auto& q : c.samples) EXPECT_NEAR(q.norm(), 2.0, 1e-3);
    EXPECT_NEAR(c.profile.curvature[c.profile.curvature.size() / 2], 0.5, 0.01);
    EXPECT_TRUE(c.features.empty());
  }
  EXPECT_EQ(curves[0].beams.back(), 300u);
  EXPECT_EQ(curves[1].beams.front(), 320u);
}

TEST(ExtractCurve, DegenerateInputIsAnError) {
  std::string error;
  EXPECT_FALSE(ExtractCurve({{0, 0}, {0, 0}, {0, 0}, {0, 0}}, {}, &error));
  EXPECT_FALSE(error.empty());
  EXPECT_TRUE(ExtractCurves(Scan()).empty());
}

TEST(SplineExtractionOptions, Validate) {
  EXPECT_TRUE(SplineExtractionOptions().Validate().ok());
  SplineExtractionOptions o;
  o.epsilon_m = 0;
  EXPECT_FALSE(o.Validate().ok());
}

}  // namespace
}  // namespace splam::kernel
