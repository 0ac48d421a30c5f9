#include "sim/ray_caster.h"

#include <gtest/gtest.h>

#include <cmath>

#include "kernel/angle.h"
#include "kernel/random.h"
#include "sim/builtin_worlds.h"

namespace splam::sim {
namespace {

using kernel::kPi;
using kernel::Random;

kernel::Ray2 RayAt(double x, double y, double angle) {
  return {{x, y}, {std::cos(angle), std::sin(angle)}};
}

World RandomWorld(Random* random) {
  World w;
  auto point = [&] { return Eigen::Vector2d(random->Uniform(0, 12), random->Uniform(0, 10)); };
  const int n = 5 + static_cast<int>(random->Index(15));
  for (int i = 0; i < n; ++i) {
    switch (random->Index(5)) {
      case 0: {
        const Eigen::Vector2d a = point();
        w.obstacles.push_back(Polyline{
            {a, a + Eigen::Vector2d(random->Uniform(-3, 3), random->Uniform(-3, 3)), point()},
            random->Uniform() < 0.5});
        break;
      }
      case 1:
        w.obstacles.push_back(kernel::Circle2{point(), random->Uniform(0.1, 1.5)});
        break;
      case 2:
        w.obstacles.push_back(kernel::Ellipse2{
            point(), random->Uniform(0.1, 2), random->Uniform(0.1, 2), random->Uniform(-kPi, kPi)});
        break;
      case 3: {
        Spline s;
        const Eigen::Vector2d start = point();
        for (int k = 0; k < 4 + static_cast<int>(random->Index(5)); ++k) {
          s.control_points.push_back(
              start + Eigen::Vector2d(random->Uniform(-3, 3), random->Uniform(-3, 3)));
        }
        w.obstacles.push_back(s);
        break;
      }
      default: {
        Spline s{{}, true};
        const Eigen::Vector2d c = point();
        for (int k = 0; k < 6; ++k) {
          const double a = 2 * kPi * k / 6;
          const double r = random->Uniform(0.3, 1.5);
          s.control_points.push_back(c + r * Eigen::Vector2d(std::cos(a), std::sin(a)));
        }
        w.obstacles.push_back(s);
      }
    }
  }
  return w;
}

TEST(RayCaster, PropertyIndexedEqualsBruteForceOverRandomWorlds) {
  Random random(21);
  int hits = 0, rays = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const World world = RandomWorld(&random);
    ASSERT_TRUE(world.Validate().ok());
    RayCasterOptions options;
    options.cell_size_m = random.Uniform(0.2, 1.5);
    const RayCaster caster(world, options);
    for (int i = 0; i < 300; ++i) {
      // Origins also outside the world's box.
      const kernel::Ray2 ray =
          RayAt(random.Uniform(-3, 15), random.Uniform(-3, 13), random.Uniform(-kPi, kPi));
      const double max_range = random.Uniform(0.5, 20);
      const RayHit fast = caster.Cast(ray, max_range);
      const RayHit slow = caster.CastBruteForce(ray, max_range);
      ++rays;
      ASSERT_EQ(fast.range_m == kernel::kNoHit, slow.range_m == kernel::kNoHit)
          << "trial " << trial << " ray " << i;
      if (slow.range_m == kernel::kNoHit) continue;
      ++hits;
      EXPECT_NEAR(fast.range_m, slow.range_m, 1e-12) << "trial " << trial << " ray " << i;
      EXPECT_EQ(fast.obstacle, slow.obstacle);
      EXPECT_LT(fast.range_m, max_range);
    }
  }
  EXPECT_GT(hits, rays / 4);
}

TEST(RayCaster, CircleRangesAreExact) {
  World w;
  w.obstacles.push_back(kernel::Circle2{{0, 0}, 5.0});
  const RayCaster caster(w);
  Random random(22);
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector2d o(random.Uniform(-3, 3), random.Uniform(-3, 3));
    const double a = random.Uniform(-kPi, kPi);
    const RayHit hit = caster.Cast(RayAt(o.x(), o.y(), a), 20.0);
    ASSERT_EQ(hit.obstacle, 0);
    EXPECT_NEAR((o + hit.range_m * Eigen::Vector2d(std::cos(a), std::sin(a))).norm(), 5.0, 1e-9);
  }
}

TEST(RayCaster, CurvedWallsAreExactToAMillimetre) {
  // Dense polyline (0.1 mm chords) of the complex world's curved walls as the reference.
  const World complex = *BuiltinWorld("complex");
  World curves, dense;
  for (const Shape& shape : complex.obstacles) {
    if (!std::holds_alternative<Spline>(shape)) continue;
    curves.obstacles.push_back(shape);
    Primitives p;
    curves.AppendPrimitives(curves.obstacles.size() - 1, &p);
    for (const kernel::CubicBezier& b : p.beziers) {
      Polyline line;
      for (int k = 0; k <= 20000; ++k) line.vertices.push_back(b.Point(k / 20000.0));
      dense.obstacles.push_back(line);
    }
  }
  ASSERT_GE(curves.obstacles.size(), 4u);
  const RayCaster exact(curves), reference(dense);
  Random random(23);
  int hits = 0;
  for (int i = 0; i < 2000; ++i) {
    const kernel::Ray2 ray =
        RayAt(random.Uniform(1, 19), random.Uniform(1, 14), random.Uniform(-kPi, kPi));
    const RayHit a = exact.Cast(ray, 8.0), b = reference.CastBruteForce(ray, 8.0);
    ASSERT_EQ(a.range_m == kernel::kNoHit, b.range_m == kernel::kNoHit);
    if (a.range_m == kernel::kNoHit) continue;
    ++hits;
    EXPECT_NEAR(a.range_m, b.range_m, 1e-3);
  }
  EXPECT_GT(hits, 500);
}

// Found by fuzz_world: a wall 428 km long made the grid 43 million cells (over 10 s and a GB).
// The grid stays under 2^20 cells and the casts stay exact.
TEST(RayCaster, AWorldHundredsOfKilometresWideGetsCoarserCells) {
  World w;
  w.obstacles.push_back(Polyline{{{0, -1.2}, {10, -1.2}, {18, 428255}}, false});
  w.obstacles.push_back(kernel::Circle2{{5, 5}, 1.0});
  const RayCaster caster(w);
  const RayHit hit = caster.Cast({{5, 2}, {0, 1}}, 100.0);
  EXPECT_EQ(hit.obstacle, 1);
  EXPECT_NEAR(hit.range_m, 2.0, 1e-9);
  EXPECT_NEAR(caster.Cast({{5, 0}, {0, -1}}, 100.0).range_m, 1.2, 1e-9);
}

TEST(RayCaster, NothingWithinRangeIsNoHit) {
  World w;
  w.obstacles.push_back(Polyline{{{10, -1}, {10, 1}}, false});
  const RayCaster caster(w);
  EXPECT_EQ(caster.Cast(RayAt(0, 0, 0), 5.0).obstacle, -1);
  EXPECT_EQ(caster.Cast(RayAt(0, 0, 0), 5.0).range_m, kernel::kNoHit);
  EXPECT_NEAR(caster.Cast(RayAt(0, 0, 0), 50.0).range_m, 10.0, 1e-12);
  EXPECT_EQ(caster.Cast(RayAt(0, 0, kPi), 50.0).obstacle, -1);
}

TEST(RayCaster, CollisionsWithBoundariesAndInsides) {
  World w;
  w.obstacles.push_back(Polyline{{{0, 0}, {10, 0}}, false});
  w.obstacles.push_back(kernel::Circle2{{5, 5}, 1.0});
  w.obstacles.push_back(Spline{{{8, 8}, {9, 8}, {9, 9}, {8, 9}}, true});
  const RayCaster caster(w);
  EXPECT_TRUE(caster.Collides({2, 0.2}, 0.3));
  EXPECT_FALSE(caster.Collides({2, 0.4}, 0.3));
  EXPECT_TRUE(caster.Collides({5, 6.2}, 0.3));
  EXPECT_FALSE(caster.Collides({5, 6.4}, 0.3));
  EXPECT_TRUE(caster.Collides({5, 5}, 0.3));  // inside the pillar
  EXPECT_TRUE(caster.IsInsideObstacle({5, 5.5}));
  EXPECT_TRUE(caster.IsInsideObstacle({8.5, 8.5}));
  EXPECT_FALSE(caster.IsInsideObstacle({2, 2}));
  EXPECT_TRUE(caster.Collides({8.5, 8.5}, 0.01));
}

TEST(RayCasterOptions, Validate) {
  EXPECT_TRUE(RayCasterOptions().Validate().ok());
  RayCasterOptions o;
  o.cell_size_m = 0;
  EXPECT_FALSE(o.Validate().ok());
}

}  // namespace
}  // namespace splam::sim
