#include "kernel/bspline.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>

namespace splam::kernel {
namespace {

// Gauss-Legendre nodes and weights on [-1, 1], 5 points: exact for polynomials of degree 9.
constexpr double kGaussNodes[5] = {-0.9061798459386640, -0.5384693101056831, 0.0,
                                   0.5384693101056831, 0.9061798459386640};
constexpr double kGaussWeights[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                     0.4786286704993665, 0.2369268850561891};
// Sub-intervals per Bezier piece in the arc-length table.
constexpr int kTableSteps = 16;

// Arc length of a Bezier piece between local parameters a and b.
double PieceLength(const CubicBezier& piece, double a, double b) {
  const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
  double sum = 0.0;
  for (int i = 0; i < 5; ++i)
    sum += kGaussWeights[i] * piece.Derivative(mid + half * kGaussNodes[i]).norm();
  return half * sum;
}

std::vector<CubicBezier> DecomposeToBezier(const std::vector<Eigen::Vector2d>& control_points,
                                           const std::vector<double>& knots) {
  // Algorithm A5.6 of Piegl & Tiller, The NURBS Book: insert every interior knot up to
  // multiplicity 3, collecting one Bezier piece per span.
  constexpr int p = CubicBSpline::kDegree;
  const std::vector<double>& u = knots;
  const int m = static_cast<int>(u.size()) - 1;
  std::vector<CubicBezier> pieces(1);
  for (int i = 0; i <= p; ++i) pieces[0].p[i] = control_points[i];
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
      for (int j = p - mult; j <= p; ++j) next.p[j] = control_points[b - p + j];
      pieces.push_back(next);
      a = b;
      ++b;
    }
  }
  return pieces;
}

}  // namespace

Result<CubicBSpline> CubicBSpline::Create(std::vector<Eigen::Vector2d> control_points,
                                          std::vector<double> knots) {
  using R = Result<CubicBSpline>;
  const std::size_t n = control_points.size();
  if (n < 4) {
    return R::Fail("a cubic B-spline needs at least 4 control points, got " + std::to_string(n));
  }
  if (knots.size() != n + 4) {
    return R::Fail("expected " + std::to_string(n + 4) + " knots, got " +
                   std::to_string(knots.size()));
  }
  for (const Eigen::Vector2d& p : control_points) {
    if (!p.allFinite()) {
      return R::Fail("control point is not finite");
    }
  }
  for (std::size_t i = 0; i < knots.size(); ++i) {
    if (!std::isfinite(knots[i]) || (i > 0 && knots[i] < knots[i - 1])) {
      return R::Fail("knots must be finite and non-decreasing");
    }
  }
  if (knots[0] != knots[3] || knots[n] != knots[n + 3] || knots[3] >= knots[n]) {
    return R::Fail("knot vector must be clamped (end multiplicity 4) with a non-empty domain");
  }
  return R::Ok(CubicBSpline(std::move(control_points), std::move(knots)));
}

Result<CubicBSpline> CubicBSpline::ClampedUniform(std::vector<Eigen::Vector2d> control_points) {
  using R = Result<CubicBSpline>;
  const std::size_t n = control_points.size();
  if (n < 4) {
    return R::Fail("a cubic B-spline needs at least 4 control points, got " + std::to_string(n));
  }
  std::vector<double> knots(n + 4, 0.0);
  const std::size_t spans = n - 3;
  for (std::size_t i = 4; i < n; ++i) {
    knots[i] = static_cast<double>(i - 3) / static_cast<double>(spans);
  }
  std::fill(knots.begin() + static_cast<std::ptrdiff_t>(n), knots.end(), 1.0);
  return Create(std::move(control_points), std::move(knots));
}

void CubicBasis(const std::vector<double>& knots, std::size_t span, double t, double values[4]) {
  // Piegl & Tiller, The NURBS Book, algorithm A2.2.
  double left[4], right[4];
  values[0] = 1.0;
  for (int j = 1; j <= CubicBSpline::kDegree; ++j) {
    left[j] = t - knots[span + 1 - j];
    right[j] = knots[span + j] - t;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      const double denom = right[r + 1] + left[j - r];
      const double temp = denom != 0.0 ? values[r] / denom : 0.0;
      values[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    values[j] = saved;
  }
}

std::size_t CubicBSpline::KnotSpan(double t) const {
  const std::size_t n = control_points_.size();
  const auto it = std::upper_bound(knots_.begin() + kDegree,
                                   knots_.begin() + static_cast<std::ptrdiff_t>(n), t);
  return std::min(static_cast<std::size_t>(it - knots_.begin()) - 1, n - 1);
}

CubicBSpline::Basis CubicBSpline::BasisAt(double t) const {
  t = std::clamp(t, DomainStart(), DomainEnd());
  const std::size_t k = KnotSpan(t);
  Basis basis;
  basis.first = k - kDegree;
  CubicBasis(knots_, k, t, basis.values);
  return basis;
}

Eigen::Vector2d CubicBSpline::PointDeBoor(double t) const {
  t = std::clamp(t, DomainStart(), DomainEnd());
  const std::size_t k = KnotSpan(t);
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

CubicBSpline::CubicBSpline(std::vector<Eigen::Vector2d> control_points, std::vector<double> knots)
    : control_points_(std::move(control_points)),
      knots_(std::move(knots)),
      pieces_(DecomposeToBezier(control_points_, knots_)) {
  for (std::size_t i = kDegree; i <= control_points_.size(); ++i) {
    if (span_starts_.empty() || knots_[i] > span_starts_.back()) span_starts_.push_back(knots_[i]);
  }
  assert(span_starts_.size() == pieces_.size() + 1);
  cumulative_.push_back({0, 0.0, 0.0});
  for (std::size_t k = 0; k < pieces_.size(); ++k) {
    for (int j = 1; j <= kTableSteps; ++j) {
      const double a = static_cast<double>(j - 1) / kTableSteps,
                   b = static_cast<double>(j) / kTableSteps;
      cumulative_.push_back({k, b, cumulative_.back().arc_length + PieceLength(pieces_[k], a, b),
                             pieces_[k].Derivative(a).norm(), pieces_[k].Derivative(b).norm()});
    }
  }
  boxes_.reserve(pieces_.size());
  for (const CubicBezier& piece : pieces_) boxes_.push_back(piece.ControlBounds());
}

std::pair<std::size_t, double> CubicBSpline::Locate(double t) const {
  t = std::clamp(t, DomainStart(), DomainEnd());
  const auto it = std::upper_bound(span_starts_.begin() + 1, span_starts_.end() - 1, t);
  const std::size_t k = static_cast<std::size_t>(it - span_starts_.begin()) - 1;
  return {k, (t - span_starts_[k]) / (span_starts_[k + 1] - span_starts_[k])};
}

Eigen::Vector2d CubicBSpline::Point(double t) const {
  const auto [k, u] = Locate(t);
  return pieces_[k].Point(u);
}

Eigen::Vector2d CubicBSpline::Derivative(double t) const {
  const auto [k, u] = Locate(t);
  return pieces_[k].Derivative(u) / (span_starts_[k + 1] - span_starts_[k]);
}

Eigen::Vector2d CubicBSpline::SecondDerivative(double t) const {
  const auto [k, u] = Locate(t);
  const double h = span_starts_[k + 1] - span_starts_[k];
  return pieces_[k].SecondDerivative(u) / (h * h);
}

double CubicBSpline::ArcLengthAt(double t) const {
  const auto [k, u] = Locate(t);
  const int step = std::min(static_cast<int>(u * kTableSteps), kTableSteps - 1);
  // Entry k * kTableSteps + step is the arc length at u = step / kTableSteps of piece k (for
  // step 0 it is stored as the end of piece k - 1).
  const TableEntry& entry = cumulative_[k * kTableSteps + static_cast<std::size_t>(step)];
  return entry.arc_length + PieceLength(pieces_[k], static_cast<double>(step) / kTableSteps, u);
}

double CubicBSpline::ParameterAtArcLength(double s) const {
  s = std::clamp(s, 0.0, Length());
  // The table step [lo, hi] holding s. Its parameter as a function of the arc length, u(s), has
  // du/ds = 1 / |B'(u)| at both ends: the cubic Hermite interpolant of u(s) is the first guess
  // (error O(h^4) for a step of arc length h), then Newton on the arc length, safeguarded by
  // bisection. Newton's error after a step from an arc-length error f is about kappa f^2 / 2
  // (kappa the curvature), so |f| < kNewtonStop ends the iteration with the step taken.
  constexpr double kNewtonStop = 1e-7;  // m; below 1e-12 m after the step up to kappa = 100 / m
  const auto it =
      std::upper_bound(cumulative_.begin() + 1, cumulative_.end(), s,
                       [](double value, const TableEntry& e) { return value < e.arc_length; });
  if (it == cumulative_.end()) return DomainEnd();
  const TableEntry& hi = *it;
  const TableEntry& lo = *(it - 1);
  const CubicBezier& piece = pieces_[hi.piece];
  const double u_lo = hi.u - 1.0 / kTableSteps;
  double a = u_lo, b = hi.u;
  const double target = s - lo.arc_length;
  const double span = hi.arc_length - lo.arc_length;
  double u = u_lo;
  if (span > 0.0) {
    const double x = target / span, x2 = x * x, x3 = x2 * x;
    const double linear = u_lo + (b - a) * x;  // where a speed is 0 (a cusp)
    const double hermite = hi.speed_lo > 0.0 && hi.speed_hi > 0.0
                               ? (2 * x3 - 3 * x2 + 1) * u_lo +
                                     (x3 - 2 * x2 + x) * span / hi.speed_lo +
                                     (-2 * x3 + 3 * x2) * b + (x3 - x2) * span / hi.speed_hi
                               : linear;
    u = hermite >= a && hermite <= b ? hermite : linear;
  }
  for (int it2 = 0; it2 < 30; ++it2) {
    const double f = PieceLength(piece, u_lo, u) - target;
    if (std::abs(f) < 1e-13) break;
    if (f > 0.0)
      b = u;
    else
      a = u;
    const double df = piece.Derivative(u).norm();
    double next = df > 0.0 ? u - f / df : 0.5 * (a + b);
    const bool newton = next > a && next < b;
    if (!newton) next = 0.5 * (a + b);
    if (std::abs(next - u) < 1e-15) break;
    u = next;
    if (newton && std::abs(f) < kNewtonStop) break;
  }
  return span_starts_[hi.piece] + u * (span_starts_[hi.piece + 1] - span_starts_[hi.piece]);
}

std::vector<Eigen::Vector2d> CubicBSpline::ResampleByArcLength(double epsilon_m) const {
  assert(epsilon_m > 0.0);
  const double length = Length();
  if (!(length / epsilon_m <= kMaxSamples)) return {};
  const std::size_t n = static_cast<std::size_t>(std::floor(length / epsilon_m + 1e-9)) + 1;
  std::vector<Eigen::Vector2d> points;
  points.reserve(n);
  for (std::size_t i = 0; i < n; ++i)
    points.push_back(Point(ParameterAtArcLength(static_cast<double>(i) * epsilon_m)));
  return points;
}

CubicBSpline::ClosestPoint CubicBSpline::Closest(const Eigen::Vector2d& q) const {
  // Squared distance from q to piece k's box: a lower bound of its distance to the piece.
  auto box_distance2 = [&](std::size_t k) {
    const Eigen::Vector2d d =
        (boxes_[k].min - q).cwiseMax(q - boxes_[k].max).cwiseMax(Eigen::Vector2d::Zero());
    return d.squaredNorm();
  };
  // Start from the piece with the nearest box, so that the bound prunes from the first test.
  std::size_t first = 0;
  double nearest = kNoHit;
  for (std::size_t k = 0; k < pieces_.size(); ++k) {
    const double d2 = box_distance2(k);
    if (d2 < nearest) {
      nearest = d2;
      first = k;
    }
  }
  ClosestPoint best;
  best.distance = kNoHit;
  for (std::size_t i = 0; i < pieces_.size(); ++i) {
    const std::size_t k = i == 0 ? first : (i <= first ? i - 1 : i);
    if (i > 0 && box_distance2(k) > best.distance * best.distance) continue;
    const double u = pieces_[k].ClosestParameter(q);
    const Eigen::Vector2d p = pieces_[k].Point(u);
    const double d = (p - q).norm();
    if (d < best.distance) {
      best = {span_starts_[k] + u * (span_starts_[k + 1] - span_starts_[k]), p, d};
    }
  }
  return best;
}

CubicBSpline CubicBSpline::Transformed(const Pose2& a_T_b) const {
  return CubicBSpline(a_T_b * control_points_, knots_);
}

double Intersect(const Ray2& ray, const CubicBSpline& curve, double t_min, double t_max) {
  double best = kNoHit;
  for (const CubicBezier& piece : curve.pieces())
    best = std::min(best, Intersect(ray, piece, t_min, std::min(t_max, best)));
  return best;
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
