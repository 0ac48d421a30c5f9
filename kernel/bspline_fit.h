#ifndef SPLAM_KERNEL_BSPLINE_FIT_H_
#define SPLAM_KERNEL_BSPLINE_FIT_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "kernel/bspline.h"
#include "kernel/options.h"
#include "kernel/status.h"

namespace splam::kernel {

struct BSplineFitOptions {
  // One control point per this much chord length of the data (the count grows with the
  // segment's length), metres. Smaller follows detail and noise more closely.
  double control_point_spacing_m = 0.25;
  int min_control_points = 4;   // >= 4 (a single cubic piece)
  int max_control_points = 64;  // cap for very long segments
  // At least this many distinct points per control point (but at least 4 control points), so
  // that the fit is a least-squares approximation, not an interpolation that rings between
  // sparse points.
  double points_per_control_point = 1.5;
  // A fit longer than this times the polyline through its points is refused: it rings (the
  // polyline is already longer than the curve it samples; a good fit is shorter still).
  double max_length_ratio = 2.0;
  // The chord-length parameters are measured along a moving average of 2 h + 1 points (h this
  // value), so that range noise does not inflate the length; 0 uses the raw points.
  int parameter_smoothing_half_window = 3;

  // Describes every field (key, unit, comment) to a visitor: the YAML form.
  void VisitFields(kernel::FieldVisitor& v);
  Status Validate() const;
};

// Least-squares cubic B-spline through ordered points D_0..D_m (paper 000 eq. 4, Piegl & Tiller
// §9.4.1): parameters t_k from chord length (of the smoothed points) normalised to [0, 1], clamped
// knots placed by de Boor's averaging so that every span holds data, and all control points
// minimising sum_k |C(t_k) - D_k|^2 (the curve's ends are fitted too, not pinned to noisy end
// points). The number of control points is round(chord length / spacing) + 1, clamped to
// [min_control_points, max_control_points] and to distinct / points_per_control_point (at least 4).
// Fails, saying why, for fewer than 4 points, non-finite points, fewer than 4
// distinct points along the chord (e.g. all points equal), or a curve longer than
// max_length_ratio times the points' polyline.
Result<CubicBSpline> FitCubicBSpline(const std::vector<Eigen::Vector2d>& points,
                                     const BSplineFitOptions& options = {});

// The fit as a linear operator, for propagating covariances (EKF-SLAM with B-splines, SPEC §8):
// with the parameters and knots of FitCubicBSpline, the control points are X_i = sum_k M(i, k) D_k
// (each coordinate alike), M = (N^T N)^-1 N^T, N(k, i) = N_i(t_k). The parameters depend on the
// points only through chord lengths; M treats them as fixed, as Pedraza et al. do.
struct BSplineFitOperator {
  std::vector<double> knots;  // control points + 4
  Eigen::MatrixXd m;          // control points x data points
};
Result<BSplineFitOperator> CubicBSplineFitOperator(const std::vector<Eigen::Vector2d>& points,
                                                   const BSplineFitOptions& options = {});

}  // namespace splam::kernel

#endif  // SPLAM_KERNEL_BSPLINE_FIT_H_
