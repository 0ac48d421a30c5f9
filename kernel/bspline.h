#ifndef SPLAM_KERNEL_BSPLINE_H_
#define SPLAM_KERNEL_BSPLINE_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "kernel/cubic_bezier.h"

namespace splam::kernel {

// A cubic B-spline C(t) = sum_i X_i N_{i,3}(t) with a clamped knot vector (the first and last
// knots have multiplicity 4, so the curve starts at X_0 and ends at X_n), over the domain
// [knots[3], knots[n + 1]].
class CubicBSpline {
 public:
  static constexpr int kDegree = 3;

  // Validates: at least 4 control points, knots.size() == control_points.size() + 4,
  // non-decreasing, clamped, finite. Returns nullopt and sets *error otherwise.
  static std::optional<CubicBSpline> Create(std::vector<Eigen::Vector2d> control_points,
                                            std::vector<double> knots,
                                            std::string* error = nullptr);
  // Clamped uniform knots on [0, 1]: 0,0,0,0, 1/(n-2), ..., 1,1,1,1. Needs >= 4 points.
  static std::optional<CubicBSpline> ClampedUniform(std::vector<Eigen::Vector2d> control_points,
                                                    std::string* error = nullptr);

  const std::vector<Eigen::Vector2d>& control_points() const { return control_points_; }
  const std::vector<double>& knots() const { return knots_; }
  double DomainStart() const { return knots_[kDegree]; }
  double DomainEnd() const { return knots_[control_points_.size()]; }

  // de Boor's algorithm; t is clamped to the domain.
  Eigen::Vector2d Point(double t) const;
  // The curve as Bezier pieces, one per non-empty knot span (Boehm knot insertion).
  std::vector<CubicBezier> ToBezier() const;

 private:
  CubicBSpline(std::vector<Eigen::Vector2d> control_points, std::vector<double> knots)
      : control_points_(std::move(control_points)), knots_(std::move(knots)) {}

  std::vector<Eigen::Vector2d> control_points_;
  std::vector<double> knots_;
};

// A closed uniform cubic B-spline over the control polygon X_0 .. X_{n-1} (wrapping around;
// n >= 3) as n Bezier pieces; piece i is the span of X_i .. X_{i+3 mod n}. The curve is C2 and
// closed, and does not pass through its control points.
std::vector<CubicBezier> ClosedUniformBSplineToBezier(const std::vector<Eigen::Vector2d>& control);

}  // namespace splam::kernel

#endif  // SPLAM_KERNEL_BSPLINE_H_
