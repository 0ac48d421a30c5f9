#include "estimation/topological/topological_slam.h"

#include "kernel/angle.h"

namespace splam::estimation {

kernel::Status TopologicalSlamOptions::Validate() const {
  if (kernel::Status e = extraction.Validate(); !e.ok()) return e;
  if (kernel::Status e = association.Validate(); !e.ok()) return e;
  if (!(max_curve_range_m >= 0.0)) return kernel::Status::Error("max_curve_range_m must be >= 0");
  if (!(region_margin_m >= 0.0 && region_margin_m <= 100.0) || !region.Validate().ok())
    return kernel::Status::Error(
        "the local region needs a margin in [0, 100] m, a radius in (0, 30] m and 0 < alpha < 1");
  if (!(min_information >= 0.0)) return kernel::Status::Error("min_information must be >= 0");
  // Weights are 1 / sigma^2: 1e308 m underflowed them and the solve returned NaN; 1e-300 m
  // squared is zero, and the fusion divided by it (a NaN pose, the option fuzzer).
  if (!(point_sigma_m >= 1e-6 && point_sigma_m <= 10.0))
    return kernel::Status::Error("point_sigma_m must be in [1e-6, 10] m");
  if (kernel::Status e = odometry.Validate(); !e.ok()) return e;
  if (prediction == TopologicalPrediction::kScanMatching) {
    if (kernel::Status e = scan_matching.Validate(); !e.ok()) return e.Prefixed("scan_matching");
    // 1.8e200 squared is infinite: the prediction's covariance, then the pose, became NaN.
    if (!(scan_matching_noise_scale > 0.0 && scan_matching_noise_scale <= 100.0))
      return kernel::Status::Error("scan_matching_noise_scale must be in (0, 100]");
  }
  if (correction_rounds < 1 || correction_rounds > 100)
    return kernel::Status::Error("correction_rounds must be in [1, 100]");
  if (!(correction_gain > 0.0 && correction_gain <= 1.0))
    return kernel::Status::Error("correction_gain must be in (0, 1]");
  // point_spacing_m: 0 (the fit's spacing) or at least a millimetre: 1e-20 m put 10^20 points
  // on a metre of curve.
  if (!(end_trim_m >= 0.0 && end_trim_m <= 100.0) ||
      !(min_chord_length_m > 0.0 && min_chord_length_m <= 100.0) ||
      !(point_spacing_m == 0.0 || (point_spacing_m >= 1e-3 && point_spacing_m <= 10.0)))
    return kernel::Status::Error(
        "end_trim_m must be in [0, 100] m, min_chord_length_m in (0, 100] m and point_spacing_m "
        "0 or in [0.001, 10] m");
  // A weight of 1e308 made the correction's cost infinite and its pose NaN (UBSan).
  const auto weight = [](double w) { return w > 0.0 && w <= 1000.0; };
  if (!weight(feature_weight) || !weight(line_weight) || !weight(curve_weight) ||
      !(line_flatness_m >= 0.0 && line_flatness_m <= 10.0))
    return kernel::Status::Error(
        "reliability weights must be in (0, 1000] and line_flatness_m in [0, 10] m");
  if (!(loss.heading_scale_rad > 0.0 && loss.heading_scale_rad <= 10.0) ||
      !(loss.translation_scale_m > 0.0 && loss.translation_scale_m <= 100.0))
    return kernel::Status::Error("loss scales must be in (0, 10] rad and (0, 100] m");
  if (!(verify_threshold_m > 0.0) || !(max_heading_correction_rad > 0.0) ||
      !(max_translation_correction_m > 0.0))
    return kernel::Status::Error("verify_threshold_m and the correction bounds must be positive");
  if (!(map_update_distance_m >= 0.0) || !(map_update_angle_rad >= 0.0))
    return kernel::Status::Error("map update thresholds must be >= 0");
  if (!(min_new_curve_length_m >= 0.0) || min_new_curve_points < 4)
    return kernel::Status::Error("new curves need a length >= 0 and at least 4 points");
  if (!(min_extension_length_m > 0.0) || !(end_tolerance_m >= 0.0) || max_control_points < 4)
    return kernel::Status::Error("bad extension thresholds");
  if (dense_min_points < 3 || !(dense_max_angle_rad > 0.0))
    return kernel::Status::Error("dense_min_points must be >= 3 and dense_max_angle_rad positive");
  // The curve index is walked cell by cell over the region: cells of a micrometre, or a region
  // of kilometres, would be 10^12 cells.
  if (!(index_cell_m >= 0.01 && index_cell_m <= 100.0))
    return kernel::Status::Error("index_cell_m must be in [0.01, 100] m");
  return kernel::Status::Ok();
}

GraphSlamOptions TopologicalSlamOptions::ScanMatchingDefaults() {
  GraphSlamOptions o;
  o.loop.enabled = false;
  return o;
}

void TopologicalSlamOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Nested("extraction", "curves from a scan", &extraction);
  v.Nested("association", "curvature association", &association);
  v.Field("max_curve_range_m", &max_curve_range_m,
          "beams longer are not used for curves (0: all), m");
  v.Field("region_margin_m", &region_margin_m, "local region widened by this margin, m");
  // `region` is the explorer's r and alpha: set once, in the local_region section (see
  // SlamContext).
  int prediction_source = static_cast<int>(prediction);
  v.Choice("prediction", &prediction_source, {"scan_matching", "odometry"},
           "odometry refined by scan-to-submap registration, or the odometry (paper 003)");
  prediction = static_cast<TopologicalPrediction>(prediction_source);
  v.Nested("scan_matching", "scan_matching: the graph SLAM's front end (loop closure off)",
           &scan_matching);
  v.Field("scan_matching_noise_scale", &scan_matching_noise_scale,
          "scan_matching: the prediction's sigmas, as a fraction of the odometry model's");
  v.Field("scan_matching_feedback", &scan_matching_feedback,
          "scan_matching: the front end's keyframes at the corrected poses");
  int method = static_cast<int>(correction);
  v.Choice("correction", &method, {"point_to_curve", "paper"},
           "heading and position from point-to-curve distances, or paper 003's chords then "
           "points");
  correction = static_cast<TopologicalCorrection>(method);
  v.Field("min_information", &min_information,
          "point_to_curve: directions constrained by fewer points' worth are not corrected");
  v.Field("point_sigma_m", &point_sigma_m,
          "point_to_curve: sigma of a point's distance to its map curve, m");
  v.Nested("odometry", "point_to_curve: odometry noise of the pose covariance", &odometry);
  v.Field("correction_rounds", &correction_rounds, "associate-correct rounds per scan");
  v.Field("end_trim_m", &end_trim_m, "ends of a matched stretch taken this far inside, m");
  v.Field("min_chord_length_m", &min_chord_length_m, "shorter chords give no heading, m");
  v.Field("point_spacing_m", &point_spacing_m,
          "translation pairs points this far apart along a stretch (0: end points only), m");
  v.Field("feature_weight", &feature_weight, "reliability C_i of curves with paired features");
  v.Field("line_weight", &line_weight, "reliability C_i of straight stretches");
  v.Field("curve_weight", &curve_weight, "reliability C_i of smooth curves");
  v.Field("line_flatness_m", &line_flatness_m, "a stretch is straight within, m");
  v.Nested("loss", "robust loss of the corrections", &loss);
  v.Field("correction_gain", &correction_gain, "fraction of a verified correction applied");
  v.Field("max_heading_correction_rad", &max_heading_correction_rad,
          "larger heading corrections fail verification, rad");
  v.Field("max_translation_correction_m", &max_translation_correction_m,
          "larger translation corrections fail verification, m");
  v.Field("verify_threshold_m", &verify_threshold_m,
          "VERIFY_LOCALIZATION: matched points within this of their map curve, m");
  v.Field("min_verified_curves", &min_verified_curves, "a localisation verifies this many curves");
  v.Field("verify_rms_m", &verify_rms_m, "... with an RMS distance under this (0: unchecked), m");
  v.Field("verify_improves", &verify_improves,
          "... and closer to the map than at the prediction (false: paper 003's test)");
  v.Field("dense_refinement", &dense_refinement,
          "point_to_curve: every observed curve's points refine the pose against the local map");
  v.Field("dense_min_points", &dense_min_points, "... standing when this many points pair");
  v.Field("dense_max_angle_rad", &dense_max_angle_rad,
          "... with a map curve whose tangent is within this of theirs, rad");
  v.Field("map_update_distance_m", &map_update_distance_m,
          "map extended after this much motion, m");
  v.Field("map_update_angle_rad", &map_update_angle_rad, "... or this much turning, rad");
  v.Field("min_new_curve_length_m", &min_new_curve_length_m, "new objects at least, m");
  v.Field("min_new_curve_points", &min_new_curve_points, "new objects at least, points");
  v.Field("min_extension_length_m", &min_extension_length_m, "splices continue at least, m");
  v.Field("end_tolerance_m", &end_tolerance_m, "a matched stretch reaches the end within, m");
  v.Field("max_control_points", &max_control_points, "a map curve stops growing here");
  v.Field("index_cell_m", &index_cell_m, "cell side of the grid that indexes map curves, m");
}

}  // namespace splam::estimation
