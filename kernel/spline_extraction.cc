#include "kernel/spline_extraction.h"

namespace splam::kernel {

std::string SplineExtractionOptions::Validate() const {
  for (const std::string& problem :
       {segmentation.Validate(), fit.Validate(), curvature.Validate(), features.Validate()}) {
    if (!problem.empty()) return problem;
  }
  if (!(epsilon_m > 0.0)) return "epsilon_m must be positive";
  return "";
}

std::optional<SplineCurve> ExtractCurve(const std::vector<Eigen::Vector2d>& points,
                                        const SplineExtractionOptions& options,
                                        std::string* error) {
  std::optional<CubicBSpline> spline = FitCubicBSpline(points, options.fit, error);
  if (!spline) return std::nullopt;
  std::vector<Eigen::Vector2d> samples = spline->ResampleByArcLength(options.epsilon_m);
  CurvatureProfile profile = ComputeCurvature(samples, options.epsilon_m, options.curvature);
  std::vector<CurveFeature> features = FindFeatures(profile, options.features);
  return SplineCurve{
      points, {}, std::move(*spline), std::move(samples), std::move(profile), std::move(features)};
}

std::vector<SplineCurve> ExtractCurves(const Scan& scan, const SplineExtractionOptions& options) {
  std::vector<SplineCurve> curves;
  for (ScanSegment& segment : SegmentScan(scan, options.segmentation)) {
    std::optional<SplineCurve> curve = ExtractCurve(segment.points, options);
    if (!curve) continue;  // degenerate segment (e.g. repeated points): nothing to fit
    curve->beams = std::move(segment.beams);
    curves.push_back(std::move(*curve));
  }
  return curves;
}

}  // namespace splam::kernel
