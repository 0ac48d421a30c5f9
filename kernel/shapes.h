#ifndef SPLAM_KERNEL_SHAPES_H_
#define SPLAM_KERNEL_SHAPES_H_

#include <Eigen/Core>
#include <limits>
#include <vector>

namespace splam::kernel {

inline constexpr double kNoHit = std::numeric_limits<double>::infinity();

// A ray p(t) = origin + t * direction, t >= 0; `direction` must have unit length so that t is a
// distance in metres.
struct Ray2 {
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  Eigen::Vector2d direction = Eigen::Vector2d::UnitX();

  Eigen::Vector2d At(double t) const { return origin + t * direction; }
};

// Axis-aligned box; empty when min > max.
struct Box2 {
  Eigen::Vector2d min = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d max = Eigen::Vector2d::Constant(-std::numeric_limits<double>::infinity());

  void Extend(const Eigen::Vector2d& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  void Extend(const Box2& b) {
    min = min.cwiseMin(b.min);
    max = max.cwiseMax(b.max);
  }
  bool IsEmpty() const { return (min.array() > max.array()).any(); }
  Eigen::Vector2d Size() const { return max - min; }
  // Distance between the two boxes, 0 when they touch or overlap (both non-empty).
  double Gap(const Box2& b) const {
    return (min - b.max).cwiseMax(b.min - max).cwiseMax(0.0).norm();
  }
};

// Every Intersect* function returns the smallest ray parameter t with t_min < t < t_max at
// which the ray meets the shape's boundary, or kNoHit. The results are exact up to floating
// point rounding (closed forms for segments, circles and ellipses).

struct Segment2 {
  Eigen::Vector2d a, b;

  double Length() const { return (b - a).norm(); }
  double Distance(const Eigen::Vector2d& p) const;
  Box2 Bounds() const;
};
double Intersect(const Ray2& ray, const Segment2& segment, double t_min, double t_max);

struct Circle2 {
  Eigen::Vector2d center;
  double radius = 0.0;  // > 0

  // Distance to the circle line (not the disc).
  double Distance(const Eigen::Vector2d& p) const;
  bool Contains(const Eigen::Vector2d& p) const { return (p - center).norm() < radius; }
  Box2 Bounds() const;
};
double Intersect(const Ray2& ray, const Circle2& circle, double t_min, double t_max);

// Ellipse with semi-axes radius_x >= 0 along its own x axis and radius_y, the x axis rotated by
// angle_rad from the world x axis.
struct Ellipse2 {
  Eigen::Vector2d center;
  double radius_x = 0.0;  // > 0
  double radius_y = 0.0;  // > 0
  double angle_rad = 0.0;

  Eigen::Vector2d PointAt(double u_rad) const;
  // Distance to the ellipse line, accurate to 1e-9 m (sampling then Newton on the parameter).
  double Distance(const Eigen::Vector2d& p) const;
  bool Contains(const Eigen::Vector2d& p) const;
  Box2 Bounds() const;
};
double Intersect(const Ray2& ray, const Ellipse2& ellipse, double t_min, double t_max);

// True when the box and the segment share a point (separating-axis test).
bool Overlaps(const Box2& box, const Segment2& segment);

// Length of the open polyline through the points, metres (0 for fewer than two).
double PolylineLength(const std::vector<Eigen::Vector2d>& points);

}  // namespace splam::kernel

#endif  // SPLAM_KERNEL_SHAPES_H_
