#ifndef SPLAM_KERNEL_BSPLINE_H_
#define SPLAM_KERNEL_BSPLINE_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "kernel/cubic_bezier.h"
#include "kernel/pose2.h"
#include "kernel/shapes.h"
#include "kernel/status.h"

namespace splam::kernel {

// A cubic B-spline C(t) = sum_i X_i N_{i,3}(t) with a clamped knot vector (the first and last
// knots have multiplicity 4, so the curve starts at X_0 and ends at X_n), over the domain
// [knots[3], knots[n + 1]]. The curve is also held as its Bezier pieces (one per non-empty knot
// span), through which it is evaluated, measured and intersected.
class CubicBSpline {
 public:
  static constexpr int kDegree = 3;

  // Validates: at least 4 control points, knots.size() == control_points.size() + 4,
  // non-decreasing, clamped, finite; else fails saying which.
  static Result<CubicBSpline> Create(std::vector<Eigen::Vector2d> control_points,
                                     std::vector<double> knots);
  // Clamped uniform knots on [0, 1]: 0,0,0,0, 1/(n-2), ..., 1,1,1,1. Needs >= 4 points.
  static Result<CubicBSpline> ClampedUniform(std::vector<Eigen::Vector2d> control_points);

  const std::vector<Eigen::Vector2d>& control_points() const { return control_points_; }
  const std::vector<double>& knots() const { return knots_; }
  double DomainStart() const { return knots_[kDegree]; }
  double DomainEnd() const { return knots_[control_points_.size()]; }
  // The Bezier pieces in order; piece k spans [span_starts()[k], span_starts()[k + 1]].
  const std::vector<CubicBezier>& pieces() const { return pieces_; }
  const std::vector<double>& span_starts() const { return span_starts_; }

  // C(t), C'(t) and C''(t) with respect to t; t is clamped to the domain.
  Eigen::Vector2d Point(double t) const;
  Eigen::Vector2d Derivative(double t) const;
  Eigen::Vector2d SecondDerivative(double t) const;
  // The basis functions that are non-zero at t: N_{first+k,3}(t) for k = 0..3 (they sum to 1),
  // so that C(t) = sum_k values[k] X_{first+k}. t is clamped to the domain.
  struct Basis {
    std::size_t first = 0;
    double values[4] = {0.0, 0.0, 0.0, 0.0};
  };
  Basis BasisAt(double t) const;
  // C(t) by de Boor's algorithm: the reference the pieces are tested against.
  Eigen::Vector2d PointDeBoor(double t) const;

  // Arc length of the whole curve and from the domain start to t (Gauss-Legendre quadrature;
  // relative error below 1e-9 for pieces that are not degenerate).
  double Length() const { return cumulative_.back().arc_length; }
  double ArcLengthAt(double t) const;
  // The parameter at arc length s from the start (s clamped to [0, Length()]).
  double ParameterAtArcLength(double s) const;
  // Points at arc lengths 0, epsilon, 2 epsilon, ... up to Length() (the last point is the
  // curve's end only when Length() is a multiple of epsilon). epsilon > 0. Empty when the length
  // is not finite or would need more than kMaxSamples points: no allocation is sized by a
  // diverged curve.
  static constexpr double kMaxSamples = 1e7;
  std::vector<Eigen::Vector2d> ResampleByArcLength(double epsilon_m) const;

  struct ClosestPoint {
    double t = 0.0;
    Eigen::Vector2d point = Eigen::Vector2d::Zero();
    double distance = 0.0;
  };
  // The point of the curve closest to q (the best over all pieces). A piece lies inside the box
  // of its Bezier control points (convex hull property), so a piece whose box is farther from q
  // than the best point found so far is skipped: the cost grows with the pieces near q, not with
  // the curve's length (up to one box test per piece).
  ClosestPoint Closest(const Eigen::Vector2d& q) const;

  // The curve moved rigidly: a_T_b applied to a curve given in frame b. B-splines are affine
  // invariant, so this transforms the control points.
  CubicBSpline Transformed(const Pose2& a_T_b) const;

 private:
  CubicBSpline(std::vector<Eigen::Vector2d> control_points, std::vector<double> knots);
  // The knot span k with knots[k] <= t < knots[k+1], k in [3, n-1] (the last non-empty span at
  // the domain's end); t within the domain.
  std::size_t KnotSpan(double t) const;
  // Piece index and local parameter u in [0, 1] of t.
  std::pair<std::size_t, double> Locate(double t) const;

  // Arc-length table: at sub-interval boundaries of every piece, the piece, its local parameter
  // and the arc length from the curve's start.
  // Arc length at parameter u of `piece`, and the speed |dB/du| of the piece at both ends of the
  // table step that ends here (u - 1/kTableSteps and u).
  struct TableEntry {
    std::size_t piece;
    double u;
    double arc_length;
    double speed_lo = 0.0, speed_hi = 0.0;
  };

  std::vector<Eigen::Vector2d> control_points_;
  std::vector<double> knots_;
  std::vector<CubicBezier> pieces_;
  std::vector<double> span_starts_;
  std::vector<TableEntry> cumulative_;
  std::vector<Box2> boxes_;  // per piece, the box of its Bezier control points
};

// The four cubic basis functions N_{span-3..span,3}(t) that can be non-zero on the knot span
// [knots[span], knots[span+1]) (Piegl & Tiller A2.2).
void CubicBasis(const std::vector<double>& knots, std::size_t span, double t, double values[4]);

// Smallest ray parameter in (t_min, t_max) where the ray meets the curve, or kNoHit: the
// nearest hit over the Bezier pieces (see the CubicBezier overload: no crossing is missed, and
// a hit at the joint of two pieces is one hit).
double Intersect(const Ray2& ray, const CubicBSpline& curve, double t_min, double t_max);

// A closed uniform cubic B-spline over the control polygon X_0 .. X_{n-1} (wrapping around;
// n >= 3) as n Bezier pieces; piece i is the span of X_i .. X_{i+3 mod n}. The curve is C2 and
// closed, and does not pass through its control points.
std::vector<CubicBezier> ClosedUniformBSplineToBezier(const std::vector<Eigen::Vector2d>& control);

}  // namespace splam::kernel

#endif  // SPLAM_KERNEL_BSPLINE_H_
