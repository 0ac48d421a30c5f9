#include "kernel/spline_extraction.h"

#include <gtest/gtest.h>

#include <random>

#include "kernel/angle.h"
#include "kernel/shapes.h"

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
  const Result<SplineCurve> curve = ExtractCurve({{0, 0}, {0, 0}, {0, 0}, {0, 0}});
  EXPECT_FALSE(curve);
  EXPECT_NE(curve.error.find("distinct"), std::string::npos) << curve.error;
  EXPECT_TRUE(ExtractCurves(Scan()).empty());
}

// Scans whose beams wrap past a full turn (a resolution in degrees read as radians)
// crashed with a 26 GB allocation or hung. Every curve extracted from them is bounded by its
// points' path, whatever the beams' order.
TEST(ExtractCurves, PropertyScansThatWrapGiveBoundedCurves) {
  std::mt19937 gen(19);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 40; ++trial) {
    Scan scan;
    scan.start_angle_rad = -kPi;
    scan.angular_step_rad = 0.05 + 6.0 * unit(gen);
    scan.max_range_m = 30.0;
    const int n = 100 + static_cast<int>(600 * unit(gen));
    for (int i = 0; i < n; ++i) scan.ranges_m.push_back(0.5 + 10.0 * unit(gen));
    for (const SplineCurve& c : ExtractCurves(scan)) {
      const double path = PolylineLength(c.points);
      EXPECT_LE(c.spline.Length(), kMaxLengthRatio * path) << trial;
      EXPECT_LE(static_cast<double>(c.samples.size()),
                kMaxLengthRatio * path / SplineExtractionOptions().epsilon_m + 1.0)
          << trial;
    }
  }
}

// A curve whose length overflows (control points at 1e300) samples to nothing instead of asking
// for an allocation sized by it.
TEST(CubicBSpline, ResamplingAnOverflowingCurveAllocatesNothing) {
  const Result<CubicBSpline> huge =
      CubicBSpline::ClampedUniform({{0, 0}, {1e300, 0}, {-1e300, 1e300}, {1e300, -1e300}});
  ASSERT_TRUE(huge);
  EXPECT_TRUE(huge->ResampleByArcLength(0.01).empty());
  const Result<CubicBSpline> fine = CubicBSpline::ClampedUniform({{0, 0}, {1, 0}, {2, 0}, {3, 0}});
  ASSERT_TRUE(fine);
  EXPECT_EQ(fine->ResampleByArcLength(0.01).size(), 301u);
}

TEST(SplineExtractionOptions, Validate) {
  EXPECT_TRUE(SplineExtractionOptions().Validate().ok());
  SplineExtractionOptions o;
  o.epsilon_m = 0;
  EXPECT_FALSE(o.Validate().ok());
}

}  // namespace
}  // namespace splam::kernel
