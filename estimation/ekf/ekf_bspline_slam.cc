#include "estimation/ekf/ekf_bspline_slam.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "estimation/chi_square.h"
#include "estimation/ekf/bspline_models.h"
#include "estimation/ekf/joint_compatibility.h"
#include "kernel/bspline_fit.h"
#include "kernel/shapes.h"

namespace splam::estimation {
namespace {

using kernel::CubicBSpline;
using kernel::SplineCurve;

// Approximate arc length of every measured point along its curve: the chord length along the
// points scaled to the curve's length (the fit's parameters are chord lengths too).
std::vector<double> ApproximateArcLengths(const SplineCurve& curve) {
  std::vector<double> s(curve.points.size(), 0.0);
  for (std::size_t k = 1; k < s.size(); ++k)
    s[k] = s[k - 1] + (curve.points[k] - curve.points[k - 1]).norm();
  const double scale = s.back() > 0.0 ? curve.spline.Length() / s.back() : 0.0;
  for (double& v : s) v *= scale;
  return s;
}

// Variance of a measured range: the laser's noise plus the model error.
double RangeVariance(const EkfBSplineSlamOptions& o, double range_m) {
  const double sigma = o.range_sigma_floor_m + o.range_sigma_fraction * range_m;
  return sigma * sigma + o.model_sigma_m * o.model_sigma_m;
}

}  // namespace

struct EkfBSplineSlam::Match {
  std::size_t curve;
  std::size_t landmark;
  CurveMatch match;
  double Length() const { return match.observed.end_m - match.observed.start_m; }
};

// What the steps of one update share.
struct EkfBSplineSlam::ScanContext {
  ScanContext(const kernel::Scan& s, const kernel::Pose2& mounting)
      : scan(s), robot_T_laser(mounting) {}
  const kernel::Scan& scan;
  kernel::Pose2 robot_T_laser;
  std::vector<SplineCurve> curves;                     // laser frame
  std::vector<SplineCurve> observed;                   // world frame, at the prediction
  std::vector<std::optional<SplineCurve>> map_curves;  // described where needed
  std::vector<Match> matches;                          // every fine association
  std::vector<bool> near_map;                          // per observed curve
  std::vector<const Match*> accepted;                  // longest first, no duplicates
  std::vector<bool> matched;                           // per observed curve, beams used
  // Length of [start, end] of observed curve `curve` already covered by accepted matches.
  double Covered(std::size_t curve, double start, double end) const;
};

kernel::Status EkfBSplineSlamOptions::Validate() const {
  if (kernel::Status s = kernel::FirstError(odometry.Validate(), extraction.Validate(),
                                            association_options.Validate(), map_fit.Validate());
      !s.ok())
    return s;
  if (association != "pedraza" && association != "curvature")
    return kernel::Status::Error("association must be \"pedraza\" or \"curvature\", not \"" +
                                 association + "\"");
  if (match_selection != "longest" && match_selection != "jcbb")
    return kernel::Status::Error("match_selection must be \"longest\" or \"jcbb\", not \"" +
                                 match_selection + "\"");
  // Sigmas and distances bounded above as well: a variance of 1e12 m^2 beside one of 1e-4 leaves
  // the filter's covariance ill-conditioned, its corrections throw control points kilometres, and
  // the curves' resampling then takes minutes (a control point floor of 1e6 m with 52 beams per
  // match: 100 s for 30 scans, found by the option fuzzer).
  const auto within = [](double v, double lo, double hi) { return v >= lo && v <= hi; };
  if (!within(range_sigma_floor_m, 0, 10) || !within(range_sigma_fraction, 0, 1) ||
      !within(model_sigma_m, 0, 10) ||
      !(range_sigma_floor_m + range_sigma_fraction + model_sigma_m > 0))
    return kernel::Status::Error(
        "range noise: range_sigma_floor_m and model_sigma_m in [0, 10] m, range_sigma_fraction "
        "in [0, 1], not all zero");
  if (!within(beam_spacing_m, 0, 10) || max_beams_per_match < 1 || max_beams_per_match > 10000)
    return kernel::Status::Error(
        "beam selection: beam_spacing_m in [0, 10] m, max_beams_per_match in [1, 10000]");
  if (!(max_correspondence_distance_m > 0 && max_correspondence_distance_m <= 10) ||
      !(beam_gate_probability > 0 && beam_gate_probability < 1))
    return kernel::Status::Error(
        "beam gates: max_correspondence_distance_m in (0, 10] m, beam_gate_probability in (0, 1)");
  if (!(min_incidence_sine >= 0 && min_incidence_sine < 1))
    return kernel::Status::Error("bad min_incidence_sine");
  if (!(min_new_curve_length_m >= 0) || min_new_curve_points < 4 || min_observations_to_add < 1 ||
      candidate_max_age_scans < 1)
    return kernel::Status::Error("bad new-curve limits");
  if (!(max_curve_range_m >= 0)) return kernel::Status::Error("max_curve_range_m must be >= 0");
  // A curve is resampled every extension_sample_spacing_m to extend it: 1e-29 m made 1.7e29
  // samples (UBSan, found by the option fuzzer).
  if (!(min_extension_length_m > 0) || !(end_tolerance_m >= 0) ||
      !(extension_sample_spacing_m >= 1e-3 && extension_sample_spacing_m <= 10))
    return kernel::Status::Error(
        "min_extension_length_m must be positive, end_tolerance_m >= 0 and "
        "extension_sample_spacing_m in [0.001, 10] m");
  if (!within(control_point_sigma_floor_m, 0, 10))
    return kernel::Status::Error("control_point_sigma_floor_m must be in [0, 10] m");
  return kernel::Status::Ok();
}

EkfBSplineSlam::EkfBSplineSlam(const kernel::Pose2& initial_pose,
                               const Eigen::Matrix3d& initial_covariance,
                               const EkfBSplineSlamOptions& options)
    : options_(options),
      association_(MakeSplineAssociation(options.association, options.association_options)),
      beam_gate_(ChiSquareQuantile(options.beam_gate_probability, 1)),
      ekf_(initial_pose, initial_covariance),
      candidates_(options.min_observations_to_add, options.candidate_max_age_scans) {
  if (kernel::Status problem = options.Validate(); !problem.ok())
    ekf_.Fail("invalid options: " + problem.message());
}

void EkfBSplineSlam::Predict(const kernel::Pose2& u) {
  ekf_.Predict(u, options_.odometry.Covariance(u));
}

std::optional<CubicBSpline> EkfBSplineSlam::TrySplineOf(const Landmark& landmark) const {
  const Eigen::Index n = landmark.size() / 2;
  std::vector<Eigen::Vector2d> control(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i)
    control[static_cast<std::size_t>(i)] = ekf_.state().segment<2>(landmark.index + 2 * i);
  return CubicBSpline::Create(std::move(control), landmark.knots).value;
}

CubicBSpline EkfBSplineSlam::SplineOf(const Landmark& landmark) const {
  return *TrySplineOf(landmark);  // the knots are valid; the state is finite while healthy
}

std::vector<MapSpline> EkfBSplineSlam::MapSplines() const {
  std::vector<MapSpline> out;
  for (const Landmark& l : splines_) {
    // An unhealthy filter may hold non-finite control points: those splines are left out.
    if (std::optional<CubicBSpline> spline = TrySplineOf(l))
      out.push_back({l.id, std::move(*spline), l.observations});
  }
  return out;
}

BSplineUpdateReport EkfBSplineSlam::Update(const kernel::Scan& scan,
                                           const kernel::Pose2& robot_T_laser) {
  BSplineUpdateReport report;
  if (!healthy()) return report;
  ++scans_;
  ScanContext ctx(scan, robot_T_laser);
  ctx.curves = kernel::ExtractCurves(
      options_.max_curve_range_m > 0 ? scan.Clipped(options_.max_curve_range_m) : scan,
      options_.extraction);
  report.observed_curves = static_cast<int>(ctx.curves.size());
  Associate(&ctx);
  if (options_.match_selection == "jcbb")
    AcceptJointlyCompatibleMatches(&ctx);
  else
    AcceptLongestMatches(&ctx);
  CorrectWithBeams(&ctx, &report);
  if (!healthy()) return report;
  ExtendMatchedSplines(ctx, &report);
  AddNewSplines(ctx, &report);
  return report;
}

double EkfBSplineSlam::ScanContext::Covered(std::size_t curve, double start, double end) const {
  double overlap = 0.0;
  for (const Match* a : accepted) {
    if (a->curve != curve) continue;
    overlap += std::max(
        0.0, std::min(end, a->match.observed.end_m) - std::max(start, a->match.observed.start_m));
  }
  return overlap;
}

void EkfBSplineSlam::Associate(ScanContext* context) const {
  ScanContext& ctx = *context;
  // Association at the predicted pose: every observed curve against every map spline whose
  // control points come within d_min (the coarse test), then the fine association.
  const kernel::Pose2 world_T_laser = pose() * ctx.robot_T_laser;
  for (const SplineCurve& c : ctx.curves)
    ctx.observed.push_back(kernel::Transformed(c, world_T_laser));
  const double d_min = options_.association_options.d_min_m;
  // Boxes of the map splines' control points, straight from the state.
  ctx.map_curves.assign(splines_.size(), std::nullopt);
  ctx.near_map.assign(ctx.observed.size(), false);
  std::vector<kernel::Box2> map_boxes(splines_.size());
  for (std::size_t l = 0; l < splines_.size(); ++l) {
    for (Eigen::Index i = 0; i < splines_[l].size(); i += 2)
      map_boxes[l].Extend(ekf_.state().segment<2>(splines_[l].index + i));
  }
  for (std::size_t i = 0; i < ctx.observed.size(); ++i) {
    kernel::Box2 box;
    for (const Eigen::Vector2d& p : ctx.observed[i].spline.control_points()) box.Extend(p);
    for (std::size_t l = 0; l < splines_.size(); ++l) {
      if (box.Gap(map_boxes[l]) > d_min) continue;
      if (!ctx.map_curves[l])
        ctx.map_curves[l] = kernel::DescribeCurve(SplineOf(splines_[l]), options_.extraction);
      if (RelatedControlPoints(ctx.observed[i], *ctx.map_curves[l], d_min) == 0) continue;
      ctx.near_map[i] = true;
      std::optional<CurveMatch> m = association_->Match(ctx.observed[i], *ctx.map_curves[l]);
      if (m) ctx.matches.push_back({i, l, std::move(*m)});
    }
  }
}

void EkfBSplineSlam::AcceptLongestMatches(ScanContext* context) const {
  ScanContext& ctx = *context;
  // Longest stretches first; a stretch mostly covered by an accepted one of the same
  // observed curve (a duplicate map spline of the same obstacle) is dropped.
  std::sort(ctx.matches.begin(), ctx.matches.end(),
            [](const Match& a, const Match& b) { return a.Length() > b.Length(); });
  for (const Match& m : ctx.matches) {
    if (ctx.Covered(m.curve, m.match.observed.start_m, m.match.observed.end_m) > 0.5 * m.Length())
      continue;
    ctx.accepted.push_back(&m);
  }
}

void EkfBSplineSlam::AcceptJointlyCompatibleMatches(ScanContext* context) const {
  ScanContext& ctx = *context;
  std::sort(ctx.matches.begin(), ctx.matches.end(),
            [](const Match& a, const Match& b) { return a.Length() > b.Length(); });
  // Each match with the beams it would correct with, as SelectBeams picks them now.
  std::vector<CompatibilityItem> items;
  std::vector<const Match*> of_item;
  for (const Match& m : ctx.matches) {
    BeamBatch batch;
    SplineAssociationRecord record;
    SelectBeams(ctx.scan, ctx.robot_T_laser, ctx.observed[m.curve], ctx.curves[m.curve].beams, m,
                ctx.map_curves[m.landmark]->spline, &record, &batch);
    const auto rows = static_cast<Eigen::Index>(batch.nu.size());
    if (rows == 0) continue;
    CompatibilityItem item;
    item.group = static_cast<int>(items.size());
    item.innovation = Eigen::Map<const Eigen::VectorXd>(batch.nu.data(), rows);
    item.h_robot = batch.h_robot.topRows(rows);
    item.blocks = std::move(batch.blocks);
    item.noise = Eigen::Map<const Eigen::VectorXd>(batch.variance.data(), rows).asDiagonal();
    items.push_back(std::move(item));
    of_item.push_back(&m);
  }
  // Two stretches of one observed curve that overlap by half the shorter: one obstacle twice.
  const auto overlapping = [&](int a, int b) {
    const Match& x = *of_item[static_cast<std::size_t>(a)];
    const Match& y = *of_item[static_cast<std::size_t>(b)];
    if (x.curve != y.curve) return false;
    const double overlap = std::min(x.match.observed.end_m, y.match.observed.end_m) -
                           std::max(x.match.observed.start_m, y.match.observed.start_m);
    return overlap > 0.5 * std::min(x.Length(), y.Length());
  };
  const JointCompatibilityResult joint =
      JointCompatibility(items, overlapping, ekf_.covariance(), options_.beam_gate_probability);
  for (const int i : joint.chosen) ctx.accepted.push_back(of_item[static_cast<std::size_t>(i)]);
}

void EkfBSplineSlam::CorrectWithBeams(ScanContext* context, BSplineUpdateReport* out) {
  ScanContext& ctx = *context;
  BSplineUpdateReport& report = *out;
  // One correction with the selected beams of every accepted match: a single pass over P.
  BeamBatch batch;
  for (const Match* m : ctx.accepted) {
    SplineAssociationRecord record;
    record.observed_curve = m->curve;
    record.map_spline = splines_[m->landmark].id;
    record.used_features = m->match.used_features;
    // The state has not changed since the association: the described map curve is current.
    SelectBeams(ctx.scan, ctx.robot_T_laser, ctx.observed[m->curve], ctx.curves[m->curve].beams, *m,
                ctx.map_curves[m->landmark]->spline, &record, &batch);
    report.associations.push_back(std::move(record));
  }
  const Eigen::Index rows = static_cast<Eigen::Index>(batch.nu.size());
  if (rows > 0) {
    const Eigen::VectorXd r = Eigen::Map<const Eigen::VectorXd>(batch.variance.data(), rows);
    if (!ekf_.Correct(batch.h_robot.topRows(rows), batch.blocks,
                      Eigen::Map<const Eigen::VectorXd>(batch.nu.data(), rows),
                      r.asDiagonal().toDenseMatrix())) {
      for (SplineAssociationRecord& record : report.associations) {
        record.rejected_beams += static_cast<int>(record.beams.size());
        record.beams.clear();
      }
    }
  }
  ctx.matched.assign(ctx.observed.size(), false);
  for (std::size_t a = 0; a < ctx.accepted.size(); ++a) {
    const SplineAssociationRecord& record = report.associations[a];
    report.beams_rejected += record.rejected_beams;
    if (record.beams.empty()) continue;
    ctx.matched[ctx.accepted[a]->curve] = true;
    report.beams_used += static_cast<int>(record.beams.size());
    ++splines_[ctx.accepted[a]->landmark].observations;
  }
  report.matched_curves =
      static_cast<int>(std::count(ctx.matched.begin(), ctx.matched.end(), true));
}

void EkfBSplineSlam::ExtendMatchedSplines(const ScanContext& ctx, BSplineUpdateReport* out) {
  BSplineUpdateReport& report = *out;
  // Extensions: an observed curve that runs on past the end of the map spline it matched.
  const double tol = options_.end_tolerance_m;
  std::vector<bool> extended(splines_.size(), false);
  for (const Match* m : ctx.accepted) {
    if (extended[m->landmark] || !ctx.matched[m->curve]) continue;
    const SplineCurve& o = ctx.observed[m->curve];
    const double lo = o.spline.Length(), lm = ctx.map_curves[m->landmark]->spline.Length();
    const bool reversed = m->match.map.end_m < m->match.map.start_m;
    const double os = m->match.observed.start_m, oe = m->match.observed.end_m;
    const std::vector<double> arc = ApproximateArcLengths(o);
    const std::vector<std::size_t>& beams = ctx.curves[m->curve].beams;
    // Each part of the observed curve beyond the stretch: [from, to] in observed arc
    // length, whether the map stretch reaches the map curve's end on that side, and which end (the
    // map curve's end, else its start).
    struct Side {
      double from, to;
      bool map_end_reached, at_map_end;
    };
    const Side sides[2] = {
        {0.0, os, reversed ? m->match.map.start_m >= lm - tol : m->match.map.start_m <= tol,
         reversed},
        {oe, lo, reversed ? m->match.map.end_m <= tol : m->match.map.end_m >= lm - tol, !reversed},
    };
    for (int side = 0; side < 2 && !extended[m->landmark]; ++side) {
      const Side& sd = sides[side];
      if (!sd.map_end_reached || sd.to - sd.from < options_.min_extension_length_m) continue;
      if (ctx.Covered(m->curve, sd.from, sd.to) > options_.end_tolerance_m) continue;
      // Beams beyond the stretch, ordered away from the map curve.
      std::vector<std::size_t> beyond;
      for (std::size_t k = 0; k < beams.size(); ++k) {
        if (arc[k] > sd.from && arc[k] < sd.to) beyond.push_back(beams[k]);
      }
      if (side == 0) std::reverse(beyond.begin(), beyond.end());
      if (beyond.size() < 4) continue;
      Landmark& landmark = splines_[m->landmark];
      if (ExtendSpline(&landmark, ctx.scan, ctx.robot_T_laser, beyond, sd.at_map_end)) {
        extended[m->landmark] = true;
        report.extended.push_back({landmark.id, beyond});
      }
    }
  }
}

void EkfBSplineSlam::AddNewSplines(const ScanContext& ctx, BSplineUpdateReport* out) {
  BSplineUpdateReport& report = *out;
  const double d_min = options_.association_options.d_min_m;
  // New splines from curves that no map spline comes near.
  for (std::size_t i = 0; i < ctx.observed.size(); ++i) {
    if (ctx.near_map[i]) {
      report.ignored_curves += !ctx.matched[i];
      continue;
    }
    if (ctx.observed[i].spline.Length() < options_.min_new_curve_length_m ||
        static_cast<int>(ctx.curves[i].beams.size()) < options_.min_new_curve_points) {
      ++report.ignored_curves;
      continue;
    }
    // Match a candidate (a control point within d_min); promote it when seen often enough.
    const std::vector<Eigen::Vector2d> world_controls =
        ctx.curves[i].spline.Transformed(pose() * ctx.robot_T_laser).control_points();
    const auto near = [d_min](const std::vector<Eigen::Vector2d>& candidate,
                              const std::vector<Eigen::Vector2d>& seen) {
      return std::any_of(seen.begin(), seen.end(), [&](const auto& a) {
        return std::any_of(candidate.begin(), candidate.end(),
                           [&](const auto& b) { return (a - b).norm() <= d_min; });
      });
    };
    if (!candidates_.Observe(world_controls, scans_, near)) {
      ++report.candidates;
      continue;
    }
    if (AddSpline(ctx.scan, ctx.robot_T_laser, ctx.curves[i].beams))
      report.created.push_back({splines_.back().id, ctx.curves[i].beams});
  }
  candidates_.Prune(scans_);
}

void EkfBSplineSlam::SelectBeams(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser,
                                 const SplineCurve& observed, const std::vector<std::size_t>& beams,
                                 const Match& match, const CubicBSpline& spline,
                                 SplineAssociationRecord* record, BeamBatch* batch) const {
  const Landmark& landmark = splines_[match.landmark];
  const CurveMatch& cm = match.match;
  const double epsilon = options_.association_options.epsilon_m;
  // Beams in the observed stretch, spaced along it.
  const std::vector<double> arc = ApproximateArcLengths(observed);
  const double spacing = std::max(
      options_.beam_spacing_m, match.Length() / static_cast<double>(options_.max_beams_per_match));
  std::vector<std::size_t> candidates;
  double last = -1e9;
  for (std::size_t k = 0; k < beams.size(); ++k) {
    if (arc[k] < cm.observed.start_m || arc[k] > cm.observed.end_m || arc[k] - last < spacing)
      continue;
    candidates.push_back(k);
    record->matched_beams.push_back(beams[k]);
    last = arc[k];
  }

  const kernel::Pose2 x = pose();
  const kernel::Pose2 world_T_laser = x * robot_T_laser;
  const Eigen::MatrixXd& p = ekf_.covariance();
  for (const std::size_t k : candidates) {
    const std::size_t beam = beams[k];
    // The map point the association paired with this measured point.
    const double s = observed.spline.ArcLengthAt(observed.spline.Closest(observed.points[k]).t);
    if (s < cm.observed.start_m - epsilon || s > cm.observed.end_m + epsilon) continue;
    const std::size_t j = std::min(
        cm.pairs.size() - 1,
        static_cast<std::size_t>(std::max(0.0, std::round((s - cm.observed.start_m) / epsilon))));
    const Eigen::Vector2d& paired = cm.pairs[j].second;
    const double angle = scan.BeamAngle(beam);
    const std::optional<BeamPrediction> pred =
        PredictBeam(x, robot_T_laser, angle, spline, scan.max_range_m, options_.min_incidence_sine);
    if (!pred) {
      ++record->rejected_beams;
      continue;
    }
    const Eigen::Vector2d hit = world_T_laser * Eigen::Vector2d(pred->range_m * std::cos(angle),
                                                                pred->range_m * std::sin(angle));
    if ((hit - paired).norm() > options_.max_correspondence_distance_m) {
      ++record->rejected_beams;
      continue;
    }
    const double nu = scan.ranges_m[beam] - pred->range_m;
    const double variance = RangeVariance(options_, scan.ranges_m[beam]);
    // Individual chi-square gate with the local covariance of pose and the 4 control points.
    Eigen::Matrix<double, 1, 11> h;
    h << pred->d_range_d_pose, pred->d_range_d_controls;
    Eigen::Index idx[11] = {0, 1, 2};
    const Eigen::Index c0 = landmark.index + 2 * static_cast<Eigen::Index>(pred->first_control);
    for (int c = 0; c < 8; ++c) idx[3 + c] = c0 + c;
    double s_beam = variance;
    for (int a = 0; a < 11; ++a)
      for (int b = 0; b < 11; ++b) s_beam += h(a) * p(idx[a], idx[b]) * h(b);
    if (nu * nu > beam_gate_ * s_beam) {
      ++record->rejected_beams;
      continue;
    }
    const Eigen::Index row = static_cast<Eigen::Index>(batch->nu.size());
    if (row == batch->h_robot.rows()) batch->h_robot.conservativeResize(2 * row + 32, 3);
    batch->h_robot.row(row) = h.head<3>();
    batch->blocks.push_back({c0, h.tail<8>(), row});
    batch->nu.push_back(nu);
    batch->variance.push_back(variance);
    record->beams.push_back(beam);
  }
}

bool EkfBSplineSlam::AddSpline(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser,
                               const std::vector<std::size_t>& beams) {
  const BeamPoints b = Beams(scan, robot_T_laser, beams);
  const kernel::Result<kernel::BSplineFitOperator> op =
      kernel::CubicBSplineFitOperator(b.points, options_.map_fit);
  if (!op) return false;
  const Eigen::Index n = op->m.rows();
  std::vector<Eigen::Index> columns(beams.size());
  for (std::size_t k = 0; k < beams.size(); ++k) columns[k] = static_cast<Eigen::Index>(k);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(2 * n);
  Eigen::MatrixXd g_r = Eigen::MatrixXd::Zero(2 * n, 3);
  const Eigen::MatrixXd g_z = AddBeamColumns(op->m, columns, b, &g, &g_r);
  const double floor = options_.control_point_sigma_floor_m;
  const Eigen::MatrixXd q = g_z * RangeVariances(scan, beams).asDiagonal() * g_z.transpose() +
                            floor * floor * Eigen::MatrixXd::Identity(2 * n, 2 * n);
  const Eigen::Index index = ekf_.Append(g, g_r, q);
  splines_.push_back({next_id_++, index, op->knots, 1});
  return true;
}

BeamPoints EkfBSplineSlam::Beams(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser,
                                 const std::vector<std::size_t>& beams) const {
  std::vector<double> ranges, angles;
  for (const std::size_t k : beams) {
    ranges.push_back(scan.ranges_m[k]);
    angles.push_back(scan.BeamAngle(k));
  }
  return BeamPointsInWorld(pose(), robot_T_laser, ranges, angles);
}

Eigen::VectorXd EkfBSplineSlam::RangeVariances(const kernel::Scan& scan,
                                               const std::vector<std::size_t>& beams) const {
  Eigen::VectorXd v(static_cast<Eigen::Index>(beams.size()));
  for (std::size_t k = 0; k < beams.size(); ++k)
    v(static_cast<Eigen::Index>(k)) = RangeVariance(options_, scan.ranges_m[beams[k]]);
  return v;
}

bool EkfBSplineSlam::ExtendSpline(Landmark* landmark, const kernel::Scan& scan,
                                  const kernel::Pose2& robot_T_laser,
                                  const std::vector<std::size_t>& beams, bool at_end) {
  // The old curve as samples C(u_j) = sum_a N_a(u_j) X_a, linear in its control points.
  const CubicBSpline old = SplineOf(*landmark);
  const int samples = std::max(
      4, static_cast<int>(std::ceil(old.Length() / options_.extension_sample_spacing_m)) + 1);
  std::vector<CubicBSpline::Basis> basis;
  std::vector<Eigen::Vector2d> points;
  const BeamPoints b = Beams(scan, robot_T_laser, beams);
  const std::size_t m_new = beams.size();
  // Data order along the extended curve: old samples then the new points (at its end), or the
  // new points from the farthest then the old samples (at its start).
  if (!at_end) points.assign(b.points.rbegin(), b.points.rend());
  for (int j = 0; j < samples; ++j) {
    const double u = old.ParameterAtArcLength(old.Length() * j / (samples - 1));
    basis.push_back(old.BasisAt(u));
    points.push_back(old.Point(u));
  }
  if (at_end) points.insert(points.end(), b.points.begin(), b.points.end());
  const kernel::Result<kernel::BSplineFitOperator> op =
      kernel::CubicBSplineFitOperator(points, options_.map_fit);
  if (!op) return false;

  const Eigen::Index n = op->m.rows();
  const Eigen::Index old_first = at_end ? 0 : static_cast<Eigen::Index>(m_new);
  Eigen::MatrixXd g_b = Eigen::MatrixXd::Zero(2 * n, landmark->size());
  for (int j = 0; j < samples; ++j) {
    const auto col = op->m.col(old_first + j);
    const CubicBSpline::Basis& bj = basis[static_cast<std::size_t>(j)];
    for (int a = 0; a < 4; ++a) {
      const Eigen::Index c = 2 * static_cast<Eigen::Index>(bj.first + static_cast<std::size_t>(a));
      for (Eigen::Index i = 0; i < n; ++i) {
        g_b(2 * i, c) += col(i) * bj.values[a];
        g_b(2 * i + 1, c + 1) += col(i) * bj.values[a];
      }
    }
  }
  Eigen::VectorXd g = g_b * ekf_.state().segment(landmark->index, landmark->size());
  std::vector<Eigen::Index> columns(m_new);
  for (std::size_t k = 0; k < m_new; ++k) {
    columns[k] =
        at_end ? samples + static_cast<Eigen::Index>(k) : static_cast<Eigen::Index>(m_new - 1 - k);
  }
  Eigen::MatrixXd g_r = Eigen::MatrixXd::Zero(2 * n, 3);
  const Eigen::MatrixXd g_z = AddBeamColumns(op->m, columns, b, &g, &g_r);
  const Eigen::MatrixXd q = g_z * RangeVariances(scan, beams).asDiagonal() * g_z.transpose();

  const Eigen::Index old_index = landmark->index, old_size = landmark->size();
  const Eigen::Index index = ekf_.ReplaceBlock(old_index, old_size, g, g_r, g_b, q);
  for (Landmark& l : splines_) {
    if (l.index > old_index) l.index -= old_size;
  }
  landmark->index = index;
  landmark->knots = op->knots;
  return true;
}

void EkfBSplineSlamOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Nested("odometry", "odometry noise model", &odometry);
  v.Nested("extraction", "curves from a scan", &extraction);
  v.Field("association", &association, "pedraza or curvature (paper 000)");
  v.Nested("association_options", "parameters of the association", &association_options);
  v.Nested("map_fit", "fit of map splines (their control points are the state)", &map_fit);
  v.Field("range_sigma_floor_m", &range_sigma_floor_m, "beam noise: sigma = floor + fraction r, m");
  v.Field("range_sigma_fraction", &range_sigma_fraction, "beam noise: fraction of the range");
  v.Field("model_sigma_m", &model_sigma_m, "model error added in quadrature, m");
  v.Field("beam_spacing_m", &beam_spacing_m, "beams of one correction at least this apart, m");
  v.Field("max_beams_per_match", &max_beams_per_match, "... and at most this many");
  v.Field("max_correspondence_distance_m", &max_correspondence_distance_m,
          "predicted and paired map points of a beam at most this apart, m");
  v.Field("beam_gate_probability", &beam_gate_probability, "beam innovation gate (1 dof)");
  v.Field("match_selection", &match_selection,
          "longest (the longest stretches first) or jcbb (the largest jointly compatible set)");
  v.Field("min_incidence_sine", &min_incidence_sine, "grazing beams below this sine are unused");
  v.Field("min_new_curve_length_m", &min_new_curve_length_m, "new curves at least, m");
  v.Field("min_new_curve_points", &min_new_curve_points, "new curves at least, points");
  v.Field("min_observations_to_add", &min_observations_to_add,
          "a candidate curve enters the map after this many sightings");
  v.Field("candidate_max_age_scans", &candidate_max_age_scans,
          "... none more than this many scans after the previous");
  v.Field("max_curve_range_m", &max_curve_range_m,
          "beams longer are not used for curves (0: all), m");
  v.Field("min_extension_length_m", &min_extension_length_m, "extensions at least, m");
  v.Field("end_tolerance_m", &end_tolerance_m, "a matched stretch reaches the end within, m");
  v.Field("extension_sample_spacing_m", &extension_sample_spacing_m,
          "old curve samples in an extension's refit, m apart");
  v.Field("control_point_sigma_floor_m", &control_point_sigma_floor_m,
          "sigma added to new control points, m");
}

}  // namespace splam::estimation
