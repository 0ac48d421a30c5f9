#include "sim/world.h"

#include <cmath>

#include "kernel/bspline.h"

namespace splam::sim {
namespace {

template <class... Ts>
struct Overloaded : Ts... {
  using Ts::operator()...;
};

bool AllFinite(const std::vector<Eigen::Vector2d>& points) {
  for (const Eigen::Vector2d& p : points) {
    if (!p.allFinite()) return false;
  }
  return true;
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
                     if (!AllFinite(p.vertices)) return "vertex is not finite";
                     const std::size_t edges = p.closed ? p.vertices.size() : p.vertices.size() - 1;
                     for (std::size_t k = 0; k < edges; ++k) {
                       if (p.vertices[k] == p.vertices[(k + 1) % p.vertices.size()]) {
                         return "edge " + std::to_string(k) + " has zero length";
                       }
                     }
                     return "";
                   },
                   [](const kernel::Circle2& c) -> std::string {
                     if (!c.center.allFinite() || !std::isfinite(c.radius)) return "not finite";
                     return c.radius > 0.0 ? "" : "radius must be positive";
                   },
                   [](const kernel::Ellipse2& e) -> std::string {
                     if (!e.center.allFinite() || !std::isfinite(e.radius_x) ||
                         !std::isfinite(e.radius_y) || !std::isfinite(e.angle_rad)) {
                       return "not finite";
                     }
                     return (e.radius_x > 0.0 && e.radius_y > 0.0) ? "" : "radii must be positive";
                   },
                   [](const Spline& s) -> std::string {
                     const std::size_t need = s.closed ? 3 : 4;
                     if (s.control_points.size() < need) {
                       return "needs at least " + std::to_string(need) + " control points, has " +
                              std::to_string(s.control_points.size());
                     }
                     return AllFinite(s.control_points) ? "" : "control point is not finite";
                   }},
        obstacles[i]);
    if (!problem.empty()) return kernel::Status::Error(where + problem);
  }
  if (start && !start->ToVector().allFinite())
    return kernel::Status::Error("start pose is not finite");
  if (!AllFinite(route)) return kernel::Status::Error("route waypoint is not finite");
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
