#include "sim/world.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "kernel/bspline.h"

namespace splam::sim {
namespace {

template <class... Ts>
struct Overloaded : Ts... {
  using Ts::operator()...;
};
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;  // Clang 14 does not deduce aggregates (the fuzz build)

constexpr char kNotPlausible[] = "not finite or beyond +-1e6 m";

// Within kernel::kMaxCoordinateM; false for NaN.
bool Plausible(double value) { return std::abs(value) <= kernel::kMaxCoordinateM; }
bool AllPlausible(const std::vector<Eigen::Vector2d>& points) {
  for (const Eigen::Vector2d& p : points) {
    if (!Plausible(p.x()) || !Plausible(p.y())) return false;
  }
  return true;
}

// The sign of the turn a -> b -> c (exact for the doubles of a world's coordinates up to the
// rounding of one product; enough to tell crossing edges from touching ones here).
int Orientation(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  const double cross = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
  return (cross > 0.0) - (cross < 0.0);
}
// Whether segments p1-p2 and q1-q2 share a point.
bool SegmentsMeet(const Eigen::Vector2d& p1, const Eigen::Vector2d& p2, const Eigen::Vector2d& q1,
                  const Eigen::Vector2d& q2) {
  const int o1 = Orientation(p1, p2, q1), o2 = Orientation(p1, p2, q2);
  const int o3 = Orientation(q1, q2, p1), o4 = Orientation(q1, q2, p2);
  if (o1 != o2 && o3 != o4) return true;
  const auto on = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
    return c.x() >= std::min(a.x(), b.x()) && c.x() <= std::max(a.x(), b.x()) &&
           c.y() >= std::min(a.y(), b.y()) && c.y() <= std::max(a.y(), b.y());
  };
  return (o1 == 0 && on(p1, p2, q1)) || (o2 == 0 && on(p1, p2, q2)) ||
         (o3 == 0 && on(q1, q2, p1)) || (o4 == 0 && on(q1, q2, p2));
}

// Empty when the closed polygon is simple (no two edges that are not neighbours meet), else
// which edges cross. Quadratic in the vertices, with a bounding-box test first.
std::string SelfIntersection(const std::vector<Eigen::Vector2d>& v) {
  const std::size_t n = v.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d &a = v[i], &b = v[(i + 1) % n];
    for (std::size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // neighbours through the closing edge
      const Eigen::Vector2d &c = v[j], &d = v[(j + 1) % n];
      if (std::max(c.x(), d.x()) < std::min(a.x(), b.x()) ||
          std::min(c.x(), d.x()) > std::max(a.x(), b.x()) ||
          std::max(c.y(), d.y()) < std::min(a.y(), b.y()) ||
          std::min(c.y(), d.y()) > std::max(a.y(), b.y()))
        continue;
      if (SegmentsMeet(a, b, c, d))
        return "edges " + std::to_string(i) + " and " + std::to_string(j) +
               " cross: a polygon must not intersect itself";
    }
  }
  return "";
}

std::vector<kernel::CubicBezier> SplinePieces(const Spline& spline) {
  if (spline.closed) return kernel::ClosedUniformBSplineToBezier(spline.control_points);
  return kernel::CubicBSpline::ClampedUniform(spline.control_points)->pieces();
}

}  // namespace

std::string ShapeKindName(const Shape& shape) {
  return std::visit(
      Overloaded{
          [](const Polyline& p) -> std::string { return p.closed ? "polygon" : "polyline"; },
          [](const kernel::Circle2&) -> std::string { return "circle"; },
          [](const kernel::Ellipse2&) -> std::string { return "ellipse"; },
          [](const Spline& s) -> std::string { return s.closed ? "closed_spline" : "spline"; }},
      shape);
}

kernel::Status World::Validate() const {
  for (std::size_t i = 0; i < obstacles.size(); ++i) {
    const std::string where =
        "obstacle " + std::to_string(i) + " (" + ShapeKindName(obstacles[i]) + "): ";
    const std::string problem = std::visit(
        Overloaded{[](const Polyline& p) -> std::string {
                     const std::size_t need = p.closed ? 3 : 2;
                     if (p.vertices.size() < need) {
                       return "needs at least " + std::to_string(need) + " vertices, has " +
                              std::to_string(p.vertices.size());
                     }
                     if (!AllPlausible(p.vertices)) return kNotPlausible;
                     const std::size_t edges = p.closed ? p.vertices.size() : p.vertices.size() - 1;
                     for (std::size_t k = 0; k < edges; ++k) {
                       if (p.vertices[k] == p.vertices[(k + 1) % p.vertices.size()]) {
                         return "edge " + std::to_string(k) + " has zero length";
                       }
                     }
                     return p.closed ? SelfIntersection(p.vertices) : "";
                   },
                   [](const kernel::Circle2& c) -> std::string {
                     if (!AllPlausible({c.center}) || !Plausible(c.radius)) return kNotPlausible;
                     return c.radius > 0.0 ? "" : "radius must be positive";
                   },
                   [](const kernel::Ellipse2& e) -> std::string {
                     if (!AllPlausible({e.center}) || !Plausible(e.radius_x) ||
                         !Plausible(e.radius_y) || !std::isfinite(e.angle_rad)) {
                       return kNotPlausible;
                     }
                     return (e.radius_x > 0.0 && e.radius_y > 0.0) ? "" : "radii must be positive";
                   },
                   [](const Spline& s) -> std::string {
                     const std::size_t need = s.closed ? 3 : 4;
                     if (s.control_points.size() < need) {
                       return "needs at least " + std::to_string(need) + " control points, has " +
                              std::to_string(s.control_points.size());
                     }
                     if (!AllPlausible(s.control_points)) return kNotPlausible;
                     for (const Eigen::Vector2d& p : s.control_points)
                       if (p != s.control_points.front()) return "";
                     return "all control points are the same point: the curve has no length";
                   }},
        obstacles[i]);
    if (!problem.empty()) return kernel::Status::Error(where + problem);
  }
  // Every laser beam meets every person: a bound on the people bounds each sweep's cost.
  if (people.size() > kMaxPeople)
    return kernel::Status::Error("at most " + std::to_string(kMaxPeople) + " people, not " +
                                 std::to_string(people.size()));
  for (std::size_t i = 0; i < people.size(); ++i) {
    const Walker& w = people[i];
    const std::string where = "person " + std::to_string(i) + ": ";
    if (w.path.size() < 2) return kernel::Status::Error(where + "path needs at least 2 points");
    if (!AllPlausible(w.path)) return kernel::Status::Error(where + "path " + kNotPlausible);
    if (!(w.speed_mps >= 0.0 && w.speed_mps <= 10.0))
      return kernel::Status::Error(where + "speed must be in [0, 10] m/s");
    if (!(w.radius_m > 0.0 && w.radius_m <= 5.0))
      return kernel::Status::Error(where + "radius must be in (0, 5] m");
    if (!(w.start_offset_m >= 0.0 && Plausible(w.start_offset_m)))
      return kernel::Status::Error(where + "start offset must be in [0, 1e6] m");
  }
  for (const std::size_t g : glass)
    if (g >= obstacles.size())
      return kernel::Status::Error("glass obstacle " + std::to_string(g) + " does not exist (" +
                                   std::to_string(obstacles.size()) + " obstacles)");
  if (start && (!AllPlausible({start->translation()}) || !std::isfinite(start->theta())))
    return kernel::Status::Error("start pose is not finite or beyond +-1e6 m");
  if (!AllPlausible(route))
    return kernel::Status::Error("route waypoint is not finite or beyond +-1e6 m");
  return kernel::Status::Ok();
}

void World::AppendPrimitives(std::size_t index, Primitives* out) const {
  std::visit(Overloaded{[&](const Polyline& p) {
                          const std::size_t n = p.vertices.size();
                          const std::size_t edges = p.closed ? n : n - 1;
                          for (std::size_t k = 0; k < edges; ++k) {
                            out->segments.push_back({p.vertices[k], p.vertices[(k + 1) % n]});
                          }
                        },
                        [&](const kernel::Circle2& c) { out->circles.push_back(c); },
                        [&](const kernel::Ellipse2& e) { out->ellipses.push_back(e); },
                        [&](const Spline& s) {
                          for (const kernel::CubicBezier& b : SplinePieces(s)) {
                            out->beziers.push_back(b);
                          }
                        }},
             obstacles[index]);
}

Eigen::Vector2d Walker::PositionAt(double time_s) const {
  double length = 0.0;
  for (std::size_t k = 1; k < path.size(); ++k) length += (path[k] - path[k - 1]).norm();
  if (!(length > 0.0)) return path.front();
  double s = std::fmod(start_offset_m + speed_mps * std::max(time_s, 0.0), 2.0 * length);
  if (s > length) s = 2.0 * length - s;  // on the way back
  for (std::size_t k = 1; k < path.size(); ++k) {
    const double edge = (path[k] - path[k - 1]).norm();
    if (s <= edge && edge > 0.0) return path[k - 1] + (s / edge) * (path[k] - path[k - 1]);
    s -= edge;
  }
  return path.back();
}

kernel::Box2 World::Bounds() const {
  kernel::Box2 box;
  Primitives all;
  for (std::size_t i = 0; i < obstacles.size(); ++i) AppendPrimitives(i, &all);
  for (const auto& s : all.segments) box.Extend(s.Bounds());
  for (const auto& c : all.circles) box.Extend(c.Bounds());
  for (const auto& e : all.ellipses) box.Extend(e.Bounds());
  for (const auto& b : all.beziers) box.Extend(b.ControlBounds());
  return box;
}

}  // namespace splam::sim
