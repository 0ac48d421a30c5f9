// Arc length, resampling, closest points, ray intersection and transformation of B-splines.
#include <gtest/gtest.h>

#include <cmath>

#include "kernel/angle.h"
#include "kernel/bspline.h"
#include "kernel/random.h"

namespace splam::kernel {
namespace {

CubicBSpline RandomSpline(Random* random, int n) {
  std::vector<Eigen::Vector2d> control;
  Eigen::Vector2d p(random->Uniform(-2, 2), random->Uniform(-2, 2));
  for (int i = 0; i < n; ++i) {
    control.push_back(p);
    p += Eigen::Vector2d(random->Uniform(0.2, 1.0), random->Uniform(-0.8, 0.8));
  }
  return *CubicBSpline::ClampedUniform(control);
}

// Dense polyline of the curve: the reference for lengths, distances and intersections.
std::vector<Eigen::Vector2d> Dense(const CubicBSpline& s, int n = 100000) {
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i <= n; ++i) {
    points.push_back(s.Point(s.DomainStart() + (s.DomainEnd() - s.DomainStart()) * i / n));
  }
  return points;
}

TEST(CubicBSplineGeometry, DerivativesMatchFiniteDifferences) {
  Random random(51);
  for (int trial = 0; trial < 50; ++trial) {
    const CubicBSpline s = RandomSpline(&random, 4 + static_cast<int>(random.Index(8)));
    for (int k = 1; k < 10; ++k) {
      const double t = 0.1 * k + 0.013;
      const double h = 1e-6;
      EXPECT_LT((((s.Point(t + h) - s.Point(t - h)) / (2 * h)) - s.Derivative(t)).norm(),
                1e-5 * (1 + s.Derivative(t).norm()));
      EXPECT_LT(
          (((s.Derivative(t + h) - s.Derivative(t - h)) / (2 * h)) - s.SecondDerivative(t)).norm(),
          1e-4 * (1 + s.SecondDerivative(t).norm()));
    }
  }
}

TEST(CubicBSplineGeometry, PropertyArcLengthAgreesWithDensePolylineAndInverts) {
  Random random(52);
  for (int trial = 0; trial < 30; ++trial) {
    const CubicBSpline s = RandomSpline(&random, 4 + static_cast<int>(random.Index(10)));
    const auto dense = Dense(s);
    double length = 0.0;
    for (std::size_t i = 1; i < dense.size(); ++i) length += (dense[i] - dense[i - 1]).norm();
    EXPECT_NEAR(s.Length(), length, 1e-6 * length);
    for (int k = 0; k <= 20; ++k) {
      const double arc = s.Length() * k / 20.0;
      const double t = s.ParameterAtArcLength(arc);
      EXPECT_NEAR(s.ArcLengthAt(t), arc, 1e-9 * (1 + arc));
    }
    EXPECT_EQ(s.ParameterAtArcLength(-1.0), s.DomainStart());
    EXPECT_EQ(s.ParameterAtArcLength(1e9), s.DomainEnd());
  }
}

TEST(CubicBSplineGeometry, PropertyResampledSpacingEqualsEpsilon) {
  Random random(53);
  for (int trial = 0; trial < 30; ++trial) {
    const CubicBSpline s = RandomSpline(&random, 4 + static_cast<int>(random.Index(10)));
    const double epsilon = random.Uniform(0.005, 0.05);
    const auto samples = s.ResampleByArcLength(epsilon);
    ASSERT_EQ(samples.size(),
              static_cast<std::size_t>(std::floor(s.Length() / epsilon + 1e-9)) + 1);
    EXPECT_LT((samples.front() - s.Point(s.DomainStart())).norm(), 1e-12);
    double previous = 0.0;
    for (std::size_t i = 1; i < samples.size(); ++i) {
      // Consecutive samples are epsilon apart along the curve; their chord is at most that.
      const double arc = s.ArcLengthAt(s.Closest(samples[i]).t);
      EXPECT_NEAR(arc - previous, epsilon, 1e-6) << "trial " << trial << " sample " << i;
      EXPECT_LE((samples[i] - samples[i - 1]).norm(), epsilon * (1 + 1e-9));
      previous = arc;
    }
  }
}

TEST(CubicBSplineGeometry, PropertyClosestPointAgreesWithDenseSampling) {
  Random random(54);
  for (int trial = 0; trial < 30; ++trial) {
    const CubicBSpline s = RandomSpline(&random, 4 + static_cast<int>(random.Index(8)));
    const auto dense = Dense(s, 20000);
    for (int k = 0; k < 10; ++k) {
      const Eigen::Vector2d q(random.Uniform(-3, 8), random.Uniform(-4, 4));
      double best = kNoHit;
      for (const auto& p : dense) best = std::min(best, (p - q).norm());
      const CubicBSpline::ClosestPoint c = s.Closest(q);
      EXPECT_NEAR(c.distance, best, 1e-4);
      EXPECT_LE(c.distance, best + 1e-12);
      EXPECT_LT((s.Point(c.t) - c.point).norm(), 1e-12);
    }
  }
}

// Closest skips the pieces whose control-point box is farther than the best point so far: on long,
// winding curves (where it skips most) it must find what a test of every piece finds.
TEST(CubicBSplineGeometry, PropertyClosestPointEqualsTheBestOfEveryPiece) {
  Random random(57);
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<Eigen::Vector2d> control;
    double heading = random.Uniform(-kPi, kPi);
    Eigen::Vector2d p = Eigen::Vector2d::Zero();
    for (int i = 0; i < 200; ++i) {  // a random walk that crosses itself
      control.push_back(p);
      heading += random.Uniform(-1.0, 1.0);
      p += random.Uniform(0.1, 2.0) * Eigen::Vector2d(std::cos(heading), std::sin(heading));
    }
    const CubicBSpline s = *CubicBSpline::ClampedUniform(control);
    for (int k = 0; k < 50; ++k) {
      const Eigen::Vector2d q = control[random.Index(control.size())] +
                                Eigen::Vector2d(random.Uniform(-3, 3), random.Uniform(-3, 3));
      double best = kNoHit;
      for (const CubicBezier& piece : s.pieces())
        best = std::min(best, (piece.Point(piece.ClosestParameter(q)) - q).norm());
      EXPECT_EQ(s.Closest(q).distance, best) << "trial " << trial << " query " << k;
    }
  }
}

TEST(CubicBSplineGeometry, PropertyRayIntersectionAgreesWithDenseSampling) {
  Random random(55);
  int hits = 0;
  for (int trial = 0; trial < 150; ++trial) {
    const CubicBSpline s = RandomSpline(&random, 4 + static_cast<int>(random.Index(8)));
    const auto dense = Dense(s, 50000);
    const double a = random.Uniform(-kPi, kPi);
    const Ray2 ray{{random.Uniform(-3, 8), random.Uniform(-4, 4)}, {std::cos(a), std::sin(a)}};
    double reference = kNoHit;
    for (std::size_t i = 1; i < dense.size(); ++i) {
      reference = std::min(reference, Intersect(ray, Segment2{dense[i - 1], dense[i]}, 0.0, 30.0));
    }
    const double exact = Intersect(ray, s, 0.0, 30.0);
    if (reference == kNoHit) {
      if (exact != kNoHit) {
        EXPECT_LT(s.Closest(ray.At(exact)).distance, 1e-6);  // a graze the polyline missed
      }
      continue;
    }
    ++hits;
    ASSERT_NE(exact, kNoHit) << "trial " << trial;
    EXPECT_NEAR(exact, reference, 1e-5) << "trial " << trial;
  }
  EXPECT_GT(hits, 15);  // about 13 % of these random rays hit
}

TEST(CubicBSplineGeometry, RaysAtCurveEndsAndJointsAndTangents) {
  // A straight spline along x = 1, y in [0, 3], made of 3 pieces (joints at y = 1, 2).
  const CubicBSpline s =
      *CubicBSpline::ClampedUniform({{1, 0}, {1, 0.5}, {1, 1.2}, {1, 1.8}, {1, 2.5}, {1, 3}});
  ASSERT_EQ(s.pieces().size(), 3u);
  for (double y : {0.0, 3.0, s.Point(s.span_starts()[1]).y(), s.Point(s.span_starts()[2]).y()}) {
    EXPECT_NEAR(Intersect({{0, y}, {1, 0}}, s, 0.0, 10.0), 1.0, 1e-12) << "y = " << y;
  }
  EXPECT_EQ(Intersect({{0, 3.001}, {1, 0}}, s, 0.0, 10.0), kNoHit);
  // A ray at the height of the arc's sampled top (at or just under the true top) touches or
  // crosses it near x = 0; just above the true top it misses.
  const CubicBSpline arc = *CubicBSpline::ClampedUniform({{-1, 0}, {-1, 1.1}, {1, 1.1}, {1, 0}});
  double top = -1;
  for (int i = 0; i <= 1000; ++i) top = std::max(top, arc.Point(i / 1000.0).y());
  const double t = Intersect({{-3, top}, {1, 0}}, arc, 0.0, 10.0);
  ASSERT_NE(t, kNoHit);
  EXPECT_NEAR(t, 3.0, 0.05);
  EXPECT_EQ(Intersect({{-3, top + 1e-6}, {1, 0}}, arc, 0.0, 10.0), kNoHit);
}

TEST(CubicBSplineGeometry, TransformedMovesTheCurveRigidly) {
  Random random(56);
  const CubicBSpline s = RandomSpline(&random, 7);
  const Pose2 a_T_b(1.5, -2.0, 0.7);
  const CubicBSpline moved = s.Transformed(a_T_b);
  for (int k = 0; k <= 10; ++k) {
    const double t = k / 10.0;
    EXPECT_LT((moved.Point(t) - a_T_b * s.Point(t)).norm(), 1e-12);
  }
  EXPECT_NEAR(moved.Length(), s.Length(), 1e-9);
}

}  // namespace
}  // namespace splam::kernel
