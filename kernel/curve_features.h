#ifndef SPLAM_KERNEL_CURVE_FEATURES_H_
#define SPLAM_KERNEL_CURVE_FEATURES_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "kernel/curvature.h"
#include "kernel/options.h"
#include "kernel/status.h"

namespace splam::kernel {

enum class FeatureType { kInflection, kCorner };

// A distinguished point of a curve (paper 000 §3.2).
struct CurveFeature {
  FeatureType type = FeatureType::kInflection;
  std::size_t index = 0;                               // sample index in the CurvatureProfile
  double arc_length_m = 0.0;                           // index * epsilon from the curve's start
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  // on the smoothed curve
  // Corners: the signed curvature at the corner. Inflections: the largest |k| of the weaker of
  // the two lobes it separates, signed like the lobe after it (how pronounced the S is).
  double curvature = 0.0;
  double angle_rad = 0.0;  // corners: angle between the two arms (pi for a straight line)
};

struct FeatureOptions {
  // Inflection points are sign changes of the curvature between two lobes. A lobe is a stretch
  // of one sign; it ends only where |k| exceeds this dead band with the other sign (hysteresis
  // against noise around zero), 1/m.
  double inflection_dead_band = 0.4;
  // Each of the two lobes must reach this |k| (a noise floor: a straight noisy wall wiggles
  // below it), 1/m ...
  double inflection_min_curvature = 0.5;
  // ... and that each turn the tangent by at least this much (integral of |k| over the lobe).
  // Range noise of 1 % at 3.5 m makes lobes that turn by up to about 0.45 rad; the lobes of
  // real curved obstacles turn by 1 rad and more.
  double inflection_min_turn_rad = 0.5;

  // Corners after He & Yung 2008: candidates are local maxima of |k| above a global floor ...
  double corner_min_curvature = 4.0;  // 1/m: sharper than a 0.25 m radius
  // ... kept when |k| >= ratio x the mean |k| over the region of support (ROS: between the
  // neighbouring minima of |k|), which rejects round corners ...
  double corner_ratio = 1.5;
  // ... and when the angle between the two arms, measured over the ROS (at most
  // corner_arm_length_m along each side), is at most this (false corners are nearly flat).
  double corner_max_angle_rad = 2.7925268;  // 160 deg
  double corner_arm_length_m = 0.3;
  // Corners closer than this to a curve end are ignored: the last span of a fitted B-spline is
  // loosely constrained and bends with the noise of the last few points.
  double corner_end_margin_m = 0.15;
  // Paper 000: trust only corners that have an inflection point on each side. Off by default:
  // a plain L-shaped wall has no inflection points, and its corner is the most useful feature.
  bool corners_need_inflection_bounds = false;

  // Describes every field (key, unit, comment) to a visitor: the YAML form.
  void VisitFields(kernel::FieldVisitor& v);
  Status Validate() const;
};

// Inflection points and corners of a profile, in order of arc length.
std::vector<CurveFeature> FindFeatures(const CurvatureProfile& profile,
                                       const FeatureOptions& options = {});

}  // namespace splam::kernel

#endif  // SPLAM_KERNEL_CURVE_FEATURES_H_
