#include "kernel/lines.h"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>

#include "kernel/angle.h"
#include "kernel/random.h"

namespace splam::kernel {
namespace {

// Points along the line x cos th + y sin th = rho, from s0 to s1 along its direction.
std::vector<Eigen::Vector2d> OnLine(double rho, double theta, double s0, double s1, double step) {
  const Eigen::Vector2d n(std::cos(theta), std::sin(theta)), t(-std::sin(theta), std::cos(theta));
  std::vector<Eigen::Vector2d> pts;
  for (double s = s0; s <= s1; s += step) pts.push_back(rho * n + s * t);
  return pts;
}

TEST(FitLineTls, PropertyNormalFormOfExactLines) {
  Random random(91);
  for (int trial = 0; trial < 500; ++trial) {
    const double rho = random.Uniform(0.0, 10.0), theta = random.Uniform(-kPi, kPi);
    const auto line = FitLineTls(OnLine(rho, theta, -2, 2.05, 0.1));  // s = -2, -1.9, ..., 2
    ASSERT_TRUE(line.has_value());
    EXPECT_GE(line->rho_m, 0.0);
    EXPECT_GT(line->theta_rad, -kPi);
    EXPECT_LE(line->theta_rad, kPi);
    EXPECT_NEAR(line->rho_m, rho, 1e-9);
    if (rho > 1e-6) {
      EXPECT_NEAR(WrapAngle(line->theta_rad - theta), 0.0, 1e-9);
    }
    EXPECT_NEAR(line->Length(), 4.0, 0.1);
    EXPECT_NEAR(line->SignedDistance(line->start), 0.0, 1e-9);
  }
}

TEST(FitLineTls, DegenerateInputs) {
  EXPECT_FALSE(FitLineTls({}).has_value());
  EXPECT_FALSE(FitLineTls({{1, 1}}).has_value());
  EXPECT_FALSE(FitLineTls({{1, 1}, {1, 1}, {1, 1}}).has_value());
  const auto two = FitLineTls({{0, 1}, {1, 1}});
  ASSERT_TRUE(two.has_value());
  EXPECT_NEAR(two->rho_m, 1.0, 1e-12);
  EXPECT_NEAR(two->theta_rad, kPi / 2, 1e-12);
}

TEST(LineCovariance, AgreesWithMonteCarlo) {
  Random random(92);
  const double rho = 3.0, theta = 0.4, sigma = 0.01;
  const auto truth = OnLine(rho, theta, -0.5, 1.5, 0.02);  // off-centre: rho and theta correlate
  Eigen::Matrix2d sum = Eigen::Matrix2d::Zero();
  const int runs = 4000;
  Eigen::Matrix2d predicted = Eigen::Matrix2d::Zero();
  for (int r = 0; r < runs; ++r) {
    std::vector<Eigen::Vector2d> noisy;
    for (const auto& p : truth)
      noisy.push_back(p + Eigen::Vector2d(random.Gaussian(sigma), random.Gaussian(sigma)));
    const auto line = FitLineTls(noisy);
    const Eigen::Vector2d e(line->rho_m - rho, WrapAngle(line->theta_rad - theta));
    sum += e * e.transpose();
    if (r == 0)
      predicted = LineCovariance(noisy, *line, std::vector<double>(noisy.size(), sigma * sigma));
  }
  const Eigen::Matrix2d empirical = sum / runs;
  EXPECT_NEAR(predicted(0, 0), empirical(0, 0), 0.1 * empirical(0, 0));
  EXPECT_NEAR(predicted(1, 1), empirical(1, 1), 0.1 * empirical(1, 1));
  EXPECT_NEAR(predicted(0, 1), empirical(0, 1), 0.15 * std::abs(empirical(0, 1)));
  EXPECT_GT(std::abs(empirical(0, 1)), 0.3 * std::sqrt(empirical(0, 0) * empirical(1, 1)));
}

TEST(RansacLines, PropertyRecoversLinesWithThirtyPercentOutliers) {
  Random random(93);
  LineExtractionOptions options;
  // The outliers are interleaved at random places, not in scan order: no contiguity rule here.
  options.max_point_gap_m = 100.0;
  for (int trial = 0; trial < 50; ++trial) {
    const double rho = random.Uniform(0.5, 5.0), theta = random.Uniform(-kPi, kPi);
    std::vector<Eigen::Vector2d> pts;
    std::vector<std::size_t> inliers;
    for (const auto& p : OnLine(rho, theta, -1.5, 1.5, 0.02)) {
      inliers.push_back(pts.size());
      pts.push_back(p + Eigen::Vector2d(random.Gaussian(0.01), random.Gaussian(0.01)));
      // 3 outliers for every 7 inliers, scattered around the line.
      if (random.Uniform() < 3.0 / 7.0) {
        pts.push_back(p + Eigen::Vector2d(random.Uniform(-1, 1), random.Uniform(-1, 1)));
      }
    }
    EXPECT_NEAR(static_cast<double>(pts.size() - inliers.size()) / static_cast<double>(pts.size()),
                0.3, 0.06);
    const std::vector<double> sigma2(pts.size(), 1e-4);
    const auto lines = RansacLines(pts, sigma2, options, &random);
    ASSERT_FALSE(lines.empty()) << "trial " << trial;
    const LineFeature& best =
        *std::max_element(lines.begin(), lines.end(), [](const auto& a, const auto& b) {
          return a.point_indices.size() < b.point_indices.size();
        });
    EXPECT_NEAR(best.rho_m, rho, 0.02) << "trial " << trial;
    EXPECT_NEAR(WrapAngle(best.theta_rad - theta), 0.0, 0.02) << "trial " << trial;
    std::size_t found = 0;
    for (std::size_t i : inliers)
      found += std::binary_search(best.point_indices.begin(), best.point_indices.end(), i);
    EXPECT_GE(static_cast<double>(found), 0.9 * static_cast<double>(inliers.size()))
        << "trial " << trial;
  }
}

TEST(ExtractLines, CornerOfTwoWallsAndReproducibleSeeds) {
  // An LMS-200 scan of a room corner: walls x = 3 and y = 2.
  Scan scan;
  scan.start_angle_rad = -kPi / 2;
  scan.angular_step_rad = DegToRad(0.5);
  scan.max_range_m = 8.0;
  Random noise(94);
  for (int i = 0; i < 361; ++i) {
    const double a = scan.BeamAngle(i);
    const double to_x = std::cos(a) > 1e-9 ? 3.0 / std::cos(a) : 1e9;
    const double to_y = std::sin(a) > 1e-9 ? 2.0 / std::sin(a) : 1e9;
    const double r = std::min(to_x, to_y);
    scan.ranges_m.push_back(r < 8.0 ? r + noise.Gaussian(0.01) : Scan::kNoReturn);
  }
  const LineExtraction a = ExtractLines(scan);
  ASSERT_EQ(a.lines.size(), 2u);
  EXPECT_NEAR(a.lines[0].rho_m, 3.0, 0.01);
  EXPECT_NEAR(a.lines[0].theta_rad, 0.0, 0.01);
  EXPECT_NEAR(a.lines[1].rho_m, 2.0, 0.01);
  EXPECT_NEAR(a.lines[1].theta_rad, kPi / 2, 0.01);
  ASSERT_EQ(a.corners.size(), 1u);
  EXPECT_LT((a.corners[0].position - Eigen::Vector2d(3, 2)).norm(), 0.03);
  EXPECT_NEAR(a.corners[0].angle_rad, kPi / 2, 0.02);
  for (const LineFeature& l : a.lines) {
    EXPECT_GT(l.covariance(0, 0), 0.0);
    EXPECT_GT(l.covariance.determinant(), 0.0);
  }
  const LineExtraction b = ExtractLines(scan);
  ASSERT_EQ(b.lines.size(), a.lines.size());
  EXPECT_EQ(b.lines[0].point_indices, a.lines[0].point_indices);
}

TEST(ExtractLines, EmptyAndDegenerateScans) {
  EXPECT_TRUE(ExtractLines(Scan()).lines.empty());
  Scan blind;
  blind.angular_step_rad = 0.01;
  blind.max_range_m = 4;
  blind.ranges_m.assign(100, NAN);
  EXPECT_TRUE(ExtractLines(blind).lines.empty());
  blind.ranges_m.assign(100, 1.0);  // a circle arc: no straight line longer than the tolerance
  const auto arc = ExtractLines(blind);
  for (const auto& l : arc.lines) EXPECT_TRUE(std::isfinite(l.rho_m));
}

TEST(LineExtractionOptions, Validate) {
  EXPECT_TRUE(LineExtractionOptions().Validate().ok());
  LineExtractionOptions o;
  o.min_points = 1;
  EXPECT_FALSE(o.Validate().ok());
}

}  // namespace
}  // namespace splam::kernel
