#include "sim/builtin_worlds.h"

#include <algorithm>
#include <cmath>

#include "kernel/angle.h"

namespace splam::sim {
namespace {

using V = Eigen::Vector2d;

Polyline Wall(std::vector<V> vertices) { return {std::move(vertices), false}; }
Polyline Polygon(std::vector<V> vertices) { return {std::move(vertices), true}; }
Polyline Rectangle(double x0, double y0, double x1, double y1) {
  return Polygon({{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}});
}

World Corridor() {
  World w;
  w.name = "corridor";
  // South wall (y = -1.2): a 1 m recess at x 3-4, a door at x 6-7 into a 3 m x 2 m room,
  // a 2 m recess at x 10-12, a 3 m recess at x 15-18.
  w.obstacles.push_back(Wall({{0, -1.2},
                              {3, -1.2},
                              {3, -1.5},
                              {4, -1.5},
                              {4, -1.2},
                              {6, -1.2},
                              {6, -3.2},
                              {9, -3.2},
                              {9, -1.2},
                              {7, -1.2}}));
  w.obstacles.push_back(Wall({{9, -1.2},
                              {10, -1.2},
                              {10, -1.5},
                              {12, -1.5},
                              {12, -1.2},
                              {15, -1.2},
                              {15, -1.6},
                              {18, -1.6},
                              {18, -1.2},
                              {24, -1.2}}));
  // North wall (y = +1.2): a 2 m recess at x 2-4, a door at x 8-9 into a 3 m x 2 m room,
  // a 3 m recess at x 11-14, a 1 m recess at x 17-18.
  w.obstacles.push_back(Wall({{0, 1.2},
                              {2, 1.2},
                              {2, 1.5},
                              {4, 1.5},
                              {4, 1.2},
                              {8, 1.2},
                              {8, 3.2},
                              {11, 3.2},
                              {11, 1.2},
                              {9, 1.2}}));
  w.obstacles.push_back(Wall({{11, 1.2},
                              {11, 1.5},
                              {14, 1.5},
                              {14, 1.2},
                              {17, 1.2},
                              {17, 1.5},
                              {18, 1.5},
                              {18, 1.2},
                              {24, 1.2}}));
  // End walls.
  w.obstacles.push_back(Wall({{0, -1.2}, {0, 1.2}}));
  w.obstacles.push_back(Wall({{24, -1.2}, {24, 1.2}}));
  // Straight run of 16 m started 2.7 deg off the corridor axis.
  const double heading = kernel::DegToRad(2.7);
  w.start = kernel::Pose2(1.0, -0.35, heading);
  w.route = {V(1.0 + 16.0 * std::cos(heading), -0.35 + 16.0 * std::sin(heading))};
  return w;
}

World Office() {
  World w;
  w.name = "office";
  w.obstacles.push_back(Wall({{0, 0}, {16, 0}, {16, 12}, {0, 12}, {0, 0}}));  // outer walls
  // Corridor y 5-7. South side: three rooms with doors at x 2-2.9, 7-7.9, 13-13.9.
  w.obstacles.push_back(Wall({{0, 5}, {2, 5}}));
  w.obstacles.push_back(Wall({{2.9, 5}, {7, 5}}));
  w.obstacles.push_back(Wall({{7.9, 5}, {13, 5}}));
  w.obstacles.push_back(Wall({{13.9, 5}, {16, 5}}));
  w.obstacles.push_back(Wall({{5, 0}, {5, 5}}));
  w.obstacles.push_back(Wall({{10, 0}, {10, 5}}));
  // North side: doors at x 3-3.9, 8-8.9, 13.5-14.4.
  w.obstacles.push_back(Wall({{0, 7}, {3, 7}}));
  w.obstacles.push_back(Wall({{3.9, 7}, {8, 7}}));
  w.obstacles.push_back(Wall({{8.9, 7}, {13.5, 7}}));
  w.obstacles.push_back(Wall({{14.4, 7}, {16, 7}}));
  w.obstacles.push_back(Wall({{6, 7}, {6, 12}}));
  w.obstacles.push_back(Wall({{11, 7}, {11, 12}}));
  // Furniture: tables and cabinets.
  w.obstacles.push_back(Rectangle(1.0, 1.0, 2.6, 1.8));
  w.obstacles.push_back(Rectangle(6.5, 2.2, 8.5, 3.0));
  w.obstacles.push_back(Rectangle(14.6, 0.4, 15.6, 2.0));
  w.obstacles.push_back(Rectangle(1.5, 9.5, 3.5, 10.3));
  w.obstacles.push_back(Rectangle(8.0, 10.8, 10.4, 11.6));
  w.obstacles.push_back(Rectangle(12.5, 9.0, 13.7, 10.2));
  w.start = kernel::Pose2(1.0, 6.0, 0.0);
  w.route = {V(7.45, 6.0),  V(7.45, 4.0),  V(9.0, 4.0),   V(9.0, 1.2),   V(5.8, 1.2),
             V(5.8, 4.0),   V(7.45, 4.0),  V(7.45, 6.0),  V(8.45, 6.0),  V(8.45, 8.5),
             V(8.45, 9.8),  V(7.0, 9.8),   V(7.0, 8.2),   V(8.45, 8.2),  V(8.45, 6.0),
             V(15.0, 6.0),  V(13.95, 6.0), V(13.95, 8.5), V(15.0, 9.5),  V(15.0, 11.0),
             V(12.0, 11.0), V(12.0, 8.2),  V(13.95, 8.2), V(13.95, 6.0), V(2.0, 6.0)};
  return w;
}

// Adds a straight wall from p to q with a door of `width` metres centred on it: two walls.
void AddWallWithDoor(World* w, const V& p, const V& q, double width) {
  const V u = (q - p).normalized();
  const V middle = 0.5 * (p + q);
  w->obstacles.push_back(Wall({p, middle - 0.5 * width * u}));
  w->obstacles.push_back(Wall({middle + 0.5 * width * u, q}));
}

World OfficeLong() {
  World w;
  w.name = "office-long";
  w.obstacles.push_back(Wall({{0, 0}, {30, 0}, {30, 12}, {0, 12}, {0, 0}}));  // outer walls
  // A corridor y 5-7 along the whole floor. South: six 5 m rooms, each with a 1 m door.
  for (int k = 0; k < 6; ++k) {
    const double x = 5.0 * k;
    AddWallWithDoor(&w, V(x, 5), V(x + 5, 5), 1.0);
    if (k > 0) w.obstacles.push_back(Wall({{x, 0}, {x, 5}}));
  }
  // North: five rooms (x 0-25) with 1 m doors off centre, then a dead-end corridor x 25-26.5
  // running 5 m north, and a solid block beside it.
  for (int k = 0; k < 5; ++k) {
    const double x = 5.0 * k;
    w.obstacles.push_back(Wall({{x, 7}, {x + 1.0 + 0.6 * k, 7}}));
    w.obstacles.push_back(Wall({{x + 2.0 + 0.6 * k, 7}, {x + 5, 7}}));
    if (k > 0) w.obstacles.push_back(Wall({{x, 7}, {x, 12}}));
  }
  w.obstacles.push_back(Wall({{25, 7}, {25, 12}}));
  w.obstacles.push_back(Polygon({{26.5, 7}, {30, 7}, {30, 12}, {26.5, 12}}));
  // Furniture.
  w.obstacles.push_back(Rectangle(1.0, 1.0, 3.0, 1.8));
  w.obstacles.push_back(Rectangle(11.5, 2.0, 13.5, 2.8));
  w.obstacles.push_back(Rectangle(21.0, 0.3, 22.2, 1.5));
  w.obstacles.push_back(Rectangle(27.0, 2.5, 28.6, 3.3));
  w.obstacles.push_back(Rectangle(6.5, 10.0, 8.5, 10.8));
  w.obstacles.push_back(Rectangle(16.0, 8.5, 17.2, 9.7));
  w.start = kernel::Pose2(1.0, 6.0, 0.0);
  w.route = {V(25.75, 6.0), V(25.75, 11.0), V(25.75, 6.0), V(28.5, 6.0), V(1.5, 6.0)};
  return w;
}

World OfficeDoors() {
  World w;
  w.name = "office-doors";
  w.obstacles.push_back(Wall({{0, 0}, {16, 0}, {16, 12}, {0, 12}, {0, 0}}));  // outer walls
  // A hall in the middle and a room in each corner behind a wall at a different angle, with a
  // door of a different width: 0.8 m at 45 deg (south-west), 0.9 m at 39 deg (south-east),
  // 1.0 m at -45 deg (north-east), 1.2 m and 0.8 m in an L-shaped wall (north-west).
  AddWallWithDoor(&w, V(0, 5.5), V(5.5, 0), 0.8);
  AddWallWithDoor(&w, V(11, 0), V(16, 4), 0.9);
  AddWallWithDoor(&w, V(16, 7.5), V(11.5, 12), 1.0);
  AddWallWithDoor(&w, V(0, 8), V(4.5, 8), 1.2);
  AddWallWithDoor(&w, V(4.5, 8), V(4.5, 12), 0.8);
  // Furniture: a table in the hall, a cabinet in the south-west room, a round table.
  w.obstacles.push_back(Rectangle(7.0, 5.5, 9.0, 6.3));
  w.obstacles.push_back(Rectangle(0.3, 0.3, 1.5, 1.0));
  w.obstacles.push_back(kernel::Circle2{{13.0, 9.0}, 0.4});
  w.start = kernel::Pose2(8.0, 4.0, 0.0);
  w.route = {V(11.0, 4.5), V(11.0, 7.5), V(5.5, 7.0), V(5.0, 4.0), V(8.0, 4.0)};
  return w;
}

World Complex() {
  World w;
  w.name = "complex";
  // Boundary: a straight south wall, a wavy spline east wall, a wavy spline north wall and a
  // west wall with a rectangular alcove. Clamped splines end exactly at their end points, so the
  // boundary is closed.
  w.obstacles.push_back(Wall({{0, 0}, {20, 0}}));
  w.obstacles.push_back(Spline{{{20, 0}, {21.2, 3}, {19.4, 7}, {21.3, 11}, {20, 15}}, false});
  w.obstacles.push_back(
      Spline{{{20, 15}, {16, 16.4}, {12, 14.0}, {8, 16.2}, {4, 14.4}, {0, 15}}, false});
  w.obstacles.push_back(Wall({{0, 15}, {0, 9.5}, {-1.2, 9.5}, {-1.2, 6.5}, {0, 6.5}, {0, 0}}));
  // Round pillars.
  w.obstacles.push_back(kernel::Circle2{{5.0, 4.8}, 0.35});
  w.obstacles.push_back(kernel::Circle2{{10.2, 3.6}, 0.3});
  w.obstacles.push_back(kernel::Circle2{{14.6, 5.2}, 0.4});
  w.obstacles.push_back(kernel::Circle2{{9.8, 11.6}, 0.3});
  // An elliptical table.
  w.obstacles.push_back(kernel::Ellipse2{{15.6, 10.6}, 1.3, 0.6, kernel::DegToRad(30)});
  // Irregular smooth obstacles (closed splines).
  w.obstacles.push_back(Spline{
      {{2.6, 10.2}, {3.6, 9.4}, {5.0, 9.8}, {5.4, 11.2}, {4.4, 11.4}, {3.8, 12.2}, {2.6, 11.8}},
      true});
  w.obstacles.push_back(
      Spline{{{16.4, 1.2}, {17.8, 1.0}, {18.4, 2.2}, {17.2, 3.0}, {16.6, 2.4}}, true});
  // A free-standing S-shaped curved wall in the middle of the room.
  w.obstacles.push_back(
      Spline{{{7.0, 7.6}, {8.5, 9.2}, {10.5, 6.2}, {12.5, 8.8}, {13.6, 7.4}}, false});
  // An irregular polygonal obstacle.
  w.obstacles.push_back(Polygon({{11.8, 1.2}, {13.4, 1.0}, {13.8, 2.2}, {12.8, 2.9}, {11.6, 2.3}}));
  w.start = kernel::Pose2(1.5, 2.0, 0.0);
  w.route = {V(7.5, 2.0),   V(9.0, 5.2),   V(13.0, 6.3),  V(16.0, 6.6), V(18.3, 7.5),
             V(18.3, 12.6), V(13.0, 12.8), V(12.2, 10.2), V(7.5, 10.6), V(6.0, 13.0),
             V(1.5, 13.2),  V(1.2, 8.0),   V(2.5, 6.2),   V(1.5, 2.0)};
  return w;
}

// The side of a block from a to b (counter-clockwise around it) with a recess into the block,
// `width` wide and `depth` deep, every `spacing` metres: the points after a.
void AppendRecessedSide(const V& a, const V& b, double spacing, double width, double depth,
                        std::vector<V>* polygon) {
  const V u = (b - a).normalized();
  const V inward(-u.y(), u.x());  // the block lies left of a counter-clockwise side
  const double length = (b - a).norm();
  for (double t = spacing; t + width < length - 1.0; t += spacing) {
    polygon->push_back(a + t * u);
    polygon->push_back(a + t * u + depth * inward);
    polygon->push_back(a + (t + width) * u + depth * inward);
    polygon->push_back(a + (t + width) * u);
  }
  polygon->push_back(b);
}

World Loop() {
  World w;
  w.name = "loop";
  // A ring corridor 3 m wide around a 34 m x 20 m block (about 100 m round): the inner wall
  // recessed every 6 m, pillars along the outer wall every 7 m, the north-east corner rounded.
  w.obstacles.push_back(Wall({{34, 26}, {0, 26}, {0, 0}, {40, 0}, {40, 20}}));
  w.obstacles.push_back(Spline{{{40, 20}, {40, 24}, {38, 26}, {34, 26}}, false});
  std::vector<V> block{{3, 3}};
  AppendRecessedSide(V(3, 3), V(37, 3), 6.0, 1.0, 0.6, &block);
  AppendRecessedSide(V(37, 3), V(37, 23), 6.0, 1.0, 0.6, &block);
  AppendRecessedSide(V(37, 23), V(3, 23), 6.0, 1.0, 0.6, &block);
  AppendRecessedSide(V(3, 23), V(3, 3), 6.0, 1.0, 0.6, &block);
  block.pop_back();  // back at the first point
  w.obstacles.push_back(Polygon(block));
  for (double x = 5.0; x < 36.0; x += 7.0) {
    w.obstacles.push_back(kernel::Circle2{{x, 0.45}, 0.2});
    w.obstacles.push_back(kernel::Circle2{{x + 2.0, 25.55}, 0.2});
  }
  for (double y = 5.0; y < 22.0; y += 7.0) {
    w.obstacles.push_back(kernel::Circle2{{0.45, y}, 0.2});
    w.obstacles.push_back(kernel::Circle2{{39.55, y + 2.0}, 0.2});
  }
  w.start = kernel::Pose2(1.5, 13.0, M_PI / 2);
  w.route = {V(1.5, 24.5), V(37.5, 24.5), V(38.5, 22.0), V(38.5, 1.5), V(1.5, 1.5), V(1.5, 13.0)};
  return w;
}

// A closed spline around `center` whose control points alternate between radii `outer` and
// `inner`, `lobes` of each: a lobed outline with an inflection point between every lobe and dent.
Spline Lobed(const V& center, double outer, double inner, int lobes, double phase = 0.0) {
  std::vector<V> control;
  for (int k = 0; k < 2 * lobes; ++k) {
    const double angle = phase + M_PI * k / lobes;
    const double radius = k % 2 == 0 ? outer : inner;
    control.push_back(center + radius * V(std::cos(angle), std::sin(angle)));
  }
  return Spline{control, true};
}

// A star polygon: `points` corners at radius `outer` and as many at `inner` between them.
Polyline Star(const V& center, double outer, double inner, int points, double phase = 0.0) {
  std::vector<V> vertices;
  for (int k = 0; k < 2 * points; ++k) {
    const double angle = phase + M_PI * k / points;
    vertices.push_back(center + (k % 2 == 0 ? outer : inner) * V(std::cos(angle), std::sin(angle)));
  }
  return Polygon(vertices);
}

World Curves() {
  World w;
  w.name = "curves";
  // Two halls 12 m x 14 m joined by a corridor 8 m long and about 3 m wide, their obstacles rich
  // in the curvature features paper 000 pairs: lobed outlines (an inflection point between every
  // lobe and dent), free-standing S-shaped walls, star polygons (corners), wavy walls (the
  // corridor's, two halls' outer walls); a pillar and an ellipse (smooth, featureless) beside
  // them.
  w.obstacles.push_back(Wall({{12, 14}, {12, 8.5}}));
  w.obstacles.push_back(Spline{{{12, 8.5}, {14, 8.9}, {16, 8.1}, {18, 8.9}, {20, 8.5}}, false});
  w.obstacles.push_back(Wall({{20, 8.5}, {20, 14}, {32, 14}, {32, 0}}));
  w.obstacles.push_back(Spline{{{32, 0}, {29, -0.5}, {26, 0.7}, {22, -0.6}, {20, 0}}, false});
  w.obstacles.push_back(Wall({{20, 0}, {20, 5.5}}));
  w.obstacles.push_back(Spline{{{20, 5.5}, {18, 5.1}, {16, 5.9}, {14, 5.1}, {12, 5.5}}, false});
  w.obstacles.push_back(Wall({{12, 5.5}, {12, 0}, {0, 0}, {0, 14}}));
  w.obstacles.push_back(Spline{{{0, 14}, {3, 14.6}, {6, 13.4}, {9, 14.8}, {12, 14}}, false});
  // West hall.
  w.obstacles.push_back(Lobed(V(4.0, 4.0), 1.0, 0.35, 4));
  w.obstacles.push_back(Spline{{{5.5, 9.0}, {7.0, 10.5}, {8.5, 8.5}, {10.0, 10.0}}, false});
  w.obstacles.push_back(Star(V(9.0, 3.5), 0.8, 0.4, 5, 0.3));
  w.obstacles.push_back(kernel::Circle2{{6.5, 5.2}, 0.3});
  // East hall.
  w.obstacles.push_back(Lobed(V(25.0, 10.0), 1.1, 0.4, 5, 0.2));
  w.obstacles.push_back(kernel::Ellipse2{{29.0, 4.5}, 1.0, 0.5, kernel::DegToRad(20)});
  w.obstacles.push_back(Spline{{{22.0, 3.0}, {23.5, 4.5}, {25.0, 2.5}, {26.5, 4.0}}, false});
  w.obstacles.push_back(Star(V(29.5, 10.3), 0.8, 0.45, 4));
  w.obstacles.push_back(kernel::Circle2{{23.0, 7.0}, 0.35});
  // Round the west hall, the long excursion through the corridor and round the east hall, then
  // the west hall again: its obstacles re-observed after some 70 m.
  w.start = kernel::Pose2(1.5, 7.0, 0.0);
  w.route = {V(5.0, 7.0),   V(8.0, 6.6),   V(11.0, 7.0),  V(16.0, 7.0), V(21.5, 7.0), V(21.5, 12.5),
             V(27.5, 12.8), V(31.0, 12.5), V(31.0, 7.0),  V(31.0, 1.8), V(27.5, 1.5), V(21.5, 1.5),
             V(21.5, 7.0),  V(11.3, 7.0),  V(11.3, 12.5), V(1.5, 12.5), V(1.5, 2.0),  V(7.5, 1.5),
             V(11.0, 1.5),  V(11.0, 5.0),  V(7.0, 7.0),   V(1.5, 7.0)};
  return w;
}

// An arc of control points of radius `radius` around `center` from angle `from` to `to` (rad,
// counter-clockwise), about every `step` rad: an open spline close to a circular wall.
Spline CurvedWall(const V& center, double radius, double from, double to, double step) {
  const int n = std::max(3, static_cast<int>(std::ceil((to - from) / step)));
  std::vector<V> control;
  for (int k = 0; k <= n; ++k) {
    const double angle = from + (to - from) * k / n;
    control.push_back(center + radius * V(std::cos(angle), std::sin(angle)));
  }
  return Spline{control, false};
}

World Halls() {
  World w;
  w.name = "halls";
  // Two round halls (radius 7 m and 6.5 m, wider than the URG-04LX's 4 m) joined by a corridor
  // 2.4 m wide, with rings of round pillars: from the middle of a hall the laser sees pillars
  // only, and the curved walls from afar.
  const V a(8.0, 8.0), b(26.0, 8.0);
  const double gap_a = std::asin(1.2 / 7.0), gap_b = std::asin(1.2 / 6.5);
  w.obstacles.push_back(CurvedWall(a, 7.0, gap_a, 2.0 * M_PI - gap_a, 0.4));
  w.obstacles.push_back(CurvedWall(b, 6.5, -M_PI + gap_b, M_PI - gap_b, 0.4));
  const double a_end = a.x() + 7.0 * std::cos(gap_a), b_end = b.x() - 6.5 * std::cos(gap_b);
  w.obstacles.push_back(Wall({{a_end, 6.8}, {b_end, 6.8}}));
  w.obstacles.push_back(Wall({{a_end, 9.2}, {b_end, 9.2}}));
  for (int k = 0; k < 6; ++k) {
    const double angle = M_PI / 3.0 * k + M_PI / 6.0;
    w.obstacles.push_back(kernel::Circle2{a + 3.5 * V(std::cos(angle), std::sin(angle)), 0.3});
  }
  w.obstacles.push_back(kernel::Circle2{a, 0.4});
  for (int k = 0; k < 5; ++k) {
    const double angle = 2.0 * M_PI / 5.0 * k + 0.3;
    w.obstacles.push_back(kernel::Circle2{b + 3.0 * V(std::cos(angle), std::sin(angle)), 0.25});
  }
  w.obstacles.push_back(kernel::Ellipse2{b, 0.7, 0.35, kernel::DegToRad(30)});
  // Round hall a between its pillars and its wall, through the corridor, round hall b, back.
  const auto on = [](const V& c, double r, double deg) {
    return V(c + r * V(std::cos(kernel::DegToRad(deg)), std::sin(kernel::DegToRad(deg))));
  };
  w.start = kernel::Pose2(8.0, 2.75, 0.0);
  w.route = {on(a, 5.25, -45), on(a, 5.25, 0),   V(17.0, 8.0),     on(b, 4.7, 180),
             on(b, 4.7, 135),  on(b, 4.7, 90),   on(b, 4.7, 45),   on(b, 4.7, 0),
             on(b, 4.7, -45),  on(b, 4.7, -90),  on(b, 4.7, -135), on(b, 4.7, 180),
             V(17.0, 8.0),     on(a, 5.25, 0),   on(a, 5.25, 45),  on(a, 5.25, 90),
             on(a, 5.25, 135), on(a, 5.25, 180), on(a, 5.25, 225), on(a, 5.25, 270)};
  return w;
}

}  // namespace

std::vector<std::string> BuiltinWorldNames() {
  return {"corridor", "office", "office-long", "office-doors",
          "complex",  "loop",   "curves",      "halls"};
}

std::optional<World> BuiltinWorld(const std::string& name) {
  if (name == "corridor") return Corridor();
  if (name == "office") return Office();
  if (name == "office-long") return OfficeLong();
  if (name == "office-doors") return OfficeDoors();
  if (name == "complex") return Complex();
  if (name == "loop") return Loop();
  if (name == "curves") return Curves();
  if (name == "halls") return Halls();
  return std::nullopt;
}

}  // namespace splam::sim
