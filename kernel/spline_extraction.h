#ifndef SPLAM_KERNEL_SPLINE_EXTRACTION_H_
#define SPLAM_KERNEL_SPLINE_EXTRACTION_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "kernel/bspline.h"
#include "kernel/bspline_fit.h"
#include "kernel/curvature.h"
#include "kernel/curve_features.h"
#include "kernel/options.h"
#include "kernel/scan.h"
#include "kernel/segmentation.h"
#include "kernel/status.h"

namespace splam::kernel {

// Everything from a scan to curves with features (papers 000 and 003): segmentation, B-spline
// fit, resampling at equal arc length, smoothing, curvature, features. The defaults work for
// the URG-04LX and the LMS-200.
struct SplineExtractionOptions {
  SegmentationOptions segmentation;
  BSplineFitOptions fit;
  // Every curve is stored as points epsilon apart along its arc length (resolution
  // invariance, paper 000 eq. 10), metres.
  double epsilon_m = 0.01;
  CurvatureOptions curvature;
  FeatureOptions features;

  // Describes every field (key, unit, comment) to a visitor: the YAML form.
  void VisitFields(kernel::FieldVisitor& v);
  Status Validate() const;
};

// One observed obstacle outline.
struct SplineCurve {
  std::vector<Eigen::Vector2d> points;  // the segment's measured points
  std::vector<std::size_t> beams;       // their beam indices (empty when not from a scan)
  CubicBSpline spline;
  std::vector<Eigen::Vector2d> samples;  // spline points epsilon apart along the arc length
  CurvatureProfile profile;              // smoothed samples and their curvature
  std::vector<CurveFeature> features;
};

// The curve of one ordered run of points (any frame); nullopt, with *error, when the points do
// not make a curve (fewer than 4, all equal, not finite) or the fit is more than
// kMaxLengthRatio times longer than the polyline through them (a fit that diverged, e.g. on the
// points of a scan whose beams wrap past a full turn: its samples once asked for 26 GB).
inline constexpr double kMaxLengthRatio = 10.0;
Result<SplineCurve> ExtractCurve(const std::vector<Eigen::Vector2d>& points,
                                 const SplineExtractionOptions& options = {});

// The samples, curvature profile and features of a given spline (e.g. a map curve); `points`
// and `beams` stay empty.
SplineCurve DescribeCurve(CubicBSpline spline, const SplineExtractionOptions& options = {});

// The curve moved by a_T_b (given in frame b, returned in frame a). Curvature and features are
// invariant under rigid motion, so nothing is recomputed.
SplineCurve Transformed(const SplineCurve& curve, const Pose2& a_T_b);

// The curves of every segment of a scan, in the sensor frame, in beam order.
std::vector<SplineCurve> ExtractCurves(const Scan& scan,
                                       const SplineExtractionOptions& options = {});

}  // namespace splam::kernel

#endif  // SPLAM_KERNEL_SPLINE_EXTRACTION_H_
