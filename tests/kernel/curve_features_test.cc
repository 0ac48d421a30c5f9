// Inflection points and corners through the whole curve pipeline (fit, resample, smooth).
#include "kernel/curve_features.h"

#include <gtest/gtest.h>

#include <cmath>

#include "kernel/angle.h"
#include "kernel/random.h"
#include "kernel/spline_extraction.h"

namespace splam::kernel {
namespace {

Eigen::Vector2d Noise(Random* r, double sigma) { return {r->Gaussian(sigma), r->Gaussian(sigma)}; }

std::vector<CurveFeature> OfType(const std::vector<CurveFeature>& all, FeatureType type) {
  std::vector<CurveFeature> out;
  for (const auto& f : all) {
    if (f.type == type) out.push_back(f);
  }
  return out;
}

// Two 1 m arms meeting at the origin at a right angle, points 1.5 cm apart, noise sigma.
std::vector<Eigen::Vector2d> LCorner(Random* r, double sigma) {
  std::vector<Eigen::Vector2d> pts;
  for (double x = -1.0; x < 0; x += 0.015) pts.push_back(Eigen::Vector2d(x, 0) + Noise(r, sigma));
  for (double y = 0; y <= 1.0; y += 0.015) pts.push_back(Eigen::Vector2d(0, y) + Noise(r, sigma));
  return pts;
}

TEST(FindFeatures, PropertyRightAngleGivesExactlyOneCornerAtTheRightPlace) {
  Random random(81);
  for (int trial = 0; trial < 100; ++trial) {
    const Pose2 pose(random.Uniform(-5, 5), random.Uniform(-5, 5), random.Uniform(-kPi, kPi));
    const auto curve = ExtractCurve(pose * LCorner(&random, 0.01));
    ASSERT_TRUE(curve.ok());
    const auto corners = OfType(curve->features, FeatureType::kCorner);
    ASSERT_EQ(corners.size(), 1u) << "trial " << trial;
    EXPECT_LT((corners[0].position - pose.translation()).norm(), 0.06) << "trial " << trial;
    EXPECT_NEAR(corners[0].arc_length_m, 1.0, 0.08);
    EXPECT_NEAR(corners[0].angle_rad, kPi / 2, 0.35);
    EXPECT_TRUE(OfType(curve->features, FeatureType::kInflection).empty()) << "trial " << trial;
  }
}

TEST(FindFeatures, PropertySCurveGivesItsInflectionPoint) {
  Random random(82);
  for (int trial = 0; trial < 100; ++trial) {
    std::vector<Eigen::Vector2d> pts;
    for (double x = 0; x <= 2.0; x += 0.015)
      pts.push_back(Eigen::Vector2d(x, 0.3 * std::sin(kPi * x)) + Noise(&random, 0.005));
    const auto curve = ExtractCurve(pts);
    ASSERT_TRUE(curve.ok());
    const auto inflections = OfType(curve->features, FeatureType::kInflection);
    ASSERT_EQ(inflections.size(), 1u) << "trial " << trial;
    EXPECT_NEAR(inflections[0].position.x(), 1.0, 0.06);
    EXPECT_NEAR(inflections[0].position.y(), 0.0, 0.03);
    EXPECT_TRUE(OfType(curve->features, FeatureType::kCorner).empty());
  }
}

TEST(FindFeatures, NoisyStraightWallsGiveAlmostNoFeatures) {
  // A wall seen by a URG-04LX (1 % range noise) from 0.5 to 3.5 m: the worst case of the
  // defaults. Measured: no corner and 2 inflections in 200 walls with this seed.
  Random random(1);
  int corners = 0, inflections = 0;
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<Eigen::Vector2d> pts;
    const double d = random.Uniform(0.5, 3.5);
    for (double a = -0.6; a < 0.6; a += 0.00628) {
      const double range = d / std::cos(a) * (1.0 + random.Gaussian(0.01));
      pts.push_back(range * Eigen::Vector2d(std::cos(a), std::sin(a)));
    }
    const auto curve = ExtractCurve(pts);
    ASSERT_TRUE(curve.ok());
    corners += static_cast<int>(OfType(curve->features, FeatureType::kCorner).size());
    inflections += static_cast<int>(OfType(curve->features, FeatureType::kInflection).size());
  }
  EXPECT_EQ(corners, 0);
  EXPECT_LE(inflections, 3);
  // With LMS-200 noise (1 cm) there are none at all.
  int lms = 0;
  for (int trial = 0; trial < 100; ++trial) {
    std::vector<Eigen::Vector2d> pts;
    const double d = random.Uniform(0.5, 6.0);
    for (double a = -0.8; a < 0.8; a += 0.0087) {
      const double range = d / std::cos(a) + random.Gaussian(0.01);
      pts.push_back(range * Eigen::Vector2d(std::cos(a), std::sin(a)));
    }
    lms += static_cast<int>(ExtractCurve(pts)->features.size());
  }
  EXPECT_EQ(lms, 0);
}

TEST(FindFeatures, PropertyFeaturesAreInvariantUnderRigidMotion) {
  Random random(83);
  for (int trial = 0; trial < 50; ++trial) {
    // An S-curve followed by a corner: both kinds of feature.
    std::vector<Eigen::Vector2d> pts;
    for (double x = 0; x <= 2.0; x += 0.015)
      pts.push_back(Eigen::Vector2d(x, 0.3 * std::sin(kPi * x)) + Noise(&random, 0.003));
    for (double y = 0; y <= 1.0; y += 0.015)
      pts.push_back(Eigen::Vector2d(2.0, -y) + Noise(&random, 0.003));
    const Pose2 motion(random.Uniform(-20, 20), random.Uniform(-20, 20), random.Uniform(-kPi, kPi));
    const auto a = ExtractCurve(pts);
    const auto b = ExtractCurve(motion * pts);
    ASSERT_TRUE(a && b);
    ASSERT_EQ(a->features.size(), b->features.size()) << "trial " << trial;
    ASSERT_GE(a->features.size(), 2u);
    for (std::size_t i = 0; i < a->features.size(); ++i) {
      EXPECT_EQ(a->features[i].type, b->features[i].type);
      EXPECT_EQ(a->features[i].index, b->features[i].index);
      EXPECT_NEAR(a->features[i].curvature, b->features[i].curvature,
                  1e-6 * (1 + std::abs(a->features[i].curvature)));
      EXPECT_LT((motion * a->features[i].position - b->features[i].position).norm(), 1e-7);
    }
  }
}

TEST(FindFeatures, RoundCornersAndGentleBendsAreNotCorners) {
  // A quarter circle of radius 0.5 m between straight arms: round, no corner.
  std::vector<Eigen::Vector2d> pts;
  for (double x = -1.0; x < 0; x += 0.015) pts.emplace_back(x, 0);
  for (double a = 0; a < kPi / 2; a += 0.03)
    pts.emplace_back(0.5 * std::sin(a), 0.5 - 0.5 * std::cos(a));
  for (double y = 0.5; y <= 1.5; y += 0.015) pts.emplace_back(0.5, y);
  const auto curve = ExtractCurve(pts);
  ASSERT_TRUE(curve.ok());
  EXPECT_TRUE(OfType(curve->features, FeatureType::kCorner).empty());
  // A 17 degree bend (163 deg between the arms): too flat to be a corner.
  std::vector<Eigen::Vector2d> bend;
  for (double x = -1.0; x < 0; x += 0.015) bend.emplace_back(x, 0);
  for (double s = 0; s <= 1.0; s += 0.015) bend.emplace_back(s * std::cos(0.3), s * std::sin(0.3));
  EXPECT_TRUE(OfType(ExtractCurve(bend)->features, FeatureType::kCorner).empty());
}

TEST(FindFeatures, InflectionBoundRuleIsASwitch) {
  Random random(84);
  const auto pts = LCorner(&random, 0.005);
  SplineExtractionOptions strict;
  strict.features.corners_need_inflection_bounds = true;
  EXPECT_EQ(OfType(ExtractCurve(pts)->features, FeatureType::kCorner).size(), 1u);
  EXPECT_TRUE(OfType(ExtractCurve(pts, strict)->features, FeatureType::kCorner).empty());
  // S, corner, S: the corner is bounded by inflections on both sides and survives.
  std::vector<Eigen::Vector2d> zig;
  for (double x = 0; x <= 2.0; x += 0.015) zig.emplace_back(x, 0.3 * std::sin(kPi * x));
  for (double s = 0.015; s <= 2.0; s += 0.015) zig.emplace_back(2.0 - 0.3 * std::sin(kPi * s), -s);
  const auto curve = ExtractCurve(zig, strict);
  ASSERT_TRUE(curve.ok());
  EXPECT_EQ(OfType(curve->features, FeatureType::kCorner).size(), 1u);
  EXPECT_GE(OfType(curve->features, FeatureType::kInflection).size(), 2u);
}

TEST(FindFeatures, DegenerateProfilesGiveNoFeatures) {
  EXPECT_TRUE(FindFeatures(CurvatureProfile()).empty());
  CurvatureProfile flat;
  flat.epsilon_m = 0.01;
  flat.curvature.assign(100, 0.0);
  flat.smoothed.assign(100, Eigen::Vector2d::Zero());
  EXPECT_TRUE(FindFeatures(flat).empty());
}

TEST(FeatureOptions, Validate) {
  EXPECT_TRUE(FeatureOptions().Validate().ok());
  FeatureOptions o;
  o.corner_ratio = 0.5;
  EXPECT_FALSE(o.Validate().ok());
}

}  // namespace
}  // namespace splam::kernel
