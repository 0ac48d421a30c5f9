#include "sim/world.h"

#include <gtest/gtest.h>

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
            "obstacle 0 (circle): not finite");
  EXPECT_EQ(One(kernel::Ellipse2{{0, 0}, 1.0, -1.0, 0.0}).Validate().message(),
            "obstacle 0 (ellipse): radii must be positive");
  EXPECT_EQ(One(Spline{{{0, 0}, {1, 1}, {2, 0}}, false}).Validate().message(),
            "obstacle 0 (spline): needs at least 4 control points, has 3");
  EXPECT_EQ(One(Spline{{{0, 0}, {1, 1}}, true}).Validate().message(),
            "obstacle 0 (closed_spline): needs at least 3 control points, has 2");
  World w = One(kernel::Circle2{{0, 0}, 1.0});
  w.route = {{INFINITY, 0}};
  EXPECT_EQ(w.Validate().message(), "route waypoint is not finite");
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

TEST(World, BoundsCoverAllShapes) {
  World w;
  w.obstacles = {Polyline{{{0, 0}, {1, 0}}, false}, kernel::Circle2{{5, 5}, 1.0}};
  const kernel::Box2 b = w.Bounds();
  EXPECT_EQ(b.min, Eigen::Vector2d(0, 0));
  EXPECT_EQ(b.max, Eigen::Vector2d(6, 6));
}

}  // namespace
}  // namespace splam::sim
