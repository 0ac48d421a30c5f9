#include "kernel/spline_extraction.h"

#include "kernel/shapes.h"

namespace splam::kernel {

Status SplineExtractionOptions::Validate() const {
  if (Status s = FirstError(segmentation.Validate(), fit.Validate(), curvature.Validate(),
                            features.Validate());
      !s.ok())
    return s;
  // Finer than a millimetre a metre of curve is 10^3 samples and more; coarser than 1 m no
  // feature. The smoothing kernels span 6 sigma in samples, each applied at every sample: at
  // 0.1 mm samples a 5 cm sigma was 3,000 taps per sample, a hang over a scan's curves.
  if (!(epsilon_m >= 1e-3 && epsilon_m <= 1.0))
    return Status::Error("epsilon_m must be in [0.001, 1] m");
  if (!(curvature.sigma_m <= 1000.0 * epsilon_m))
    return Status::Error("curvature sigma_m must be at most 1000 samples (epsilon_m) wide");
  return Status::Ok();
}

Result<SplineCurve> ExtractCurve(const std::vector<Eigen::Vector2d>& points,
                                 const SplineExtractionOptions& options) {
  using R = Result<SplineCurve>;
  Result<CubicBSpline> spline = FitCubicBSpline(points, options.fit);
  if (!spline) return R::Fail(spline.error);
  const double polyline_m = PolylineLength(points);
  if (!(spline->Length() <= kMaxLengthRatio * polyline_m))
    return R::Fail("the fit is " + std::to_string(spline->Length()) + " m long, more than " +
                   std::to_string(kMaxLengthRatio) + " times its points' path of " +
                   std::to_string(polyline_m) + " m");
  SplineCurve curve = DescribeCurve(std::move(*spline), options);
  curve.points = points;
  return R::Ok(std::move(curve));
}

SplineCurve DescribeCurve(CubicBSpline spline, const SplineExtractionOptions& options) {
  std::vector<Eigen::Vector2d> samples = spline.ResampleByArcLength(options.epsilon_m);
  CurvatureProfile profile = ComputeCurvature(samples, options.epsilon_m, options.curvature);
  std::vector<CurveFeature> features = FindFeatures(profile, options.features);
  return SplineCurve{
      {}, {}, std::move(spline), std::move(samples), std::move(profile), std::move(features)};
}

SplineCurve Transformed(const SplineCurve& curve, const Pose2& a_T_b) {
  SplineCurve moved = curve;
  for (Eigen::Vector2d& p : moved.points) p = a_T_b * p;
  moved.spline = curve.spline.Transformed(a_T_b);
  for (Eigen::Vector2d& p : moved.samples) p = a_T_b * p;
  for (Eigen::Vector2d& p : moved.profile.smoothed) p = a_T_b * p;
  for (CurveFeature& f : moved.features) f.position = a_T_b * f.position;
  return moved;
}

std::vector<SplineCurve> ExtractCurves(const Scan& scan, const SplineExtractionOptions& options) {
  std::vector<SplineCurve> curves;
  for (ScanSegment& segment : SegmentScan(scan, options.segmentation)) {
    Result<SplineCurve> curve = ExtractCurve(segment.points, options);
    if (!curve) continue;  // degenerate segment (e.g. repeated points): nothing to fit
    curve->beams = std::move(segment.beams);
    curves.push_back(std::move(*curve));
  }
  return curves;
}

void SplineExtractionOptions::VisitFields(FieldVisitor& v) {
  v.Nested("segmentation", "scan -> segments", &segmentation);
  v.Nested("fit", "segment -> cubic B-spline", &fit);
  v.Field("epsilon_m", &epsilon_m, "curves are stored as points this far apart along the arc, m");
  v.Nested("curvature", "smoothing and curvature", &curvature);
  v.Nested("features", "inflection points and corners", &features);
}

}  // namespace splam::kernel
