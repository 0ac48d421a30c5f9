#ifndef SPLAM_SIM_WORLD_H_
#define SPLAM_SIM_WORLD_H_

#include <Eigen/Core>
#include <algorithm>
#include <cstddef>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "kernel/cubic_bezier.h"
#include "kernel/pose2.h"
#include "kernel/shapes.h"
#include "kernel/status.h"

namespace splam::sim {

// An open chain of straight walls, or a polygon when `closed`. A polygon is a solid obstacle (its
// inside collides); walls around a room are an open chain that returns to its first vertex.
struct Polyline {
  std::vector<Eigen::Vector2d> vertices;
  bool closed = false;
};

// A curved wall: an open cubic B-spline with clamped uniform knots (it starts at the first and
// ends at the last control point), or a closed uniform cubic B-spline (a smooth blob) when
// `closed`.
struct Spline {
  std::vector<Eigen::Vector2d> control_points;
  bool closed = false;
};

using Shape = std::variant<Polyline, kernel::Circle2, kernel::Ellipse2, Spline>;

// The primitives the ray caster works on; every obstacle decomposes into these.
struct Primitives {
  std::vector<kernel::Segment2> segments;
  std::vector<kernel::Circle2> circles;
  std::vector<kernel::Ellipse2> ellipses;
  std::vector<kernel::CubicBezier> beziers;
};

// A person walking back and forth along a path at a constant speed: a disc the laser sees but
// that is no obstacle of the world (not in its map, not in the sensors' ground truth, not in the
// robot's way: people step aside).
struct Walker {
  std::vector<Eigen::Vector2d> path;  // >= 2 points, walked to the end and back, forever
  double speed_mps = 1.0;             // in [0, 10]
  double radius_m = 0.25;             // in (0, 5]
  double start_offset_m = 0.0;        // distance along the out-and-back walk at t = 0, >= 0

  // Where the person is at `time_s`: s = start_offset + speed * t folded into [0, 2 L) of the
  // out-and-back walk of a path of length L.
  Eigen::Vector2d PositionAt(double time_s) const;
};

// At most this many people walk through a world (World::Validate).
inline constexpr std::size_t kMaxPeople = 1000;

// A 2-D world: static obstacles (their index is the obstacle id the sensors report), people
// walking through it, an optional start pose and an optional default route of waypoints.
struct World {
  std::string name;
  std::vector<Shape> obstacles;
  std::vector<Walker> people;
  // Indices of obstacles of glass: a wall for the robot and the sonar, but the laser reads no
  // return where its beam meets one (the light passes or is reflected away), as from the glass
  // doors, windows and partitions of real buildings.
  std::vector<std::size_t> glass;
  std::optional<kernel::Pose2> start;
  std::vector<Eigen::Vector2d> route;

  // Ok when valid, else what is wrong and with which obstacle: polylines need >= 2 vertices
  // (polygons 3) without zero-length edges, circles and ellipses positive radii, open splines
  // >= 4 and closed splines >= 3 control points; people as Walker says, at most kMaxPeople;
  // glass indices those of obstacles; all coordinates finite.
  kernel::Status Validate() const;
  // Whether obstacle `index` is of glass (listed in `glass`).
  bool IsGlass(std::size_t index) const {
    return std::find(glass.begin(), glass.end(), index) != glass.end();
  }
  // Exact primitives of obstacle `index`: segments, circles, ellipses, Bezier pieces.
  void AppendPrimitives(std::size_t index, Primitives* out) const;
  kernel::Box2 Bounds() const;
};

// Name of the shape's kind as used in world files: polyline, polygon, circle, ellipse, spline,
// closed_spline.
std::string ShapeKindName(const Shape& shape);

}  // namespace splam::sim

#endif  // SPLAM_SIM_WORLD_H_
