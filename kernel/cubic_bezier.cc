#include "kernel/cubic_bezier.h"

#include <algorithm>
#include <cmath>

namespace splam::kernel {
namespace {

// Cubic a u^3 + b u^2 + c u + e.
struct Cubic {
  double a, b, c, e;
  double operator()(double u) const { return ((a * u + b) * u + c) * u + e; }
  double Derivative(double u) const { return (3.0 * a * u + 2.0 * b) * u + c; }
};

// The single root of f in [lo, hi] given f(lo) and f(hi) of opposite signs and f monotone there.
double MonotoneRoot(const Cubic& f, double lo, double hi, double f_lo) {
  double u = 0.5 * (lo + hi);
  for (int it = 0; it < 100 && hi - lo > 1e-14; ++it) {
    const double fu = f(u);
    if (fu == 0.0) return u;
    if ((fu < 0.0) == (f_lo < 0.0)) {
      lo = u;
      f_lo = fu;
    } else {
      hi = u;
    }
    const double df = f.Derivative(u);
    double next = (df != 0.0) ? u - fu / df : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);  // Newton left the bracket: bisect
    u = next;
  }
  return u;
}

}  // namespace

Eigen::Vector2d CubicBezier::Point(double t) const {
  const double s = 1.0 - t;
  return s * s * s * p[0] + 3.0 * s * s * t * p[1] + 3.0 * s * t * t * p[2] + t * t * t * p[3];
}

Eigen::Vector2d CubicBezier::Derivative(double t) const {
  const double s = 1.0 - t;
  return 3.0 * (s * s * (p[1] - p[0]) + 2.0 * s * t * (p[2] - p[1]) + t * t * (p[3] - p[2]));
}

Eigen::Vector2d CubicBezier::SecondDerivative(double t) const {
  return 6.0 * ((1.0 - t) * (p[2] - 2.0 * p[1] + p[0]) + t * (p[3] - 2.0 * p[2] + p[1]));
}

Box2 CubicBezier::ControlBounds() const {
  Box2 box;
  for (const Eigen::Vector2d& q : p) box.Extend(q);
  return box;
}

std::pair<CubicBezier, CubicBezier> CubicBezier::Split(double t) const {
  const Eigen::Vector2d p01 = p[0] + t * (p[1] - p[0]);
  const Eigen::Vector2d p12 = p[1] + t * (p[2] - p[1]);
  const Eigen::Vector2d p23 = p[2] + t * (p[3] - p[2]);
  const Eigen::Vector2d p012 = p01 + t * (p12 - p01);
  const Eigen::Vector2d p123 = p12 + t * (p23 - p12);
  const Eigen::Vector2d mid = p012 + t * (p123 - p012);
  return {CubicBezier{{p[0], p01, p012, mid}}, CubicBezier{{mid, p123, p23, p[3]}}};
}

double CubicBezier::ClosestParameter(const Eigen::Vector2d& q) const {
  constexpr int kSamples = 32;
  double best_t = 0.0, best = (Point(0.0) - q).squaredNorm();
  for (int i = 1; i <= kSamples; ++i) {
    const double t = static_cast<double>(i) / kSamples;
    const double d = (Point(t) - q).squaredNorm();
    if (d < best) best = d, best_t = t;
  }
  double t = best_t;
  for (int it = 0; it < 20; ++it) {
    const Eigen::Vector2d r = Point(t) - q;
    const Eigen::Vector2d d1 = Derivative(t);
    const double g = d1.dot(r);
    const double dg = d1.squaredNorm() + SecondDerivative(t).dot(r);
    if (dg <= 0.0) break;
    const double next = std::clamp(t - g / dg, 0.0, 1.0);
    const bool done = std::abs(next - t) < 1e-13;
    t = next;
    if (done) break;
  }
  return (Point(t) - q).squaredNorm() <= best ? t : best_t;
}

double Intersect(const Ray2& ray, const CubicBezier& curve, double t_min, double t_max) {
  const Eigen::Vector2d n(-ray.direction.y(), ray.direction.x());
  double f[4], g[4];
  bool any_pos = false, any_neg = false, any_ahead = false, any_in_front = false;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector2d r = curve.p[i] - ray.origin;
    f[i] = n.dot(r);
    g[i] = ray.direction.dot(r);
    any_pos |= f[i] >= 0.0;
    any_neg |= f[i] <= 0.0;
    any_ahead |= g[i] > t_min;
    any_in_front |= g[i] < t_max;
  }
  // Convex hull property: the curve is on one side of the line, or entirely out of range.
  if (!any_pos || !any_neg || !any_ahead || !any_in_front) return kNoHit;

  // Power basis of the Bernstein coefficients f[].
  const Cubic cubic{-f[0] + 3.0 * f[1] - 3.0 * f[2] + f[3], 3.0 * f[0] - 6.0 * f[1] + 3.0 * f[2],
                    -3.0 * f[0] + 3.0 * f[1], f[0]};

  // Breakpoints: 0, the critical points in (0, 1) in increasing order, 1.
  double breaks[4] = {0.0, 0.0, 0.0, 0.0};
  int num_breaks = 0;
  breaks[num_breaks++] = 0.0;
  {
    const double qa = 3.0 * cubic.a, qb = 2.0 * cubic.b, qc = cubic.c;
    double roots[2];
    int num_roots = 0;
    if (std::abs(qa) < 1e-300) {
      if (qb != 0.0) roots[num_roots++] = -qc / qb;
    } else {
      const double disc = qb * qb - 4.0 * qa * qc;
      if (disc >= 0.0) {
        const double q = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
        roots[num_roots++] = q / qa;
        if (q != 0.0) roots[num_roots++] = qc / q;
      }
    }
    if (num_roots == 2 && roots[0] > roots[1]) std::swap(roots[0], roots[1]);
    for (int i = 0; i < num_roots; ++i) {
      if (roots[i] > 0.0 && roots[i] < 1.0) breaks[num_breaks++] = roots[i];
    }
  }
  breaks[num_breaks++] = 1.0;

  double best = kNoHit;
  auto consider = [&](double u) {
    const double t = ray.direction.dot(curve.Point(u) - ray.origin);
    if (t > t_min && t < t_max && t < best) best = t;
  };
  constexpr double kTouchTolerance = 1e-12;
  for (int k = 0; k + 1 < num_breaks; ++k) {
    const double lo = breaks[k], hi = breaks[k + 1];
    const double f_lo = cubic(lo), f_hi = cubic(hi);
    if (f_lo == 0.0) {
      consider(lo);
    } else if ((f_lo < 0.0) != (f_hi < 0.0) && f_hi != 0.0) {
      consider(MonotoneRoot(cubic, lo, hi, f_lo));
    } else if (k > 0 && std::abs(f_lo) < kTouchTolerance) {
      consider(lo);  // tangent touch at a critical point
    }
  }
  if (cubic(1.0) == 0.0) consider(1.0);
  return best;
}

}  // namespace splam::kernel
