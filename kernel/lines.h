#ifndef SPLAM_KERNEL_LINES_H_
#define SPLAM_KERNEL_LINES_H_

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "kernel/options.h"
#include "kernel/random.h"
#include "kernel/scan.h"
#include "kernel/segmentation.h"
#include "kernel/status.h"

namespace splam::kernel {

// A line in normal form x cos(theta) + y sin(theta) = rho, rho >= 0, theta in (-pi, pi]
// (paper 001 §3), with the extent of the points that support it.
struct LineFeature {
  double rho_m = 0.0;
  double theta_rad = 0.0;
  Eigen::Vector2d start = Eigen::Vector2d::Zero();  // projections of the first and last
  Eigen::Vector2d end = Eigen::Vector2d::Zero();    // supporting point (in beam order)
  // Covariance of (rho, theta) from the point noise (see LineCovariance).
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  std::vector<std::size_t> point_indices;  // supporting points, increasing

  Eigen::Vector2d Normal() const;     // (cos theta, sin theta)
  Eigen::Vector2d Direction() const;  // (-sin theta, cos theta)
  double Length() const { return (end - start).norm(); }
  // Signed distance of p from the line (positive on the side the normal points to).
  double SignedDistance(const Eigen::Vector2d& p) const { return Normal().dot(p) - rho_m; }
};

// Total least squares (paper 001 §3): the line through the centroid along the principal
// direction, minimising the sum of squared perpendicular distances. nullopt for fewer than two
// distinct points. start/end are the projections of the first and last point.
std::optional<LineFeature> FitLineTls(const std::vector<Eigen::Vector2d>& points);

// Covariance of the TLS line's (rho, theta), to first order, when point i is displaced across the
// line with variance sigma2[i] (independent points). With N points, s_i the position of point i
// along the line from the centroid c, S = sum s_i^2 and m = (-sin theta, cos theta) . c: the
// offset e of the line at the centroid and its angle have
//   var(e) = sum sigma2_i / N^2,  var(theta) = sum s_i^2 sigma2_i / S^2,
//   cov(e, theta) = sum s_i sigma2_i / (N S),
// and rho = e + m dtheta, so var(rho) = var(e) + 2 m cov(e, theta) + m^2 var(theta) and
// cov(rho, theta) = cov(e, theta) + m var(theta). Equal variances sigma^2 give the familiar
// sigma^2 / N + m^2 sigma^2 / S and sigma^2 / S.
Eigen::Matrix2d LineCovariance(const std::vector<Eigen::Vector2d>& points, const LineFeature& line,
                               const std::vector<double>& sigma2);

// Where two fitted lines meet at a sufficient angle (the corners of paper 003 §2.2).
struct LineCorner {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  std::size_t first_line = 0, second_line = 0;  // indices into LineExtraction::lines
  double angle_rad = 0.0;                       // angle between the two lines, in (0, pi/2]
  // Covariance of the position, propagated from the two lines' (rho, theta) covariances through
  // the intersection x = N^-1 (rho_1, rho_2), N = [n_1^T; n_2^T].
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
};

struct LineExtractionOptions {
  // Successive edge following: the scan is first split where consecutive points jump apart
  // (the Dietmayer test with this c0); RANSAC then runs inside each part.
  double sef_c0_m = 0.10;
  // Point noise model: sigma_i = range_sigma_m + range_sigma_fraction * r_i. The defaults cover
  // the LMS-200 (1 cm) and the URG-04LX (1 % of range).
  double range_sigma_m = 0.01;
  double range_sigma_fraction = 0.01;
  // A point supports a line when its distance is at most inlier_sigmas * sigma_i.
  double inlier_sigmas = 2.5;
  int ransac_iterations = 40;  // minimal samples (2 points) drawn per line
  int min_points = 8;          // consensus needed to accept a line
  double min_length_m = 0.25;  // shorter lines are dropped
  // Straightness: a line is kept only when the RMS distance of its points from it is at most
  // this many times the RMS of the point noise model; a chord of a curved wall is rejected.
  double max_residual_sigmas = 1.5;
  // A line's supporting points must be contiguous: consensus points farther apart than this
  // (along the scan) start another line.
  double max_point_gap_m = 0.25;
  // Corners: neighbouring lines (in beam order) that cross at an angle of at least this, at a
  // point within corner_max_distance_m of the facing end of each line.
  double corner_min_angle_rad = 0.5236;  // 30 deg
  double corner_max_distance_m = 0.3;
  std::uint64_t seed = 1;  // RANSAC's generator: the same seed gives the same lines

  // Describes every field (key, unit, comment) to a visitor: the YAML form.
  void VisitFields(kernel::FieldVisitor& v);
  Status Validate() const;
};

struct LineExtraction {
  std::vector<LineFeature> lines;  // in beam order; point indices refer to `points`
  std::vector<LineCorner> corners;
  std::vector<Eigen::Vector2d> points;  // the scan's hits, sensor frame
  std::vector<std::size_t> beams;       // their beam indices
};

// RANSAC over ordered points in the sensor frame with per-point range-noise variances sigma2
// (along the beam): repeatedly the largest contiguous consensus of a 2-point line, refit by TLS,
// is taken as a line and its points removed. Inliers are within inlier_sigmas * sigma of the
// line; the covariance and the straightness test use the noise across the line,
// sigma2 (n . u)^2 for the beam direction u.
std::vector<LineFeature> RansacLines(const std::vector<Eigen::Vector2d>& points,
                                     const std::vector<double>& sigma2,
                                     const LineExtractionOptions& options, Random* random);

// Lines and corners of a scan (SEF, then RANSAC with TLS refit in each part).
LineExtraction ExtractLines(const Scan& scan, const LineExtractionOptions& options = {});

}  // namespace splam::kernel

#endif  // SPLAM_KERNEL_LINES_H_
