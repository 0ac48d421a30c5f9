#include "kernel/shapes.h"

#include <algorithm>
#include <cmath>

#include "kernel/angle.h"

namespace splam::kernel {
namespace {

double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// Smallest root in (t_min, t_max) of t^2 + 2 h t + c = 0, computed without cancellation.
double SmallestQuadraticRoot(double h, double c, double t_min, double t_max) {
  const double disc = h * h - c;
  if (disc < 0.0) return kNoHit;
  const double q = -(h + std::copysign(std::sqrt(disc), h));  // |q| >= |h|
  double r0 = q;
  double r1 = (q != 0.0) ? c / q : 0.0;
  if (r0 > r1) std::swap(r0, r1);
  if (r0 > t_min && r0 < t_max) return r0;
  if (r1 > t_min && r1 < t_max) return r1;
  return kNoHit;
}

}  // namespace

double Segment2::Distance(const Eigen::Vector2d& p) const {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  if (len2 == 0.0) return (p - a).norm();
  const double s = std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
  return (a + s * ab - p).norm();
}

Box2 Segment2::Bounds() const {
  Box2 box;
  box.Extend(a);
  box.Extend(b);
  return box;
}

double Intersect(const Ray2& ray, const Segment2& segment, double t_min, double t_max) {
  // origin + t d = a + s (b - a):  t = cross(a - o, e) / cross(d, e), s = cross(a - o, d) / ...
  const Eigen::Vector2d e = segment.b - segment.a;
  const double denom = Cross(ray.direction, e);
  if (denom == 0.0) return kNoHit;  // parallel; a collinear overlap has no single hit point
  const Eigen::Vector2d ao = segment.a - ray.origin;
  const double t = Cross(ao, e) / denom;
  const double s = Cross(ao, ray.direction) / denom;
  if (s < 0.0 || s > 1.0 || t <= t_min || t >= t_max) return kNoHit;
  return t;
}

double Circle2::Distance(const Eigen::Vector2d& p) const {
  return std::abs((p - center).norm() - radius);
}

Box2 Circle2::Bounds() const {
  return {center - Eigen::Vector2d::Constant(radius), center + Eigen::Vector2d::Constant(radius)};
}

double Intersect(const Ray2& ray, const Circle2& circle, double t_min, double t_max) {
  const Eigen::Vector2d oc = ray.origin - circle.center;
  return SmallestQuadraticRoot(ray.direction.dot(oc),
                               oc.squaredNorm() - circle.radius * circle.radius, t_min, t_max);
}

Eigen::Vector2d Ellipse2::PointAt(double u_rad) const {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  const double ex = radius_x * std::cos(u_rad), ey = radius_y * std::sin(u_rad);
  return center + Eigen::Vector2d(c * ex - s * ey, s * ex + c * ey);
}

bool Ellipse2::Contains(const Eigen::Vector2d& p) const {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  const Eigen::Vector2d q = p - center;
  const double lx = (c * q.x() + s * q.y()) / radius_x;
  const double ly = (-s * q.x() + c * q.y()) / radius_y;
  return lx * lx + ly * ly < 1.0;
}

double Ellipse2::Distance(const Eigen::Vector2d& p) const {
  // Work in the ellipse frame: q = (a cos u, b sin u). Minimise |q(u) - p|^2 over u by a coarse
  // scan followed by Newton steps on the derivative (a 1-D problem, well conditioned near the
  // minimum found by the scan).
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  const Eigen::Vector2d d = p - center;
  const double px = c * d.x() + s * d.y(), py = -s * d.x() + c * d.y();
  const double a = radius_x, b = radius_y;
  auto dist2 = [&](double u) {
    const double dx = a * std::cos(u) - px, dy = b * std::sin(u) - py;
    return dx * dx + dy * dy;
  };
  constexpr int kSamples = 64;
  double best_u = 0.0, best = dist2(0.0);
  for (int i = 1; i < kSamples; ++i) {
    const double u = 2.0 * kPi * i / kSamples;
    const double v = dist2(u);
    if (v < best) best = v, best_u = u;
  }
  double u = best_u;
  for (int it = 0; it < 20; ++it) {
    const double cu = std::cos(u), su = std::sin(u);
    // f(u) = 0.5 d/du |q - p|^2 and its derivative.
    const double f = (a * cu - px) * (-a * su) + (b * su - py) * (b * cu);
    const double df = (a * su) * (a * su) + (a * cu - px) * (-a * cu) + (b * cu) * (b * cu) +
                      (b * su - py) * (-b * su);
    if (df <= 0.0) break;
    const double step = f / df;
    u -= std::clamp(step, -0.1, 0.1);
    if (std::abs(step) < 1e-12) break;
  }
  return std::sqrt(std::min(best, dist2(u)));
}

Box2 Ellipse2::Bounds() const {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  const Eigen::Vector2d half(std::hypot(radius_x * c, radius_y * s),
                             std::hypot(radius_x * s, radius_y * c));
  return {center - half, center + half};
}

double Intersect(const Ray2& ray, const Ellipse2& ellipse, double t_min, double t_max) {
  // Map the ellipse to the unit circle; the ray parameter t is unchanged by the affine map.
  const double c = std::cos(ellipse.angle_rad), s = std::sin(ellipse.angle_rad);
  const Eigen::Vector2d q = ray.origin - ellipse.center;
  const Eigen::Vector2d o((c * q.x() + s * q.y()) / ellipse.radius_x,
                          (-s * q.x() + c * q.y()) / ellipse.radius_y);
  const Eigen::Vector2d d((c * ray.direction.x() + s * ray.direction.y()) / ellipse.radius_x,
                          (-s * ray.direction.x() + c * ray.direction.y()) / ellipse.radius_y);
  // |o + t d|^2 = 1  <=>  t^2 + 2 (o.d / d.d) t + (o.o - 1) / d.d = 0.
  const double dd = d.squaredNorm();
  return SmallestQuadraticRoot(o.dot(d) / dd, (o.squaredNorm() - 1.0) / dd, t_min, t_max);
}

bool Overlaps(const Box2& box, const Segment2& segment) {
  const Box2 sb = segment.Bounds();
  if ((sb.max.array() < box.min.array()).any() || (sb.min.array() > box.max.array()).any()) {
    return false;
  }
  // Separating axis: the segment's normal. All four corners strictly on one side -> apart.
  const Eigen::Vector2d e = segment.b - segment.a;
  const Eigen::Vector2d corners[4] = {
      box.min, {box.max.x(), box.min.y()}, box.max, {box.min.x(), box.max.y()}};
  int positive = 0, negative = 0;
  for (const Eigen::Vector2d& corner : corners) {
    const double side = Cross(e, corner - segment.a);
    positive += side > 0.0;
    negative += side < 0.0;
  }
  return positive < 4 && negative < 4;
}

double PolylineLength(const std::vector<Eigen::Vector2d>& points) {
  double length = 0.0;
  for (std::size_t i = 1; i < points.size(); ++i) length += (points[i] - points[i - 1]).norm();
  return length;
}

}  // namespace splam::kernel
