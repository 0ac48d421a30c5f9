#include "estimation/topological/topological_slam.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/LU>

#include "kernel/angle.h"

namespace splam::estimation {

using kernel::CubicBSpline;
using kernel::Pose2;
using kernel::SplineCurve;

namespace {

Eigen::Vector2d PointAt(const SplineCurve& c, double s) {
  return c.spline.Point(c.spline.ParameterAtArcLength(s));
}

// Arc length of every control point's Greville abscissa (t_{i+1} + t_{i+2} + t_{i+3}) / 3: the
// place along the curve that the control point shapes most.
std::vector<double> ControlPointArcs(const CubicBSpline& spline) {
  const std::vector<double>& t = spline.knots();
  std::vector<double> arcs(spline.control_points().size());
  for (std::size_t i = 0; i < arcs.size(); ++i)
    arcs[i] = spline.ArcLengthAt((t[i + 1] + t[i + 2] + t[i + 3]) / 3.0);
  return arcs;
}

// The map curve without its first `drop_front` and last `drop_back` control points, with `head`
// control points put before and `tail` after (paper 003 Fig. 16). The knot vector is extended,
// not rebuilt: the kept interior knots stay, the clamped ends move outward by one knot step h
// (the mean interior knot spacing) per new control point, so the kept curve keeps its shape
// except in the three spans next to a junction. Needs n - drop_front - drop_back >= 4.
std::optional<CubicBSpline> Spliced(const CubicBSpline& map, std::size_t drop_front,
                                    std::size_t drop_back, const std::vector<Eigen::Vector2d>& head,
                                    const std::vector<Eigen::Vector2d>& tail) {
  const std::vector<double>& old = map.knots();
  const std::vector<Eigen::Vector2d>& kept = map.control_points();
  const std::size_t n = kept.size();
  if (n < drop_front + drop_back + 4) return std::nullopt;
  const double h = (old.back() - old.front()) / static_cast<double>(n - 3);  // n - 3 spans
  // Knots 0..3 and n..n+3 are the clamped ends; dropping control points moves them inward.
  const double a = old[3 + drop_front], b = old[n - drop_back];
  std::vector<double> knots;
  const auto front = static_cast<double>(head.size()), back = static_cast<double>(tail.size());
  knots.insert(knots.end(), 4, a - front * h);
  for (std::size_t k = head.size(); k >= 1; --k)
    knots.push_back(a - static_cast<double>(k - 1) * h);
  knots.insert(knots.end(), old.begin() + 4 + static_cast<std::ptrdiff_t>(drop_front),
               old.end() - 4 - static_cast<std::ptrdiff_t>(drop_back));
  for (std::size_t k = 0; k < tail.size(); ++k) knots.push_back(b + static_cast<double>(k) * h);
  knots.insert(knots.end(), 4, b + back * h);
  std::vector<Eigen::Vector2d> points = head;
  points.insert(points.end(), kept.begin() + static_cast<std::ptrdiff_t>(drop_front),
                kept.end() - static_cast<std::ptrdiff_t>(drop_back));
  points.insert(points.end(), tail.begin(), tail.end());
  return CubicBSpline::Create(std::move(points), std::move(knots)).value;
}

// The parts of an observed curve (world frame) that continue a map curve beyond the matched
// stretch (paper 003 Fig. 16), as control points in the map curve's direction: `head` goes before
// the map curve's first control point, `tail` after its last. The map curve's control points
// within end_trim_m of a continued end are dropped (drop_front, drop_back): the last span of a
// fitted curve bends with the noise of its last few points, and kept, that bend stays in the
// map as a kink. The observation continues from where the kept map curve ends.
struct Continuation {
  std::vector<Eigen::Vector2d> head, tail;
  std::size_t drop_front = 0, drop_back = 0;
};
Continuation ContinuationOf(const CubicBSpline& map, const CubicBSpline& observed,
                            const CurveMatch& match, const TopologicalSlamOptions& options) {
  Continuation c;
  const double lm = map.Length(), lo = observed.Length();
  const bool forward = match.map.end_m >= match.map.start_m;
  std::vector<Eigen::Vector2d> points = observed.control_points();
  std::vector<double> arcs = ControlPointArcs(observed);
  double s0 = match.observed.start_m, s1 = match.observed.end_m;
  if (!forward) {  // run the observation the way the map runs
    std::reverse(points.begin(), points.end());
    std::reverse(arcs.begin(), arcs.end());
    for (double& a : arcs) a = lo - a;
    std::tie(s0, s1) = std::pair{lo - s1, lo - s0};
  }
  const double map_lo = std::min(match.map.start_m, match.map.end_m);
  const double map_hi = std::max(match.map.start_m, match.map.end_m);
  const std::vector<double> map_arcs = ControlPointArcs(map);
  const std::size_t n = map_arcs.size();
  // Control points closer than half their spacing to the junction would fold the curve there.
  const double gap = 0.5 * lo / static_cast<double>(points.size() - 1);
  if (map_hi >= lm - options.end_tolerance_m && lo - s1 >= options.min_extension_length_m) {
    while (c.drop_back + 5 < n && map_arcs[n - 1 - c.drop_back] > lm - options.end_trim_m)
      ++c.drop_back;
    // The observed arc length where the kept map curve ends.
    const double junction = s1 - (map_hi - map_arcs[n - 1 - c.drop_back]);
    for (std::size_t i = 0; i < points.size(); ++i)
      if (arcs[i] > junction + gap) c.tail.push_back(points[i]);
    if (c.tail.empty()) c.drop_back = 0;
  }
  if (map_lo <= options.end_tolerance_m && s0 >= options.min_extension_length_m) {
    while (c.drop_front + c.drop_back + 5 < n && map_arcs[c.drop_front] < options.end_trim_m)
      ++c.drop_front;
    const double junction = s0 + (map_arcs[c.drop_front] - map_lo);
    for (std::size_t i = 0; i < points.size(); ++i)
      if (arcs[i] < junction - gap) c.head.push_back(points[i]);
    if (c.head.empty()) c.drop_front = 0;
  }
  return c;
}

}  // namespace

struct TopologicalSlam::Association {
  int observed = 0;  // index into the scan's curves
  int map = 0;       // index into curves_
  CurveMatch match;
  double reliability = 1.0;  // C_i
};

bool TopologicalSlam::RegionShape::Near(const Eigen::Vector2d& p, double margin_m) const {
  const Eigen::Vector2d d = p - center;
  const double r = d.norm();
  if (r <= margin_m) return true;
  if (r > radius_m + margin_m || bearings_rad.empty()) return false;
  const double b = std::atan2(d.y(), d.x());
  const auto it = std::lower_bound(bearings_rad.begin(), bearings_rad.end(), b);
  std::size_t hi = static_cast<std::size_t>(it - bearings_rad.begin());
  std::size_t lo = hi == 0 ? bearings_rad.size() - 1 : hi - 1;
  if (hi == bearings_rad.size()) hi = 0;
  // Outside the field of view of a partial region only the margin around the sensor counts.
  if (!full_circle && (b < bearings_rad.front() || b > bearings_rad.back())) return false;
  return r <= std::max(ranges_m[lo], ranges_m[hi]) + margin_m;
}

TopologicalSlam::TopologicalSlam(const Pose2& initial_pose, const TopologicalSlamOptions& options)
    : options_(options),
      health_(options.Validate()),
      association_(options.association),
      pose_(initial_pose) {
  if (healthy() && options_.prediction == TopologicalPrediction::kScanMatching)
    scan_matcher_ = std::make_unique<GraphSlam>(initial_pose, options_.scan_matching);
}

void TopologicalSlam::Predict(const Pose2& odometry_increment) {
  if (!healthy()) return;
  MotionJacobians j;
  pose_ = MotionModel(pose_, odometry_increment, &j);
  const Eigen::Matrix3d q =
      j.f_u * options_.odometry.Covariance(odometry_increment) * j.f_u.transpose();
  covariance_ = j.f_x * covariance_ * j.f_x.transpose() + q;
  if (!scan_matcher_) return;
  const double s2 = options_.scan_matching_noise_scale * options_.scan_matching_noise_scale;
  scan_matched_covariance_ = j.f_x * scan_matched_covariance_ * j.f_x.transpose() + s2 * q;
  scan_matcher_->Predict(odometry_increment);
  // PredictByScanMatching's increment; with the feedback the front end's pose is this SLAM's.
  if (!options_.scan_matching_feedback) since_update_ = since_update_ * odometry_increment;
}

void TopologicalSlam::PredictByScanMatching(const kernel::Scan& scan, const Pose2& robot_T_laser,
                                            TopologicalUpdateReport* report) {
  // The front end's pose moves by the same odometry; its registration then corrects it. The
  // prediction is the last update's pose times the front end's increment since then.
  const Pose2 front_before = scan_matcher_->pose() * since_update_.Inverse();
  const Pose2 before = pose_ * since_update_.Inverse();
  scan_matcher_->Update(scan, robot_T_laser);
  since_update_ = Pose2();
  report->scan_matched = scan_matcher_->registered();
  if (!report->scan_matched) return;  // the odometry's prediction and covariance stand
  pose_ = before * front_before.Between(scan_matcher_->pose());
  covariance_ = scan_matched_covariance_;
}

void TopologicalSlam::Fuse(const Pose2& predicted, const Pose2& corrected,
                           const PoseInformation& information) {
  // The measurement: the corrected pose along the directions the points constrain (rows of H).
  if (information.directions.cols() == 0) return;
  const Eigen::MatrixXd h = information.directions.transpose();
  const double var = options_.point_sigma_m * options_.point_sigma_m;
  const Eigen::MatrixXd r = (h * information.weighted * h.transpose() / var).inverse();
  const Eigen::MatrixXd k =
      covariance_ * h.transpose() * (h * covariance_ * h.transpose() + r).inverse();
  const Eigen::Vector3d innovation(corrected.x() - predicted.x(), corrected.y() - predicted.y(),
                                   kernel::WrapAngle(corrected.theta() - predicted.theta()));
  const Eigen::Vector3d step = k * (h * innovation);
  pose_ = Pose2(predicted.x() + step.x(), predicted.y() + step.y(),
                kernel::WrapAngle(predicted.theta() + step.z()));
  covariance_ = (Eigen::Matrix3d::Identity() - k * h) * covariance_;
  covariance_ = 0.5 * (covariance_ + covariance_.transpose()).eval();
}

void TopologicalSlam::SetRegion(const kernel::LocalSafeRegion& region) {
  RegionShape shape;
  shape.center = region.center();
  shape.full_circle = region.full_circle();
  shape.radius_m = region.radius();
  std::vector<std::pair<double, double>> polar;
  for (const Eigen::Vector2d& v : region.boundary()) {
    const Eigen::Vector2d d = v - region.center();
    if (d.norm() < 1e-9) continue;  // the sensor vertex of a partial region
    polar.emplace_back(std::atan2(d.y(), d.x()), d.norm());
  }
  std::sort(polar.begin(), polar.end());
  for (const auto& [b, r] : polar) {
    shape.bearings_rad.push_back(b);
    shape.ranges_m.push_back(r);
  }
  region_ = std::move(shape);
}

void TopologicalSlam::SetLocalRegion(const kernel::LocalSafeRegion& region) {
  if (!healthy()) return;
  SetRegion(region);
  node_pending_ = true;
}

std::size_t TopologicalSlam::num_control_points() const {
  std::size_t n = 0;
  for (const SplineCurve& c : curves_) n += c.spline.control_points().size();
  return n;
}

std::vector<MapSpline> TopologicalSlam::MapSplines() const {
  std::vector<MapSpline> out;
  for (std::size_t i = 0; i < curves_.size(); ++i)
    out.push_back({static_cast<int>(i), curves_[i].spline, observations_[i]});
  return out;
}

std::int64_t TopologicalSlam::CellKey(const Eigen::Vector2d& p) const {
  return CellKey(static_cast<std::int64_t>(std::floor(p.x() / options_.index_cell_m)),
                 static_cast<std::int64_t>(std::floor(p.y() / options_.index_cell_m)));
}

void TopologicalSlam::Register(int curve) {
  const SplineCurve& c = curves_[static_cast<std::size_t>(curve)];
  std::vector<std::int64_t> keys;
  for (const Eigen::Vector2d& p : c.spline.control_points()) keys.push_back(CellKey(p));
  const std::size_t stride = std::max<std::size_t>(
      1, static_cast<std::size_t>(0.25 * options_.index_cell_m / options_.extraction.epsilon_m));
  for (std::size_t k = 0; k < c.samples.size(); k += stride) keys.push_back(CellKey(c.samples[k]));
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  for (std::int64_t key : keys) cells_[key].push_back(curve);
  curve_cells_[static_cast<std::size_t>(curve)] = std::move(keys);
}

void TopologicalSlam::Unregister(int curve) {
  for (std::int64_t key : curve_cells_[static_cast<std::size_t>(curve)]) {
    std::vector<int>& list = cells_[key];
    list.erase(std::remove(list.begin(), list.end(), curve), list.end());
  }
  curve_cells_[static_cast<std::size_t>(curve)].clear();
}

void TopologicalSlam::AddMapCurve(SplineCurve curve) {
  curves_.push_back(std::move(curve));
  observations_.push_back(1);
  curve_cells_.emplace_back();
  Register(static_cast<int>(curves_.size() - 1));
}

void TopologicalSlam::Reanchor(const std::function<Pose2(int)>& correction, const Pose2& pose) {
  for (std::size_t i = 0; i < curves_.size(); ++i) {
    const Pose2 c = correction(static_cast<int>(i));
    if (c.translation().isZero() && c.theta() == 0.0) continue;
    Unregister(static_cast<int>(i));
    curves_[i] = kernel::Transformed(curves_[i], c);
    Register(static_cast<int>(i));
  }
  const Pose2 moved = pose * pose_.Inverse();  // the pose's own correction
  if (region_) {
    region_->center = moved * region_->center;
    // Bearings are world-frame angles: turn them and keep them sorted.
    std::vector<std::pair<double, double>> polar;
    for (std::size_t k = 0; k < region_->bearings_rad.size(); ++k)
      polar.emplace_back(kernel::WrapAngle(region_->bearings_rad[k] + moved.theta()),
                         region_->ranges_m[k]);
    std::sort(polar.begin(), polar.end());
    for (std::size_t k = 0; k < polar.size(); ++k)
      std::tie(region_->bearings_rad[k], region_->ranges_m[k]) = polar[k];
  }
  if (last_map_update_) last_map_update_ = moved * *last_map_update_;
  pose_ = pose;
  if (scan_matcher_) front_frame_ = pose_ * scan_matcher_->pose().Inverse();
}

std::vector<int> TopologicalSlam::LocalCurves() const {
  std::vector<int> candidates;
  if (!region_) return candidates;
  const double reach = region_->radius_m + options_.region_margin_m;
  const double cell = options_.index_cell_m;
  const auto lo_x = static_cast<std::int64_t>(std::floor((region_->center.x() - reach) / cell));
  const auto hi_x = static_cast<std::int64_t>(std::floor((region_->center.x() + reach) / cell));
  const auto lo_y = static_cast<std::int64_t>(std::floor((region_->center.y() - reach) / cell));
  const auto hi_y = static_cast<std::int64_t>(std::floor((region_->center.y() + reach) / cell));
  for (std::int64_t ix = lo_x; ix <= hi_x; ++ix) {
    for (std::int64_t iy = lo_y; iy <= hi_y; ++iy) {
      const auto it = cells_.find(CellKey(ix, iy));
      if (it != cells_.end())
        candidates.insert(candidates.end(), it->second.begin(), it->second.end());
    }
  }
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  std::vector<int> local;
  const std::size_t stride =
      std::max<std::size_t>(1, static_cast<std::size_t>(0.1 / options_.extraction.epsilon_m));
  for (int i : candidates) {
    const std::vector<Eigen::Vector2d>& samples = curves_[static_cast<std::size_t>(i)].samples;
    for (std::size_t k = 0; k < samples.size(); k += stride) {
      if (region_->Near(samples[k], options_.region_margin_m)) {
        local.push_back(i);
        break;
      }
    }
  }
  return local;
}

std::vector<TopologicalSlam::Association> TopologicalSlam::Associate(
    const std::vector<SplineCurve>& observed, const Pose2& pose,
    const std::vector<int>& local) const {
  std::vector<Association> out;
  for (std::size_t i = 0; i < observed.size(); ++i) {
    const SplineCurve world = kernel::Transformed(observed[i], pose);
    std::optional<Association> best;
    for (int m : local) {
      std::optional<CurveMatch> match =
          association_.Match(world, curves_[static_cast<std::size_t>(m)]);
      if (!match || match->pairs.size() < 2) continue;
      const double length = match->observed.end_m - match->observed.start_m;
      if (best && length <= best->match.observed.end_m - best->match.observed.start_m) continue;
      best = Association{static_cast<int>(i), m, std::move(*match), 1.0};
    }
    if (!best) continue;
    // Reliability: paired features, else a straight stretch, else a smooth curve.
    if (best->match.used_features) {
      best->reliability = options_.feature_weight;
    } else {
      const CurveStretch& s = best->match.observed;
      const Eigen::Vector2d a = PointAt(observed[i], s.start_m);
      const Eigen::Vector2d b = PointAt(observed[i], s.end_m);
      const Eigen::Vector2d n = Eigen::Vector2d(a.y() - b.y(), b.x() - a.x()).normalized();
      double flatness = 0.0;
      const double step = std::max(0.05, (s.end_m - s.start_m) / 20.0);
      for (double t = s.start_m; t <= s.end_m; t += step)
        flatness = std::max(flatness, std::abs(n.dot(PointAt(observed[i], t) - a)));
      best->reliability =
          flatness <= options_.line_flatness_m ? options_.line_weight : options_.curve_weight;
    }
    out.push_back(std::move(*best));
  }
  return out;
}

namespace {

// The pair index of a point at observed arc length s inside a match (pairs are epsilon apart).
std::size_t PairIndex(const CurveMatch& match, double s, double epsilon) {
  const double k = std::round((s - match.observed.start_m) / epsilon);
  return std::min(match.pairs.size() - 1, static_cast<std::size_t>(std::max(0.0, k)));
}

// The features of `observed` (robot frame) inside the matched stretch, each with the map point
// the association paired it with: physical points, compared in both coordinates. Empty when the
// match paired no features.
std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> FeaturePairs(const SplineCurve& observed,
                                                                      const CurveMatch& m,
                                                                      double epsilon) {
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> out;
  if (!m.used_features) return out;
  for (const kernel::CurveFeature& f : observed.features) {
    if (f.arc_length_m < m.observed.start_m || f.arc_length_m > m.observed.end_m) continue;
    out.emplace_back(PointAt(observed, f.arc_length_m),
                     m.pairs[PairIndex(m, f.arc_length_m, epsilon)].second);
  }
  return out;
}

// Spacing of the points along a matched stretch at which its fit to the map curve is measured, m.
constexpr double kFitSpacingM = 0.1;
// Rounds of projection and solution of the point-to-curve correction (it stops earlier when a
// round moves the pose by less than 0.1 mm and 1e-5 rad).
constexpr int kPointToCurveIterations = 3;

// The spacing of an observed curve's samples in a correction or a test: `spacing`, but no finer
// than the curve's measured points lie apart on average (its length over their number). Between
// them the spline only interpolates: denser samples add cost, not evidence (a 1 mm spacing with
// 100 correction rounds took 16 s a scan, the option fuzzer's timeout).
double SampleSpacing(const SplineCurve& curve, double spacing) {
  if (curve.points.size() < 2) return spacing;
  return std::max(spacing, curve.spline.Length() / static_cast<double>(curve.points.size()));
}

// The start and end of a matched stretch, `trim` inside it when it is long enough.
std::pair<double, double> TrimmedEnds(const CurveStretch& s, double trim) {
  if (s.end_m - s.start_m <= 4.0 * trim) return {s.start_m, s.end_m};
  return {s.start_m + trim, s.end_m - trim};
}

// `robot` (robot frame) paired with `map` linearised at its projection c, or nullopt when c lies
// within end_trim_m of the curve's ends (the last span of a map curve bends with the noise of its
// last points, and a point that projects onto the end lies beyond it: neither gives a direction
// to trust) or the curve has no direction there.
std::optional<CurvePointPair> PairOn(const CubicBSpline& map, const CubicBSpline::ClosestPoint& c,
                                     const Eigen::Vector2d& robot, double end_trim_m,
                                     double weight) {
  const double arc = map.ArcLengthAt(c.t);
  if (arc < end_trim_m || arc > map.Length() - end_trim_m) return std::nullopt;
  const Eigen::Vector2d d = map.Derivative(c.t);
  if (d.norm() < 1e-12) return std::nullopt;
  return CurvePointPair{robot, c.point, Eigen::Vector2d(-d.y(), d.x()).normalized(), weight};
}

}  // namespace

Pose2 TopologicalSlam::Correct(const std::vector<SplineCurve>& observed,
                               const std::vector<Association>& associations, const Pose2& pose,
                               SolverCounts* solver) const {
  return options_.correction == TopologicalCorrection::kPaper
             ? CorrectAsPaper(observed, associations, pose, solver)
             : CorrectPointToCurve(observed, associations, pose, solver);
}

TopologicalSlam::CurvePoints TopologicalSlam::PointsOf(
    const std::vector<SplineCurve>& observed, const std::vector<Association>& associations) const {
  CurvePoints out;
  for (const Association& a : associations) {
    const SplineCurve& o = observed[static_cast<std::size_t>(a.observed)];
    const double spacing =
        SampleSpacing(o, options_.point_spacing_m > 0.0 ? options_.point_spacing_m : kFitSpacingM);
    const CubicBSpline* map = &curves_[static_cast<std::size_t>(a.map)].spline;
    const auto [s0, s1] = TrimmedEnds(a.match.observed, options_.end_trim_m);
    for (double s = s0; s <= s1 + 1e-9; s += spacing)
      out.samples.push_back({PointAt(o, s), map, a.reliability});
    for (const auto& [robot, map_point] : FeaturePairs(o, a.match, options_.association.epsilon_m))
      out.features.push_back({map_point, robot, a.reliability});
  }
  return out;
}

std::vector<CurvePointPair> TopologicalSlam::PairsAt(const CurvePoints& points,
                                                     const Pose2& pose) const {
  std::vector<CurvePointPair> pairs;
  pairs.reserve(points.samples.size());
  for (const CurvePoints::Sample& sample : points.samples) {
    const std::optional<CurvePointPair> pair =
        PairOn(*sample.map, sample.map->Closest(pose * sample.robot), sample.robot,
               options_.end_trim_m, sample.weight);
    if (pair) pairs.push_back(*pair);
  }
  return pairs;
}

Pose2 TopologicalSlam::CorrectPointToCurve(const std::vector<SplineCurve>& observed,
                                           const std::vector<Association>& associations,
                                           const Pose2& pose, SolverCounts* solver) const {
  const CurvePoints points = PointsOf(observed, associations);
  // Iterative closest points on the curves: each round linearises every curve at the projection
  // of its points seen from the previous round's pose.
  Pose2 current = pose;
  for (int i = 0; i < kPointToCurveIterations; ++i) {
    const Pose2 next = SolvePoseCorrection(PairsAt(points, current), points.features, current,
                                           options_.min_information, options_.loss, solver);
    const bool settled = (next.translation() - current.translation()).norm() < 1e-4 &&
                         std::abs(kernel::WrapAngle(next.theta() - current.theta())) < 1e-5;
    current = next;
    if (settled) break;
  }
  return current;
}

std::optional<TopologicalSlam::DenseResult> TopologicalSlam::RefineDense(
    const std::vector<SplineCurve>& observed, const std::vector<int>& local, const Pose2& start,
    const Pose2& predicted, SolverCounts* solver) const {
  // Every observed curve's points with their unit tangents, robot frame.
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> samples;
  for (const SplineCurve& o : observed) {
    const double spacing =
        SampleSpacing(o, options_.point_spacing_m > 0.0 ? options_.point_spacing_m : kFitSpacingM);
    const CurveStretch whole{0.0, o.spline.Length()};
    const auto [s0, s1] = TrimmedEnds(whole, options_.end_trim_m);
    for (double s = s0; s <= s1 + 1e-9; s += spacing) {
      const double t = o.spline.ParameterAtArcLength(s);
      const Eigen::Vector2d d = o.spline.Derivative(t);
      if (d.norm() > 1e-12) samples.emplace_back(o.spline.Point(t), d.normalized());
    }
  }
  if (static_cast<int>(samples.size()) < options_.dense_min_points) return std::nullopt;
  const double cos_max = std::cos(options_.dense_max_angle_rad);
  const double cell = options_.index_cell_m;
  if (!start.translation().allFinite() || !std::isfinite(start.theta())) return std::nullopt;
  Pose2 current = start;
  DenseResult result;
  for (int round = 0; round < kPointToCurveIterations; ++round) {
    const double gate =
        round == 0 ? options_.max_translation_correction_m : options_.verify_threshold_m;
    result.pairs.clear();
    for (const auto& [robot, tangent] : samples) {
      const Eigen::Vector2d world = current * robot;
      const Eigen::Vector2d world_tangent = current.Rotation() * tangent;
      const auto ix = static_cast<std::int64_t>(std::floor(world.x() / cell));
      const auto iy = static_cast<std::int64_t>(std::floor(world.y() / cell));
      std::optional<CurvePointPair> best;
      double best_distance = gate;
      for (std::int64_t dx = -1; dx <= 1; ++dx) {
        for (std::int64_t dy = -1; dy <= 1; ++dy) {
          const auto it = cells_.find(CellKey(ix + dx, iy + dy));
          if (it == cells_.end()) continue;
          for (int m : it->second) {
            if (!std::binary_search(local.begin(), local.end(), m)) continue;
            const CubicBSpline& map = curves_[static_cast<std::size_t>(m)].spline;
            const CubicBSpline::ClosestPoint c = map.Closest(world);
            if (c.distance >= best_distance) continue;
            std::optional<CurvePointPair> pair = PairOn(map, c, robot, options_.end_trim_m, 1.0);
            // The map curve's tangent is the pair's normal turned back by 90 deg.
            if (!pair || std::abs(pair->map_normal.x() * world_tangent.y() -
                                  pair->map_normal.y() * world_tangent.x()) < cos_max)
              continue;
            best = std::move(pair);
            best_distance = c.distance;
          }
        }
      }
      if (best) result.pairs.push_back(*best);
    }
    if (static_cast<int>(result.pairs.size()) < options_.dense_min_points) return std::nullopt;
    const Pose2 next = SolvePoseCorrection(result.pairs, {}, current, options_.min_information,
                                           options_.loss, solver);
    // A degenerate solve (weights that underflow) is no correction.
    if (!next.translation().allFinite() || !std::isfinite(next.theta())) return std::nullopt;
    const bool settled = (next.translation() - current.translation()).norm() < 1e-4 &&
                         std::abs(kernel::WrapAngle(next.theta() - current.theta())) < 1e-5;
    current = next;
    if (settled && round > 0) break;
  }
  if (std::abs(kernel::WrapAngle(current.theta() - predicted.theta())) >
          options_.max_heading_correction_rad ||
      (current.translation() - predicted.translation()).norm() >
          options_.max_translation_correction_m)
    return std::nullopt;
  double sum = 0.0;
  for (const CurvePointPair& p : result.pairs) {
    const double d = p.map_normal.dot(current * p.robot_point - p.map_point);
    sum += d * d;
  }
  if (options_.verify_rms_m > 0.0 &&
      std::sqrt(sum / static_cast<double>(result.pairs.size())) > options_.verify_rms_m)
    return std::nullopt;
  result.pose = current;
  return result;
}

Pose2 TopologicalSlam::CorrectAsPaper(const std::vector<SplineCurve>& observed,
                                      const std::vector<Association>& associations,
                                      const Pose2& pose, SolverCounts* solver) const {
  const double epsilon = options_.association.epsilon_m;
  auto map_of = [&](const Association& a) -> const CubicBSpline& {
    return curves_[static_cast<std::size_t>(a.map)].spline;
  };
  // Angular correction: one chord per matched stretch, between its (trimmed) start and end. The
  // map ends of the chord are the projections of the observed ends, placed at the estimate, onto
  // the matched map curve: a point of a smooth curve is known only up to a slide along it, and
  // the association's arc-length pairs would carry the prediction's along-curve error.
  std::vector<ChordPair> chords;
  for (const Association& a : associations) {
    const SplineCurve& o = observed[static_cast<std::size_t>(a.observed)];
    const CurveMatch& m = a.match;
    const auto [s0, s1] = TrimmedEnds(m.observed, options_.end_trim_m);
    const Eigen::Vector2d p0 = PointAt(o, s0);
    const Eigen::Vector2d p1 = PointAt(o, s1);
    const double chord = (p1 - p0).norm();
    if (chord < options_.min_chord_length_m) continue;
    const Eigen::Vector2d m0 = map_of(a).Closest(pose * p0).point;
    const Eigen::Vector2d m1 = map_of(a).Closest(pose * p1).point;
    chords.push_back({m1 - m0, p1 - p0, a.reliability * chord * chord});
  }
  const double theta =
      pose.theta() + SolveHeadingCorrection(chords, pose.theta(), options_.loss, solver);
  const Pose2 turned(pose.translation(), theta);

  // Translational correction: start, end and intermediate points of every stretch, each paired
  // with its projection onto the map curve at the corrected heading, and the paired features
  // (physical points: paired with the map feature).
  std::vector<PointPair> points;
  for (const Association& a : associations) {
    const SplineCurve& o = observed[static_cast<std::size_t>(a.observed)];
    const CurveMatch& m = a.match;
    const CubicBSpline& map = map_of(a);
    const auto [s0, s1] = TrimmedEnds(m.observed, options_.end_trim_m);
    auto on_curve = [&](double s) {
      const Eigen::Vector2d p = PointAt(o, s);
      points.push_back({map.Closest(turned * p).point, p, a.reliability});
    };
    on_curve(s0);
    on_curve(s1);
    if (options_.point_spacing_m > 0.0) {
      const double spacing = SampleSpacing(o, options_.point_spacing_m);
      for (double s = s0 + spacing; s < s1 - 0.5 * spacing; s += spacing) on_curve(s);
    }
    for (const auto& [robot, map_point] : FeaturePairs(o, m, epsilon))
      points.push_back({map_point, robot, a.reliability});
  }
  const Eigen::Vector2d e =
      SolveTranslationCorrection(points, pose.translation(), theta, options_.loss, solver);
  return Pose2(pose.translation() + e, theta);
}

bool TopologicalSlam::Verifies(const SplineCurve& observed, const Association& a,
                               const Pose2& pose) const {
  const CurveMatch& m = a.match;
  const CubicBSpline& map = curves_[static_cast<std::size_t>(a.map)].spline;
  const double threshold = options_.verify_threshold_m;
  const auto [s0, s1] = TrimmedEnds(m.observed, options_.end_trim_m);
  for (double s : {s0, s1}) {
    if (map.Closest(pose * PointAt(observed, s)).distance > threshold) return false;
  }
  // The whole stretch must lie on the map curve, not just its ends.
  if (options_.verify_rms_m > 0.0) {
    int n = 0;
    const double sum = SquaredDistances(
        observed, a, pose,
        SampleSpacing(observed, options_.point_spacing_m > 0.0 ? options_.point_spacing_m : 0.1),
        &n);
    if (n > 0 && std::sqrt(sum / n) > options_.verify_rms_m) return false;
  }
  for (const auto& [robot, map_point] : FeaturePairs(observed, m, options_.association.epsilon_m))
    if ((pose * robot - map_point).norm() > threshold) return false;
  return true;
}

double TopologicalSlam::SquaredDistances(const SplineCurve& observed, const Association& a,
                                         const Pose2& pose, double spacing_m, int* count) const {
  const CubicBSpline& map = curves_[static_cast<std::size_t>(a.map)].spline;
  const auto [s0, s1] = TrimmedEnds(a.match.observed, options_.end_trim_m);
  double sum = 0.0;
  for (double s = s0; s <= s1; s += spacing_m) {
    const double d = map.Closest(pose * PointAt(observed, s)).distance;
    sum += d * d;
    ++*count;
  }
  return sum;
}

double TopologicalSlam::MeanSquaredDistance(const std::vector<SplineCurve>& observed,
                                            const std::vector<Association>& associations,
                                            const Pose2& pose) const {
  double sum = 0.0;
  int n = 0;
  for (const Association& a : associations)
    sum +=
        SquaredDistances(observed[static_cast<std::size_t>(a.observed)], a, pose, kFitSpacingM, &n);
  return n > 0 ? sum / n : 0.0;
}

bool TopologicalSlam::NearMap(const std::vector<Eigen::Vector2d>& points, int except) const {
  const double d_min = options_.association.d_min_m;
  std::vector<int> candidates;
  for (const Eigen::Vector2d& p : points) {
    for (double dx : {-d_min, 0.0, d_min}) {
      for (double dy : {-d_min, 0.0, d_min}) {
        const auto it = cells_.find(CellKey(p + Eigen::Vector2d(dx, dy)));
        if (it != cells_.end())
          candidates.insert(candidates.end(), it->second.begin(), it->second.end());
      }
    }
  }
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  for (int c : candidates) {
    if (c == except) continue;
    const CubicBSpline& spline = curves_[static_cast<std::size_t>(c)].spline;
    for (const Eigen::Vector2d& p : points)
      if (spline.Closest(p).distance <= d_min) return true;
  }
  return false;
}

void TopologicalSlam::ExtendMap(const std::vector<SplineCurve>& observed,
                                const std::vector<Association>& verified,
                                TopologicalUpdateReport* report) {
  std::vector<bool> associated(observed.size(), false);
  std::vector<bool> extended(curves_.size(), false);
  for (const Association& a : verified) {
    associated[static_cast<std::size_t>(a.observed)] = true;
    ++observations_[static_cast<std::size_t>(a.map)];
    if (extended[static_cast<std::size_t>(a.map)]) continue;  // its match is stale now
    const SplineCurve world =
        kernel::Transformed(observed[static_cast<std::size_t>(a.observed)], pose_);
    const CubicBSpline& map = curves_[static_cast<std::size_t>(a.map)].spline;
    Continuation c = ContinuationOf(map, world.spline, a.match, options_);
    // A continuation that runs onto another map curve would duplicate it.
    if (!c.head.empty() && NearMap(c.head, a.map)) c = {{}, c.tail, 0, c.drop_back};
    if (!c.tail.empty() && NearMap(c.tail, a.map)) c = {c.head, {}, c.drop_front, 0};
    const std::size_t total =
        c.head.size() + map.control_points().size() + c.tail.size() - c.drop_front - c.drop_back;
    if ((c.head.empty() && c.tail.empty()) ||
        total > static_cast<std::size_t>(options_.max_control_points))
      continue;
    std::optional<CubicBSpline> spliced = Spliced(map, c.drop_front, c.drop_back, c.head, c.tail);
    if (!spliced) continue;
    Unregister(a.map);
    curves_[static_cast<std::size_t>(a.map)] =
        kernel::DescribeCurve(std::move(*spliced), options_.extraction);
    Register(a.map);
    extended[static_cast<std::size_t>(a.map)] = true;
    ++report->extended_curves;
  }
  for (std::size_t i = 0; i < observed.size(); ++i) {
    if (associated[i]) continue;
    const SplineCurve& o = observed[i];
    if (static_cast<int>(o.points.size()) < options_.min_new_curve_points ||
        o.spline.Length() < options_.min_new_curve_length_m)
      continue;
    SplineCurve world = kernel::Transformed(o, pose_);
    const std::vector<Eigen::Vector2d>& probe = world.spline.control_points();
    // New objects come from the local region, where the map is kept: a far piece of a wall is
    // spliced onto it once the robot is near, not started as a second object.
    const auto inside = std::count_if(probe.begin(), probe.end(), [&](const Eigen::Vector2d& p) {
      return region_->Near(p, options_.region_margin_m);
    });
    if (2 * static_cast<std::size_t>(inside) < probe.size() || NearMap(probe, -1)) continue;
    AddMapCurve(std::move(world));
    ++report->added_curves;
  }
}

TopologicalUpdateReport TopologicalSlam::Update(const kernel::Scan& scan,
                                                const Pose2& robot_T_laser) {
  TopologicalUpdateReport report;
  if (!healthy()) return report;
  const kernel::Scan clipped =
      options_.max_curve_range_m > 0.0 ? scan.Clipped(options_.max_curve_range_m) : scan;
  std::vector<SplineCurve> observed;  // robot frame
  for (const SplineCurve& c : kernel::ExtractCurves(clipped, options_.extraction))
    observed.push_back(kernel::Transformed(c, robot_T_laser));
  report.observed_curves = static_cast<int>(observed.size());

  if (scan_matcher_ && options_.scan_matching_feedback) {
    // The front end's registered pose is the prediction, and the corrected pose goes back to it
    // before it makes the scan a keyframe.
    GraphFrontEnd& front_end = scan_matcher_->front_end();
    if (std::optional<GraphFrontEnd::PreparedScan> registered =
            front_end.Register(scan, robot_T_laser)) {
      report.scan_matched = front_end.registered();
      if (report.scan_matched) {
        pose_ = front_frame_ * front_end.pose();
        covariance_ = scan_matched_covariance_;
      }
      CorrectAndMap(scan, robot_T_laser, observed, &report);
      if (front_end.Settle(front_frame_.Inverse() * pose_))
        scan_matcher_->AddScan(std::move(*registered), robot_T_laser);
    }
  } else {
    if (scan_matcher_) PredictByScanMatching(scan, robot_T_laser, &report);
    CorrectAndMap(scan, robot_T_laser, observed, &report);
  }
  scan_matched_covariance_ = covariance_;
  return report;
}

void TopologicalSlam::CorrectAndMap(const kernel::Scan& scan, const Pose2& robot_T_laser,
                                    const std::vector<SplineCurve>& observed,
                                    TopologicalUpdateReport* out) {
  TopologicalUpdateReport& report = *out;
  const Pose2 predicted = pose_;
  if (!region_ || (predicted.translation() - region_->center).norm() >
                      options_.region.alpha * options_.region.radius_m)
    SetRegion(kernel::LocalSafeRegion::FromScan(scan, predicted * robot_T_laser,
                                                options_.region.radius_m));
  const std::vector<int> local = LocalCurves();
  report.local_map_curves = static_cast<int>(local.size());

  // Associate and correct, each round at the pose the previous one corrected.
  Pose2 pose = predicted;
  std::vector<Association> first, associations;
  for (int round = 0; round < options_.correction_rounds; ++round) {
    std::vector<Association> found = Associate(observed, pose, local);
    if (round == 0) first = found;
    if (found.empty()) break;  // keep the previous round's associations and pose
    associations = std::move(found);
    pose = Correct(observed, associations, pose, &report.solver);
  }
  report.associated_curves = static_cast<int>(first.size());

  // VERIFY_LOCALIZATION: the whole set, else the best hypothesis of a single curve.
  std::vector<Association> verified;
  auto verifying = [&](const std::vector<Association>& set, const Pose2& at) {
    std::vector<Association> ok;
    for (const Association& a : set)
      if (Verifies(observed[static_cast<std::size_t>(a.observed)], a, at)) ok.push_back(a);
    return ok;
  };
  auto plausible = [&](const Pose2& corrected) {
    return std::abs(kernel::WrapAngle(corrected.theta() - predicted.theta())) <=
               options_.max_heading_correction_rad &&
           (corrected.translation() - predicted.translation()).norm() <=
               options_.max_translation_correction_m;
  };
  if (!associations.empty()) {
    if (plausible(pose)) verified = verifying(associations, pose);
    if (verified.size() == associations.size()) {
      report.localized = true;
    } else {
      verified.clear();
      report.used_fallback = true;
      Pose2 best_pose = predicted;
      for (const Association& a : first) {
        const Pose2 hypothesis = Correct(observed, {a}, predicted, &report.solver);
        if (!plausible(hypothesis)) continue;
        std::vector<Association> agree = verifying(first, hypothesis);
        if (agree.size() > verified.size()) {
          verified = std::move(agree);
          best_pose = hypothesis;
        }
      }
      if (!verified.empty()) {
        report.localized = true;
        pose = Correct(observed, verified, predicted, &report.solver);
        std::vector<Association> joint;
        if (plausible(pose)) joint = verifying(verified, pose);
        if (joint.empty()) {
          pose = best_pose;
        } else {
          verified = std::move(joint);
        }
      } else {
        pose = predicted;
      }
    }
  }
  report.verified_curves = static_cast<int>(verified.size());
  if (report.localized && static_cast<int>(verified.size()) < options_.min_verified_curves) {
    report.localized = false;  // too little to trust: keep the prediction, do not map
    pose = predicted;
  }
  // A correction that does not bring the verified curves closer to the map than the prediction
  // had them is refused (it turned or moved them along themselves): the prediction stands and the
  // map is not extended from it.
  if (report.localized && options_.verify_improves &&
      MeanSquaredDistance(observed, verified, pose) >=
          MeanSquaredDistance(observed, verified, predicted)) {
    report.localized = false;
    report.refused_no_better = true;
    pose = predicted;
  }
  if (options_.correction == TopologicalCorrection::kPaper) {
    const double k = options_.correction_gain;
    pose_ = Pose2(predicted.translation() + k * (pose.translation() - predicted.translation()),
                  predicted.theta() + k * kernel::WrapAngle(pose.theta() - predicted.theta()));
  } else {
    std::optional<DenseResult> dense;
    if (options_.dense_refinement && !local.empty())
      dense = RefineDense(observed, local, pose, predicted, &report.solver);
    if (dense) {
      report.dense = true;
      report.dense_points = static_cast<int>(dense->pairs.size());
      Fuse(predicted, dense->pose,
           PointInformation(dense->pairs, {}, dense->pose.theta(), options_.min_information));
    } else if (report.localized) {
      const CurvePoints points = PointsOf(observed, verified);
      Fuse(predicted, pose,
           PointInformation(PairsAt(points, pose), points.features, pose.theta(),
                            options_.min_information));
    }
  }
  report.heading_correction_rad = kernel::WrapAngle(pose_.theta() - predicted.theta());
  report.translation_correction = pose_.translation() - predicted.translation();

  // Map extension, when due, and not after a failed localisation (the map would be corrupted).
  const bool due = node_pending_ || !last_map_update_ ||
                   (pose_.translation() - last_map_update_->translation()).norm() >=
                       options_.map_update_distance_m ||
                   std::abs(kernel::WrapAngle(pose_.theta() - last_map_update_->theta())) >=
                       options_.map_update_angle_rad;
  if (due && (report.localized || first.empty())) {
    ExtendMap(observed, verified, &report);
    report.map_updated = true;
    last_map_update_ = pose_;
    node_pending_ = false;
  }
}

}  // namespace splam::estimation
