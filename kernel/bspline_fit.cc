#include "kernel/bspline_fit.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "kernel/shapes.h"

namespace splam::kernel {

Status BSplineFitOptions::Validate() const {
  if (!(control_point_spacing_m > 0.0))
    return Status::Error("control_point_spacing_m must be positive");
  if (min_control_points < 4) return Status::Error("min_control_points must be at least 4");
  if (max_control_points < min_control_points || max_control_points > 10000)
    return Status::Error("max_control_points must be in [min_control_points, 10000]");
  if (!(max_length_ratio >= 1.0)) return Status::Error("max_length_ratio must be at least 1");
  if (!(points_per_control_point >= 1.0))
    return Status::Error("points_per_control_point must be at least 1");
  if (parameter_smoothing_half_window < 0 || parameter_smoothing_half_window > 1000)
    return Status::Error("parameter_smoothing_half_window must be in [0, 1000]");
  return Status::Ok();
}

namespace {

// Chord-length parameters t_k and knots of the fit; fails for degenerate points.
Status FitParametersAndKnots(const std::vector<Eigen::Vector2d>& points,
                             const BSplineFitOptions& options, std::vector<double>* t_out,
                             std::vector<double>* knots_out) {
  const std::size_t m = points.size();
  if (m < 4) {
    return Status::Error("a cubic B-spline fit needs at least 4 points, got " + std::to_string(m));
  }
  for (const Eigen::Vector2d& p : points) {
    if (!p.allFinite()) {
      return Status::Error("point is not finite");
    }
  }
  // Chord-length parameters along a moving average of the points: on noisy data the raw chords
  // zig-zag, so their length overstates the progress along the curve and the fit follows the
  // noise. The fit itself uses the raw points.
  const std::size_t half =
      static_cast<std::size_t>(std::max(options.parameter_smoothing_half_window, 0));
  std::vector<Eigen::Vector2d> smoothed(m);
  for (std::size_t k = 0; k < m; ++k) {
    const std::size_t h = std::min({half, k, m - 1 - k});  // symmetric, shrinking at the ends
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    for (std::size_t j = k - h; j <= k + h; ++j) sum += points[j];
    smoothed[k] = sum / static_cast<double>(2 * h + 1);
  }
  std::vector<double> t(m, 0.0);
  for (std::size_t k = 1; k < m; ++k) t[k] = t[k - 1] + (smoothed[k] - smoothed[k - 1]).norm();
  const double length = t.back();
  std::size_t distinct = 1;
  for (std::size_t k = 1; k < m; ++k) distinct += t[k] > t[k - 1];
  if (!(length > 0.0) || distinct < 4) {
    return Status::Error("the points are not spread along a curve (fewer than 4 distinct points)");
  }
  for (double& v : t) v /= length;

  int wanted = static_cast<int>(std::lround(length / options.control_point_spacing_m)) + 1;
  wanted = std::clamp(wanted, options.min_control_points, options.max_control_points);
  // At most one control point per points_per_control_point distinct points: with as many control
  // points as points the least squares interpolates, and on sparse points (a far wall at 1 deg
  // steps) the curve rings between them, hundreds of metres long for a 14 m wall.
  const std::size_t by_points = static_cast<std::size_t>(
      std::floor(static_cast<double>(distinct) / options.points_per_control_point));
  const std::size_t n = std::max<std::size_t>(
      4, std::min({static_cast<std::size_t>(wanted), distinct, by_points}));  // control points

  // Knots by averaging (Piegl & Tiller eq. 9.69): every span contains parameters.
  std::vector<double> knots(n + 4, 0.0);
  const double d = static_cast<double>(m) / static_cast<double>(n - 3);
  for (std::size_t j = 1; j + 3 < n; ++j) {
    const double jd = static_cast<double>(j) * d;
    const std::size_t i = static_cast<std::size_t>(jd);
    const double alpha = jd - static_cast<double>(i);
    knots[j + 3] = (1.0 - alpha) * t[i - 1] + alpha * t[std::min(i, m - 1)];
  }
  std::fill(knots.begin() + static_cast<std::ptrdiff_t>(n), knots.end(), 1.0);
  // Averaging can repeat a knot when parameters repeat; keep the vector strictly increasing
  // inside so that no span is empty.
  for (std::size_t j = 4; j < n; ++j) {
    if (knots[j] <= knots[j - 1]) knots[j] = std::nextafter(knots[j - 1], 2.0);
  }
  if (n > 4 && knots[n - 1] >= 1.0) {
    return Status::Error("cannot place knots for these points");
  }
  *t_out = std::move(t);
  *knots_out = std::move(knots);
  return Status::Ok();
}

// The normal matrix N^T N of the fit and the basis rows: row k of N is nonzero in columns
// first[k] .. first[k] + 3 with values basis[k].
struct NormalEquations {
  Eigen::MatrixXd ntn;
  std::vector<Eigen::Index> first;
  std::vector<Eigen::Vector4d> basis;
};
NormalEquations BuildNormalEquations(const std::vector<double>& t,
                                     const std::vector<double>& knots) {
  const std::size_t n = knots.size() - 4;
  NormalEquations e;
  e.ntn = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  e.first.reserve(t.size());
  e.basis.reserve(t.size());
  std::size_t span = 3;
  for (const double tk : t) {
    while (span + 1 < n && tk >= knots[span + 1]) ++span;
    Eigen::Vector4d basis;
    CubicBasis(knots, span, tk, basis.data());
    const Eigen::Index first = static_cast<Eigen::Index>(span - 3);
    e.ntn.block<4, 4>(first, first) += basis * basis.transpose();
    e.first.push_back(first);
    e.basis.push_back(basis);
  }
  return e;
}

}  // namespace

Result<CubicBSpline> FitCubicBSpline(const std::vector<Eigen::Vector2d>& points,
                                     const BSplineFitOptions& options) {
  using R = Result<CubicBSpline>;
  std::vector<double> t, knots;
  if (Status bad = FitParametersAndKnots(points, options, &t, &knots); !bad.ok())
    return R::Fail(bad);
  // Normal equations N^T N X = N^T D for all control points. The ends are not pinned to the
  // first and last measurement: a noisy end point would bend the end of the curve into a hook.
  const NormalEquations e = BuildNormalEquations(t, knots);
  Eigen::MatrixXd ntd = Eigen::MatrixXd::Zero(e.ntn.rows(), 2);
  for (std::size_t k = 0; k < points.size(); ++k)
    ntd.middleRows<4>(e.first[k]) += e.basis[k] * points[k].transpose();
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(e.ntn);
  const Eigen::MatrixXd x = ldlt.solve(ntd);
  if (ldlt.info() != Eigen::Success || !x.allFinite()) {
    return R::Fail("the least-squares system is singular");
  }
  std::vector<Eigen::Vector2d> control(static_cast<std::size_t>(x.rows()));
  for (Eigen::Index i = 0; i < x.rows(); ++i) control[static_cast<std::size_t>(i)] = x.row(i);
  R spline = CubicBSpline::Create(std::move(control), std::move(knots));
  // A curve longer than max_length_ratio times the points' polyline (which noise only lengthens)
  // rings between them: refused, so that no later step samples a curve of kilometres.
  const double polyline = PolylineLength(points);
  if (spline && spline->Length() > options.max_length_ratio * polyline) {
    return R::Fail("the fitted curve is " + std::to_string(spline->Length() / polyline) +
                   " times as long as its points' polyline");
  }
  return spline;
}

Result<BSplineFitOperator> CubicBSplineFitOperator(const std::vector<Eigen::Vector2d>& points,
                                                   const BSplineFitOptions& options) {
  using R = Result<BSplineFitOperator>;
  std::vector<double> t, knots;
  if (Status bad = FitParametersAndKnots(points, options, &t, &knots); !bad.ok())
    return R::Fail(bad);
  const NormalEquations e = BuildNormalEquations(t, knots);
  Eigen::MatrixXd nt = Eigen::MatrixXd::Zero(e.ntn.rows(), static_cast<Eigen::Index>(t.size()));
  for (std::size_t k = 0; k < t.size(); ++k)
    nt.col(static_cast<Eigen::Index>(k)).segment<4>(e.first[k]) = e.basis[k];
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(e.ntn);
  BSplineFitOperator op{std::move(knots), ldlt.solve(nt)};
  if (ldlt.info() != Eigen::Success || !op.m.allFinite()) {
    return R::Fail("the least-squares system is singular");
  }
  return R::Ok(std::move(op));
}

void BSplineFitOptions::VisitFields(FieldVisitor& v) {
  v.Field("control_point_spacing_m", &control_point_spacing_m,
          "one control point per this much chord length, m");
  v.Field("min_control_points", &min_control_points, "at least this many control points (>= 4)");
  v.Field("max_control_points", &max_control_points, "at most this many control points");
  v.Field("points_per_control_point", &points_per_control_point,
          "at least this many distinct points per control point (at least 4 control points)");
  v.Field("max_length_ratio", &max_length_ratio,
          "fits longer than this times their points' polyline are refused (they ring)");
  v.Field("parameter_smoothing_half_window", &parameter_smoothing_half_window,
          "chord-length parameters along a moving average of 2 h + 1 points (0: raw points)");
}

}  // namespace splam::kernel
