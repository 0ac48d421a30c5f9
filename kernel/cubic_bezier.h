#ifndef SPLAM_KERNEL_CUBIC_BEZIER_H_
#define SPLAM_KERNEL_CUBIC_BEZIER_H_

#include <Eigen/Core>
#include <array>
#include <utility>

#include "kernel/shapes.h"

namespace splam::kernel {

// B(t) = sum_i C(3,i) (1-t)^(3-i) t^i P_i for t in [0, 1]; the curve lies in the convex hull of
// its four control points. Every piece of a cubic B-spline is one of these.
struct CubicBezier {
  std::array<Eigen::Vector2d, 4> p;

  Eigen::Vector2d Point(double t) const;
  Eigen::Vector2d Derivative(double t) const;
  Eigen::Vector2d SecondDerivative(double t) const;
  // Bounds of the control points (contain the curve).
  Box2 ControlBounds() const;
  // de Casteljau split at t: the pieces over [0, t] and [t, 1].
  std::pair<CubicBezier, CubicBezier> Split(double t) const;
  // The parameter of the point of the curve closest to q: a scan of 33 samples, then Newton
  // steps on B'(t) . (B(t) - q) = 0; the distance is accurate to 1e-9 m.
  double ClosestParameter(const Eigen::Vector2d& q) const;
  double Distance(const Eigen::Vector2d& q) const {
    return (Point(ClosestParameter(q)) - q).norm();
  }
};

// Smallest ray parameter in (t_min, t_max) where the ray meets the curve, or kNoHit.
// Method: the signed distance f(u) = n . (B(u) - origin) of the curve to the ray's line (n the
// line's normal) is a cubic in u. Its critical points split [0, 1] into monotone pieces; each
// piece with a sign change holds exactly one root, found by Newton steps safeguarded by
// bisection to 1e-14 in u, so no crossing is missed or reported twice. A touching root (double
// root without a sign change) counts when |f| there is below 1e-12 m. Curves whose control
// points all lie on one side of the line are rejected before any root finding.
double Intersect(const Ray2& ray, const CubicBezier& curve, double t_min, double t_max);

}  // namespace splam::kernel

#endif  // SPLAM_KERNEL_CUBIC_BEZIER_H_
