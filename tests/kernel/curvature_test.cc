#include "kernel/curvature.h"

#include <gtest/gtest.h>

#include <cmath>

#include "kernel/random.h"

namespace splam::kernel {
namespace {

std::vector<Eigen::Vector2d> Arc(double radius, double length, double epsilon) {
  std::vector<Eigen::Vector2d> points;
  for (double s = 0; s <= length; s += epsilon) {
    points.emplace_back(radius * std::cos(s / radius), radius * std::sin(s / radius));
  }
  return points;
}

TEST(ComputeCurvature, StraightLineHasZeroCurvatureEverywhere) {
  std::vector<Eigen::Vector2d> line;
  for (int i = 0; i < 200; ++i) line.emplace_back(0.3 + 0.01 * i * 0.6, -1 + 0.01 * i * 0.8);
  const CurvatureProfile p = ComputeCurvature(line, 0.01);
  for (double k : p.curvature) EXPECT_NEAR(k, 0.0, 1e-9);
  // The ends stay straight thanks to point-reflection padding.
  EXPECT_LT((p.smoothed.front() - line.front()).norm(), 1e-9);
  EXPECT_LT((p.smoothed.back() - line.back()).norm(), 1e-9);
}

TEST(ComputeCurvature, PropertyCircleOfRadiusRHasCurvatureOneOverR) {
  Random random(71);
  for (int trial = 0; trial < 50; ++trial) {
    const double r = random.Uniform(0.2, 5.0);
    const double epsilon = 0.01;
    const auto arc = Arc(r, std::min(3.0, 4.0 * r), epsilon);
    const CurvatureProfile p = ComputeCurvature(arc, epsilon);
    // Away from the ends (the kernel's reach), and counter-clockwise: positive.
    for (std::size_t i = 20; i + 20 < p.curvature.size(); ++i) {
      EXPECT_NEAR(p.curvature[i], 1.0 / r, 0.02 / r) << "r = " << r;
    }
    // Clockwise: negative.
    std::vector<Eigen::Vector2d> reversed(arc.rbegin(), arc.rend());
    const CurvatureProfile q = ComputeCurvature(reversed, epsilon);
    EXPECT_NEAR(q.curvature[q.curvature.size() / 2], -1.0 / r, 0.02 / r);
  }
}

TEST(ComputeCurvature, ParabolaCurvatureAtTheVertex) {
  // y = x^2 / 2: curvature 1 at the vertex.
  std::vector<Eigen::Vector2d> pts;
  const double h = 0.005;
  for (int i = -200; i <= 200; ++i) pts.emplace_back(i * h, 0.5 * (i * h) * (i * h));
  // Not equally spaced in arc length, but nearly so at the vertex.
  const CurvatureProfile p = ComputeCurvature(pts, h);
  EXPECT_NEAR(p.curvature[200], 1.0, 0.01);
}

TEST(ComputeCurvature, FewSamplesAndBadSpacingGiveZeros) {
  const CurvatureProfile p = ComputeCurvature({{0, 0}, {1, 1}}, 0.01);
  EXPECT_EQ(p.curvature, (std::vector<double>{0.0, 0.0}));
  EXPECT_EQ(p.smoothed.size(), 2u);
  EXPECT_TRUE(ComputeCurvature({}, 0.01).curvature.empty());
  const CurvatureProfile zero = ComputeCurvature(Arc(1, 1, 0.01), 0.0);
  for (double k : zero.curvature) EXPECT_EQ(k, 0.0);
}

TEST(CurvatureOptions, Validate) {
  EXPECT_TRUE(CurvatureOptions().Validate().ok());
  CurvatureOptions o;
  o.sigma_m = 0;
  EXPECT_FALSE(o.Validate().ok());
}

}  // namespace
}  // namespace splam::kernel
