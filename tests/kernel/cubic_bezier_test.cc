#include "kernel/cubic_bezier.h"

#include <gtest/gtest.h>

#include <cmath>

#include "kernel/angle.h"
#include "kernel/random.h"

namespace splam::kernel {
namespace {

CubicBezier RandomCurve(Random* random) {
  CubicBezier b;
  for (auto& p : b.p) p = {random->Uniform(-3, 3), random->Uniform(-3, 3)};
  return b;
}

// Reference: the first crossing of the ray with a polyline of 200000 samples of the curve.
double DenseIntersect(const Ray2& ray, const CubicBezier& b, double t_max) {
  constexpr int kN = 200000;
  double best = kNoHit;
  Eigen::Vector2d prev = b.Point(0);
  for (int k = 1; k <= kN; ++k) {
    const Eigen::Vector2d next = b.Point(static_cast<double>(k) / kN);
    best = std::min(best, Intersect(ray, Segment2{prev, next}, 0.0, t_max));
    prev = next;
  }
  return best;
}

TEST(CubicBezier, EndPointsAndDerivatives) {
  const CubicBezier b{{Eigen::Vector2d(0, 0), {1, 2}, {3, 2}, {4, 0}}};
  EXPECT_EQ(b.Point(0), Eigen::Vector2d(0, 0));
  EXPECT_EQ(b.Point(1), Eigen::Vector2d(4, 0));
  EXPECT_TRUE(b.Derivative(0).isApprox(Eigen::Vector2d(3, 6)));
  EXPECT_TRUE(b.Derivative(1).isApprox(Eigen::Vector2d(3, -6)));
  // Numeric derivatives.
  const double h = 1e-6;
  for (double t : {0.2, 0.5, 0.8}) {
    EXPECT_TRUE(((b.Point(t + h) - b.Point(t - h)) / (2 * h)).isApprox(b.Derivative(t), 1e-7));
    EXPECT_TRUE(((b.Derivative(t + h) - b.Derivative(t - h)) / (2 * h))
                    .isApprox(b.SecondDerivative(t), 1e-7));
  }
}

TEST(CubicBezier, SplitReproducesTheCurve) {
  Random random(6);
  for (int i = 0; i < 100; ++i) {
    const CubicBezier b = RandomCurve(&random);
    const double s = random.Uniform(0.1, 0.9);
    const auto [first, second] = b.Split(s);
    for (double u : {0.0, 0.3, 0.7, 1.0}) {
      EXPECT_LT((first.Point(u) - b.Point(u * s)).norm(), 1e-12);
      EXPECT_LT((second.Point(u) - b.Point(s + u * (1 - s))).norm(), 1e-12);
    }
  }
}

TEST(CubicBezier, PropertyRayIntersectionAgreesWithDenseSampling) {
  Random random(8);
  int hits = 0;
  for (int i = 0; i < 300; ++i) {
    const CubicBezier b = RandomCurve(&random);
    const Ray2 ray{{random.Uniform(-4, 4), random.Uniform(-4, 4)}, {0, 0}};
    const double a = random.Uniform(-kPi, kPi);
    const Ray2 r{ray.origin, {std::cos(a), std::sin(a)}};
    const double exact = Intersect(r, b, 0.0, 20.0);
    const double dense = DenseIntersect(r, b, 20.0);
    if (dense == kNoHit) {
      // A miss by the polyline can only be a grazing hit of the true curve.
      if (exact != kNoHit) {
        EXPECT_LT(b.Distance(r.At(exact)), 1e-6);
      }
      continue;
    }
    ++hits;
    ASSERT_NE(exact, kNoHit) << "trial " << i;
    EXPECT_NEAR(exact, dense, 1e-5) << "trial " << i;
    EXPECT_LT(b.Distance(r.At(exact)), 1e-9);
  }
  EXPECT_GT(hits, 40);  // about 17 % of random rays hit
}

TEST(CubicBezier, RayThroughAnSCurveFindsTheNearestOfThreeCrossings) {
  // y = 0 crossed three times by an S-shaped curve.
  const CubicBezier s{{Eigen::Vector2d(0, -1), {1, 3}, {2, -3}, {3, 1}}};
  const double t = Intersect({{-1, 0}, {1, 0}}, s, 0.0, 10.0);
  EXPECT_NEAR(std::abs(s.Point(0).y()), 1.0, 0);
  ASSERT_NE(t, kNoHit);
  EXPECT_NEAR(Eigen::Vector2d(-1 + t, 0).x(), DenseIntersect({{-1, 0}, {1, 0}}, s, 10.0) - 1, 1e-6);
  // From beyond the last crossing, looking back, the last crossing is the nearest.
  const double back = Intersect({{4, 0}, {-1, 0}}, s, 0.0, 10.0);
  EXPECT_NEAR(back, DenseIntersect({{4, 0}, {-1, 0}}, s, 10.0), 1e-6);
}

TEST(CubicBezier, RayThroughJointOfTwoPiecesIsHitOnce) {
  // A straight line split in two: a ray through the joint must still hit at the joint.
  const CubicBezier line{{Eigen::Vector2d(0, -1), {0, -1.0 / 3}, {0, 1.0 / 3}, {0, 1}}};
  const auto [lower, upper] = line.Split(0.5);
  const Ray2 ray{{-2, 0}, {1, 0}};
  EXPECT_NEAR(std::min(Intersect(ray, lower, 0, 10), Intersect(ray, upper, 0, 10)), 2.0, 1e-12);
}

TEST(CubicBezier, DistanceAgreesWithDenseSampling) {
  Random random(10);
  for (int i = 0; i < 200; ++i) {
    const CubicBezier b = RandomCurve(&random);
    const Eigen::Vector2d q(random.Uniform(-4, 4), random.Uniform(-4, 4));
    double dense = kNoHit;
    for (int k = 0; k <= 20000; ++k) dense = std::min(dense, (b.Point(k / 20000.0) - q).norm());
    EXPECT_NEAR(b.Distance(q), dense, 1e-4);
  }
}

TEST(CubicBezier, DegenerateCurvesGiveDefinedResults) {
  const CubicBezier point{{Eigen::Vector2d(1, 1), {1, 1}, {1, 1}, {1, 1}}};
  EXPECT_NEAR(point.Distance({1, 2}), 1.0, 1e-12);
  const double t = Intersect({{0, 1}, {1, 0}}, point, 0, 10);
  EXPECT_TRUE(t == kNoHit || std::abs(t - 1.0) < 1e-9);
}

}  // namespace
}  // namespace splam::kernel
