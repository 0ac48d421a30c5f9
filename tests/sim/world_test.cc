#include "sim/world.h"

#include <gtest/gtest.h>

#include <cmath>

#include "kernel/random.h"

namespace splam::sim {
namespace {

World One(Shape shape) {
  World w;
  w.obstacles.push_back(std::move(shape));
  return w;
}

TEST(World, ValidWorldHasNoProblems) {
  World w;
  w.obstacles = {Polyline{{{0, 0}, {1, 0}}, false}, kernel::Circle2{{2, 2}, 0.5},
                 kernel::Ellipse2{{4, 4}, 1, 0.5, 0.3},
                 Spline{{{0, 5}, {1, 6}, {2, 5}, {3, 6}}, false},
                 Spline{{{5, 5}, {6, 5}, {6, 6}}, true}};
  EXPECT_TRUE(w.Validate().ok());
}

TEST(World, ValidateNamesTheObstacleAndTheProblem) {
  EXPECT_EQ(One(Polyline{{{0, 0}}, false}).Validate().message(),
            "obstacle 0 (polyline): needs at least 2 vertices, has 1");
  EXPECT_EQ(One(Polyline{{{0, 0}, {1, 0}}, true}).Validate().message(),
            "obstacle 0 (polygon): needs at least 3 vertices, has 2");
  EXPECT_EQ(One(Polyline{{{0, 0}, {0, 0}, {1, 0}}, false}).Validate().message(),
            "obstacle 0 (polyline): edge 0 has zero length");
  EXPECT_EQ(One(kernel::Circle2{{0, 0}, 0.0}).Validate().message(),
            "obstacle 0 (circle): radius must be positive");
  EXPECT_EQ(One(kernel::Circle2{{NAN, 0}, 1.0}).Validate().message(),
            "obstacle 0 (circle): not finite or beyond +-1e6 m");
  EXPECT_EQ(One(kernel::Ellipse2{{0, 0}, 1.0, -1.0, 0.0}).Validate().message(),
            "obstacle 0 (ellipse): radii must be positive");
  EXPECT_EQ(One(Spline{{{0, 0}, {1, 1}, {2, 0}}, false}).Validate().message(),
            "obstacle 0 (spline): needs at least 4 control points, has 3");
  EXPECT_EQ(One(Spline{{{0, 0}, {1, 1}}, true}).Validate().message(),
            "obstacle 0 (closed_spline): needs at least 3 control points, has 2");
  World w = One(kernel::Circle2{{0, 0}, 1.0});
  w.route = {{INFINITY, 0}};
  EXPECT_EQ(w.Validate().message(), "route waypoint is not finite or beyond +-1e6 m");
  // Worlds that were accepted and then broke the run.
  EXPECT_EQ(One(Polyline{{{0, 0}, {1e300, 0}, {0, 1}}, true}).Validate().message(),
            "obstacle 0 (polygon): not finite or beyond +-1e6 m");
  EXPECT_EQ(One(kernel::Circle2{{0, 0}, 1e300}).Validate().message(),
            "obstacle 0 (circle): not finite or beyond +-1e6 m");
  EXPECT_EQ(One(Polyline{{{0, 0}, {2, 2}, {2, 0}, {0, 2}}, true}).Validate().message(),
            "obstacle 0 (polygon): edges 0 and 2 cross: a polygon must not intersect itself");
  EXPECT_EQ(One(Spline{{{1, 1}, {1, 1}, {1, 1}, {1, 1}}, false}).Validate().message(),
            "obstacle 0 (spline): all control points are the same point: the curve has no length");
  // A simple polygon, convex or not, and an open polyline that crosses itself (two walls) pass.
  EXPECT_TRUE(One(Polyline{{{0, 0}, {4, 0}, {4, 4}, {2, 1}, {0, 4}}, true}).Validate().ok());
  EXPECT_TRUE(One(Polyline{{{0, 0}, {2, 2}, {2, 0}, {0, 2}}, false}).Validate().ok());
}

TEST(World, PropertyStarShapedPolygonsAreSimpleAndFoldedOnesAreNot) {
  kernel::Random random(11);
  for (int trial = 0; trial < 200; ++trial) {
    // Vertices at increasing angles around a centre: a star-shaped, simple polygon.
    std::vector<Eigen::Vector2d> v;
    const int n = 3 + trial % 20;
    for (int k = 0; k < n; ++k) {
      const double a = 2.0 * M_PI * (k + 0.8 * random.Uniform()) / n;
      const double r = 0.5 + 2.0 * random.Uniform();
      v.emplace_back(5.0 + r * std::cos(a), 5.0 + r * std::sin(a));
    }
    EXPECT_TRUE(One(Polyline{v, true}).Validate().ok()) << trial;
    // The same angles on a circle (convex position): swapping vertices 1 and 3 makes the edges
    // 0-3 and 1-4 chords whose ends interleave, so they cross.
    if (n >= 5) {
      for (Eigen::Vector2d& p : v)
        p = Eigen::Vector2d(5, 5) + 2.0 * (p - Eigen::Vector2d(5, 5)).normalized();
      EXPECT_TRUE(One(Polyline{v, true}).Validate().ok()) << trial;
      std::swap(v[1], v[3]);
      EXPECT_FALSE(One(Polyline{v, true}).Validate().ok()) << trial;
    }
  }
}

TEST(World, PrimitivesOfEachShape) {
  World w;
  w.obstacles = {Polyline{{{0, 0}, {1, 0}, {1, 1}}, false},
                 Polyline{{{0, 0}, {1, 0}, {1, 1}}, true},
                 Spline{{{0, 5}, {1, 6}, {2, 5}, {3, 6}, {4, 5}}, false},
                 Spline{{{5, 5}, {6, 5}, {6, 6}}, true}};
  Primitives p;
  w.AppendPrimitives(0, &p);
  EXPECT_EQ(p.segments.size(), 2u);
  w.AppendPrimitives(1, &p);
  EXPECT_EQ(p.segments.size(), 5u);
  w.AppendPrimitives(2, &p);
  EXPECT_EQ(p.beziers.size(), 2u);  // 5 control points: 2 spans
  EXPECT_TRUE(p.beziers.front().p[0].isApprox(Eigen::Vector2d(0, 5)));
  EXPECT_TRUE(p.beziers.back().p[3].isApprox(Eigen::Vector2d(4, 5)));
  w.AppendPrimitives(3, &p);
  EXPECT_EQ(p.beziers.size(), 5u);
  EXPECT_EQ(ShapeKindName(w.obstacles[3]), "closed_spline");
}

// Property: a walker is always on its path, moves at most speed * dt between two instants, and
// is back where it started after one out-and-back walk (2 L / speed).
TEST(Walker, PropertyWalksItsPathBackAndForthAtItsSpeed) {
  kernel::Random random(11);
  for (int trial = 0; trial < 200; ++trial) {
    Walker w;
    const int n = 2 + static_cast<int>(random.Uniform() * 4);
    double length = 0.0;
    for (int k = 0; k < n; ++k) {
      w.path.emplace_back(random.Uniform(-10, 10), random.Uniform(-10, 10));
      if (k > 0) length += (w.path[k] - w.path[k - 1]).norm();
    }
    w.speed_mps = random.Uniform(0.2, 2.0);
    w.start_offset_m = random.Uniform(0.0, 30.0);
    World world;
    world.people = {w};
    ASSERT_TRUE(world.Validate().ok());
    const double period = 2.0 * length / w.speed_mps;
    Eigen::Vector2d last = w.PositionAt(0.0);
    for (double t = 0.05; t < 2.0 * period; t += 0.05) {
      const Eigen::Vector2d p = w.PositionAt(t);
      EXPECT_LE((p - last).norm(), w.speed_mps * 0.05 + 1e-9);
      double to_path = 1e9;
      for (int k = 1; k < n; ++k)
        to_path = std::min(to_path, kernel::Segment2{w.path[k - 1], w.path[k]}.Distance(p));
      EXPECT_LT(to_path, 1e-9);
      last = p;
    }
    EXPECT_LT((w.PositionAt(period) - w.PositionAt(0.0)).norm(), 1e-6);
  }
}

TEST(Walker, ValidateNamesThePerson) {
  World w;
  w.people.push_back({{{0, 0}, {1, 0}}, 1.0, 0.25, 0.0});
  w.people.push_back({{{0, 0}, {1, 0}}, 1.0, 0.0, 0.0});
  EXPECT_EQ(w.Validate().message(), "person 1: radius must be in (0, 5] m");
  w.people[1] = {{{0, 0}}, 1.0, 0.25, 0.0};
  EXPECT_EQ(w.Validate().message(), "person 1: path needs at least 2 points");
  w.people[1] = {{{0, 0}, {NAN, 0}}, 1.0, 0.25, 0.0};
  EXPECT_EQ(w.Validate().message(), "person 1: path not finite or beyond +-1e6 m");
  w.people.assign(kMaxPeople + 1, {{{0, 0}, {1, 0}}, 1.0, 0.25, 0.0});
  EXPECT_EQ(w.Validate().message(), "at most 1000 people, not 1001");
}

TEST(World, BoundsCoverAllShapes) {
  World w;
  w.obstacles = {Polyline{{{0, 0}, {1, 0}}, false}, kernel::Circle2{{5, 5}, 1.0}};
  const kernel::Box2 b = w.Bounds();
  EXPECT_EQ(b.min, Eigen::Vector2d(0, 0));
  EXPECT_EQ(b.max, Eigen::Vector2d(6, 6));
}

}  // namespace
}  // namespace splam::sim
