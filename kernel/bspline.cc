#include "kernel/bspline.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>

namespace splam::kernel {
namespace {

void SetError(std::string* error, std::string message) {
  if (error != nullptr) *error = std::move(message);
}

}  // namespace

std::optional<CubicBSpline> CubicBSpline::Create(std::vector<Eigen::Vector2d> control_points,
                                                 std::vector<double> knots, std::string* error) {
  const std::size_t n = control_points.size();
  if (n < 4) {
    SetError(error, "a cubic B-spline needs at least 4 control points, got " + std::to_string(n));
    return std::nullopt;
  }
  if (knots.size() != n + 4) {
    SetError(error,
             "expected " + std::to_string(n + 4) + " knots, got " + std::to_string(knots.size()));
    return std::nullopt;
  }
  for (const Eigen::Vector2d& p : control_points) {
    if (!p.allFinite()) {
      SetError(error, "control point is not finite");
      return std::nullopt;
    }
  }
  for (std::size_t i = 0; i < knots.size(); ++i) {
    if (!std::isfinite(knots[i]) || (i > 0 && knots[i] < knots[i - 1])) {
      SetError(error, "knots must be finite and non-decreasing");
      return std::nullopt;
    }
  }
  if (knots[0] != knots[3] || knots[n] != knots[n + 3] || knots[3] >= knots[n]) {
    SetError(error, "knot vector must be clamped (end multiplicity 4) with a non-empty domain");
    return std::nullopt;
  }
  return CubicBSpline(std::move(control_points), std::move(knots));
}

std::optional<CubicBSpline> CubicBSpline::ClampedUniform(
    std::vector<Eigen::Vector2d> control_points, std::string* error) {
  const std::size_t n = control_points.size();
  if (n < 4) {
    SetError(error, "a cubic B-spline needs at least 4 control points, got " + std::to_string(n));
    return std::nullopt;
  }
  std::vector<double> knots(n + 4, 0.0);
  const std::size_t spans = n - 3;
  for (std::size_t i = 4; i < n; ++i) {
    knots[i] = static_cast<double>(i - 3) / static_cast<double>(spans);
  }
  std::fill(knots.begin() + static_cast<std::ptrdiff_t>(n), knots.end(), 1.0);
  return Create(std::move(control_points), std::move(knots), error);
}

Eigen::Vector2d CubicBSpline::Point(double t) const {
  t = std::clamp(t, DomainStart(), DomainEnd());
  // Span k with knots[k] <= t < knots[k+1], k in [3, n-1].
  const std::size_t n = control_points_.size();
  std::size_t k = static_cast<std::size_t>(
      std::upper_bound(knots_.begin() + kDegree, knots_.begin() + static_cast<std::ptrdiff_t>(n),
                       t) -
      knots_.begin() - 1);
  k = std::min(k, n - 1);
  std::array<Eigen::Vector2d, 4> d;
  for (int j = 0; j <= kDegree; ++j) d[j] = control_points_[k - kDegree + j];
  for (int r = 1; r <= kDegree; ++r) {
    for (int j = kDegree; j >= r; --j) {
      const std::size_t i = k - kDegree + j;
      const double denom = knots_[i + kDegree + 1 - r] - knots_[i];
      const double alpha = denom > 0.0 ? (t - knots_[i]) / denom : 0.0;
      d[j] = (1.0 - alpha) * d[j - 1] + alpha * d[j];
    }
  }
  return d[kDegree];
}

std::vector<CubicBezier> CubicBSpline::ToBezier() const {
  // Algorithm A5.6 of Piegl & Tiller, The NURBS Book: insert every interior knot up to
  // multiplicity 3, collecting one Bezier piece per span.
  constexpr int p = kDegree;
  const std::vector<double>& u = knots_;
  const int m = static_cast<int>(u.size()) - 1;
  std::vector<CubicBezier> pieces(1);
  for (int i = 0; i <= p; ++i) pieces[0].p[i] = control_points_[i];
  int a = p, b = p + 1;
  std::array<double, p> alphas{};
  while (b < m) {
    const int i = b;
    while (b < m && u[b + 1] == u[b]) ++b;
    const int mult = b - i + 1;
    CubicBezier next;
    if (mult < p) {
      const double numer = u[b] - u[a];
      for (int j = p; j > mult; --j) alphas[j - mult - 1] = numer / (u[a + j] - u[a]);
      const int r = p - mult;
      for (int j = 1; j <= r; ++j) {
        const int save = r - j, s = mult + j;
        CubicBezier& q = pieces.back();
        for (int k = p; k >= s; --k) {
          const double alpha = alphas[k - s];
          q.p[k] = alpha * q.p[k] + (1.0 - alpha) * q.p[k - 1];
        }
        if (b < m) next.p[save] = q.p[p];
      }
    }
    if (b < m) {
      for (int j = p - mult; j <= p; ++j) next.p[j] = control_points_[b - p + j];
      pieces.push_back(next);
      a = b;
      ++b;
    }
  }
  return pieces;
}

std::vector<CubicBezier> ClosedUniformBSplineToBezier(const std::vector<Eigen::Vector2d>& control) {
  const std::size_t n = control.size();
  assert(n >= 3);
  std::vector<CubicBezier> pieces;
  pieces.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& p0 = control[i];
    const Eigen::Vector2d& p1 = control[(i + 1) % n];
    const Eigen::Vector2d& p2 = control[(i + 2) % n];
    const Eigen::Vector2d& p3 = control[(i + 3) % n];
    pieces.push_back(CubicBezier{{(p0 + 4.0 * p1 + p2) / 6.0, (2.0 * p1 + p2) / 3.0,
                                  (p1 + 2.0 * p2) / 3.0, (p1 + 4.0 * p2 + p3) / 6.0}});
  }
  return pieces;
}

}  // namespace splam::kernel
