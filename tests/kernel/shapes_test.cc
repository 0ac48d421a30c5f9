#include "kernel/shapes.h"

#include <gtest/gtest.h>

#include <cmath>

#include "kernel/angle.h"
#include "kernel/random.h"

namespace splam::kernel {
namespace {

Ray2 RayAt(double x, double y, double angle) {
  return {{x, y}, {std::cos(angle), std::sin(angle)}};
}

TEST(Segment2, RayHitsAtTheRightDistance) {
  const Segment2 wall{{2, -3}, {2, 3}};
  EXPECT_NEAR(Intersect(RayAt(0, 0, 0), wall, 0, 10), 2.0, 1e-15);
  EXPECT_NEAR(Intersect(RayAt(0, 0, kPi / 4), wall, 0, 10), 2.0 * std::sqrt(2.0), 1e-14);
  EXPECT_EQ(Intersect(RayAt(0, 0, kPi), wall, 0, 10), kNoHit);      // behind
  EXPECT_EQ(Intersect(RayAt(0, 0, 0), wall, 0, 1.5), kNoHit);       // beyond range
  EXPECT_EQ(Intersect(RayAt(0, 0, kPi / 2), wall, 0, 10), kNoHit);  // parallel
  EXPECT_EQ(Intersect(RayAt(0, 0, 1.2), wall, 0, 10), kNoHit);      // passes above the end
}

TEST(Segment2, DistanceAndBounds) {
  const Segment2 s{{0, 0}, {2, 0}};
  EXPECT_DOUBLE_EQ(s.Distance({1, 1}), 1.0);
  EXPECT_DOUBLE_EQ(s.Distance({3, 0}), 1.0);
  EXPECT_DOUBLE_EQ(s.Distance({-3, 4}), 5.0);
  EXPECT_DOUBLE_EQ(Segment2({{1, 1}, {1, 1}}).Distance({1, 2}), 1.0);
  EXPECT_EQ(s.Bounds().max, Eigen::Vector2d(2, 0));
  EXPECT_DOUBLE_EQ(s.Length(), 2.0);
}

TEST(Circle2, RayHitsFromOutsideAndInside) {
  const Circle2 c{{5, 0}, 1.0};
  EXPECT_NEAR(Intersect(RayAt(0, 0, 0), c, 0, 10), 4.0, 1e-14);
  EXPECT_NEAR(Intersect(RayAt(5, 0, 0), c, 0, 10), 1.0, 1e-14);  // from the centre
  EXPECT_EQ(Intersect(RayAt(0, 0, 0.3), c, 0, 10), kNoHit);
  // Grazing: tangent at y = 1.
  EXPECT_NEAR(Intersect(RayAt(0, 1 - 1e-9, 0), c, 0, 10), 5.0, 1e-3);
}

TEST(Circle2, PropertyHitPointLiesOnTheCircle) {
  Random random(4);
  int hits = 0;
  for (int i = 0; i < 2000; ++i) {
    const Circle2 c{{random.Uniform(-5, 5), random.Uniform(-5, 5)}, random.Uniform(0.1, 3)};
    const Ray2 ray = RayAt(random.Uniform(-5, 5), random.Uniform(-5, 5), random.Uniform(-kPi, kPi));
    const double t = Intersect(ray, c, 0, 100);
    if (t == kNoHit) continue;
    ++hits;
    EXPECT_NEAR((ray.At(t) - c.center).norm(), c.radius, 1e-9);
    EXPECT_GT(t, 0.0);
  }
  EXPECT_GT(hits, 250);  // about 18 % of random rays hit
}

TEST(Ellipse2, RayHitsAxisAlignedAndRotated) {
  const Ellipse2 e{{0, 0}, 2.0, 1.0, 0.0};
  EXPECT_NEAR(Intersect(RayAt(-5, 0, 0), e, 0, 10), 3.0, 1e-14);
  EXPECT_NEAR(Intersect(RayAt(0, -5, kPi / 2), e, 0, 10), 4.0, 1e-14);
  const Ellipse2 r{{0, 0}, 2.0, 1.0, kPi / 2};  // long axis along y
  EXPECT_NEAR(Intersect(RayAt(0, -5, kPi / 2), r, 0, 10), 3.0, 1e-14);
  EXPECT_TRUE(r.Contains({0, 1.9}));
  EXPECT_FALSE(r.Contains({1.5, 0}));
}

TEST(Ellipse2, PropertyHitsAndDistancesAgreeWithTheParametricCurve) {
  Random random(5);
  for (int i = 0; i < 500; ++i) {
    const Ellipse2 e{{random.Uniform(-3, 3), random.Uniform(-3, 3)},
                     random.Uniform(0.2, 3),
                     random.Uniform(0.2, 3),
                     random.Uniform(-kPi, kPi)};
    const Ray2 ray = RayAt(random.Uniform(-6, 6), random.Uniform(-6, 6), random.Uniform(-kPi, kPi));
    const double t = Intersect(ray, e, 0, 100);
    // Dense reference for the distance from a point to the curve.
    auto reference_distance = [&](const Eigen::Vector2d& p) {
      double best = kNoHit;
      for (int k = 0; k < 20000; ++k)
        best = std::min(best, (e.PointAt(2 * kPi * k / 20000) - p).norm());
      return best;
    };
    if (t != kNoHit) {
      EXPECT_LT(reference_distance(ray.At(t)), 2e-3);
    }
    const Eigen::Vector2d q(random.Uniform(-6, 6), random.Uniform(-6, 6));
    EXPECT_NEAR(e.Distance(q), reference_distance(q), 2e-3);
    EXPECT_LE(e.Distance(q), reference_distance(q) + 1e-12);
    const Box2 b = e.Bounds();
    for (int k = 0; k < 64; ++k) {
      const Eigen::Vector2d p = e.PointAt(2 * kPi * k / 64);
      EXPECT_TRUE((p.array() >= b.min.array() - 1e-12).all() &&
                  (p.array() <= b.max.array() + 1e-12).all());
    }
  }
}

TEST(Overlaps, SegmentAndBox) {
  const Box2 box{{0, 0}, {1, 1}};
  EXPECT_TRUE(Overlaps(box, {{-1, 0.5}, {2, 0.5}}));       // crosses
  EXPECT_TRUE(Overlaps(box, {{0.2, 0.2}, {0.3, 0.3}}));    // inside
  EXPECT_FALSE(Overlaps(box, {{-1, 1.5}, {2, 1.5}}));      // above
  EXPECT_FALSE(Overlaps(box, {{1.2, -0.5}, {2.5, 0.9}}));  // beside the corner, bounds overlap
  EXPECT_TRUE(Overlaps(box, {{1, 1}, {2, 2}}));            // touches a corner
}

TEST(Box2, ExtendAndEmpty) {
  Box2 b;
  EXPECT_TRUE(b.IsEmpty());
  b.Extend(Eigen::Vector2d(1, 2));
  EXPECT_FALSE(b.IsEmpty());
  b.Extend(Box2{{-1, 0}, {0, 5}});
  EXPECT_EQ(b.Size(), Eigen::Vector2d(2, 5));
}

}  // namespace
}  // namespace splam::kernel
