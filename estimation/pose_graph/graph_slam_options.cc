#include "estimation/pose_graph/graph_slam_options.h"

#include <algorithm>
#include <string>
#include <utility>

#include "kernel/angle.h"

namespace splam::estimation {

RegistrationOptions LoopClosureOptions::RegistrationDefaults() {
  RegistrationOptions o;
  // The correlative search is within a cell and an angular step: a weak prior around it.
  o.prior_sigma_m = 0.1;
  o.prior_sigma_rad = 0.05;
  o.min_inlier_fraction = 0.6;
  o.max_correction_m = 0.2;
  o.max_correction_rad = 0.1;
  return o;
}

void EdgeModel::VisitFields(kernel::FieldVisitor& v) {
  v.Field("sigma_m", &sigma_m, "position sigma: base, m");
  v.Field("per_m", &per_m, "position sigma: per metre travelled");
  v.Field("sigma_rad", &sigma_rad, "heading sigma: base, rad");
  v.Field("per_rad", &per_rad, "heading sigma: per radian turned");
}

kernel::Status EdgeModel::Validate() const {
  if (!(sigma_m > 0) || !(sigma_rad > 0) || !(per_m >= 0) || !(per_rad >= 0))
    return kernel::Status::Error("the base sigmas must be positive, the growths >= 0");
  return kernel::Status::Ok();
}

void FrontEndOptions::Advanced::VisitFields(kernel::FieldVisitor& v) {
  v.Field("submap_insert_keyframes", &submap_insert_keyframes,
          "new keyframes inserted into the submap before it is built anew (0: anew every time)");
  v.Field("raster_curves", &raster_curves, "rasterise the curves' samples");
  v.Field("raster_points", &raster_points, "rasterise the scan points");
  v.Field("line_tolerance_m", &line_tolerance_m,
          "farther neighbours on a line with a third within this are one outline (0: off), m");
  v.Field("signed_distance", &signed_distance, "signed distance (needs smooth outlines)");
  v.Field("mask_unseen", &mask_unseen, "points where the submap's scans never saw are ignored");
  v.Field("seen_margin_m", &seen_margin_m, "a scan saw this far behind its hits, m");
  v.Field("odometry_outlier_probability", &odometry_outlier_probability,
          "prior probability that a scan's odometry increment is an outlier (a slip)");
  v.Field("recovery_step_rad", &recovery_step_rad, "heading step of the recovery search, rad");
  v.Field("recovery_sigma_m", &recovery_sigma_m, "likelihood sigma of the recovery search, m");
  v.Field("recovery_ambiguity_ratio", &recovery_ambiguity_ratio,
          "a recovery is refused when a distinct pose scores this fraction of the best");
  v.Field("recovery_tell_apart_alpha", &recovery_tell_apart_alpha,
          "... unless the points fitting only one of the two favour the best at this "
          "significance (sign test; 0: never)");
  v.Field("verify_misfit_fraction", &verify_misfit_fraction,
          "a registration with more of its points contradicting the submap is checked by the "
          "recovery search (1: never)");
  v.Field("robust_recovery_edges", &robust_recovery_edges,
          "the keyframe edge across a recovered scan gets the closures' robust loss");
}

kernel::Status FrontEndOptions::Advanced::Validate() const {
  if (submap_insert_keyframes < 0 || submap_insert_keyframes > 1000)
    return kernel::Status::Error("submap_insert_keyframes in [0, 1000]");
  if (!(seen_margin_m >= 0) || !(line_tolerance_m >= 0))
    return kernel::Status::Error("seen_margin_m and line_tolerance_m must be >= 0");
  if (!(odometry_outlier_probability > 0 && odometry_outlier_probability < 1))
    return kernel::Status::Error("odometry_outlier_probability must be in (0, 1)");
  if (!(recovery_step_rad > 0 && recovery_step_rad <= kernel::kPi) || !(recovery_sigma_m > 0) ||
      !(recovery_ambiguity_ratio > 0 && recovery_ambiguity_ratio <= 1) ||
      !(recovery_tell_apart_alpha >= 0 && recovery_tell_apart_alpha <= 1))
    return kernel::Status::Error(
        "recovery_step_rad must be in (0, pi], recovery_sigma_m positive, "
        "recovery_ambiguity_ratio in (0, 1] and recovery_tell_apart_alpha in [0, 1]");
  if (!(verify_misfit_fraction >= 0 && verify_misfit_fraction <= 1))
    return kernel::Status::Error("verify_misfit_fraction must be in [0, 1]");
  return kernel::Status::Ok();
}

void FrontEndOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Nested("extraction", "curves of every keyframe", &extraction);
  v.Field("max_range_m", &max_range_m, "beams longer are not used (0: the laser's maximum), m");
  v.Field("keyframe_distance_m", &keyframe_distance_m, "a keyframe every this much travel, m");
  v.Field("keyframe_angle_rad", &keyframe_angle_rad, "or this much turn, rad");
  v.Field("submap_keyframes", &submap_keyframes, "keyframes in the registration submap");
  v.Field("grid_resolution_m", &grid_resolution_m, "distance field cell size, in [0.01, 1] m");
  v.Field("truncation_m", &truncation_m, "distance field truncation, at most 10 m");
  v.Field("normal_max_gap_m", &normal_max_gap_m,
          "a scan point's normal from neighbours at most this far, m");
  v.Nested("moving", "moving objects left out", &moving);
  v.Field("moving_keyframes", &moving_keyframes,
          "each scan is compared with this many last keyframes' scans");
  v.Nested("registration", "scan-to-submap registration", &registration);
  v.Field("odometry_prior", &odometry_prior, "the registration's prior is the odometry model");
  v.Nested("odometry", "odometry noise model of that prior", &odometry);
  v.Field("recovery_window_m", &recovery_window_m,
          "a failed registration is searched again within this of the odometry (0: never), m");
  v.Field("recovery_window_rad", &recovery_window_rad, "and within this heading, rad");
  v.Nested("edge", "the edge between consecutive keyframes", &edge);
  v.Field("map_spacing_m", &map_spacing_m, "map curves from keyframes this far apart, m");
  v.Field("map_spacing_rad", &map_spacing_rad, "or turned this much from each other, rad");
  v.Nested("advanced", "knobs to tune, switches for comparisons", &advanced);
}

kernel::Status FrontEndOptions::Validate() const {
  if (kernel::Status e = kernel::FirstError(extraction.Validate(), registration.Validate(),
                                            odometry.Validate(), moving.Validate());
      !e.ok())
    return e;
  if (kernel::Status e = edge.Validate(); !e.ok()) return e.Prefixed("edge");
  if (kernel::Status e = advanced.Validate(); !e.ok()) return e.Prefixed("advanced");
  if (!(max_range_m >= 0) || !(keyframe_distance_m > 0) || !(keyframe_angle_rad > 0))
    return kernel::Status::Error("max_range_m >= 0, keyframe distance and angle > 0");
  if (!(normal_max_gap_m > 0)) return kernel::Status::Error("normal_max_gap_m must be positive");
  if (moving_keyframes < 0 || moving_keyframes > 1000)
    return kernel::Status::Error("moving_keyframes in [0, 1000]");
  if (submap_keyframes < 1 || !(grid_resolution_m >= 0.01 && grid_resolution_m <= 1) ||
      !(truncation_m > grid_resolution_m && truncation_m <= 10))
    return kernel::Status::Error(
        "submap_keyframes >= 1, grid_resolution_m in [0.01, 1] m, truncation_m above it and at "
        "most 10 m");
  if (!(recovery_window_m >= 0 && recovery_window_m <= 100) ||
      !(recovery_window_rad >= 0 && recovery_window_rad <= kernel::kPi))
    return kernel::Status::Error(
        "recovery_window_m must be in [0, 100] and recovery_window_rad in [0, pi]");
  if (!(map_spacing_m >= 0) || !(map_spacing_rad >= 0))
    return kernel::Status::Error("map spacings must be >= 0");
  return kernel::Status::Ok();
}

void LoopClosureOptions::Advanced::VisitFields(kernel::FieldVisitor& v) {
  v.Field("reach_m", &reach_m,
          "wide search: a candidate this far from the query still sees the same walls (added to "
          "the uncertainty when choosing candidates), m");
  v.Field("candidate_sigmas", &candidate_sigmas,
          "wide search: candidates and windows within this many standard deviations of the "
          "graph's relative uncertainty");
  v.Field("wide_window_ratio", &wide_window_ratio,
          "wide search: only when its window is this many times as wide as the first");
  v.Field("stride_window_m", &stride_window_m,
          "wide search: a window of w m is searched every ceil(w / this) keyframes, m");
  v.Field("levels", &levels, "correlative search resolution levels");
  v.Field("tell_apart_alpha", &tell_apart_alpha,
          "an ambiguous closure stands when the points fitting only one of the two poses favour "
          "the best at this significance (sign test; 0: never)");
  v.Field("max_misfit_fraction", &max_misfit_fraction,
          "closure test: fraction of the query's points where the target saw free space, away "
          "from its outline, at most");
  v.Field("seen_free_score", &seen_free_score,
          "correlative score of a point where the target's returning beams passed, three cells or "
          "more from its outline (in [-10, 0]; 0: as where it never looked)");
  v.Field("truncation_m", &truncation_m, "loop target field truncation, at most 10 m");
  v.Field("seen_margin_m", &seen_margin_m, "a target's scan saw this far behind its hits, m");
  v.Field("normal_max_gap_m", &normal_max_gap_m,
          "a query point's normal from neighbours at most this far, m");
}

kernel::Status LoopClosureOptions::Advanced::Validate() const {
  if (levels < 1 || levels > 8) return kernel::Status::Error("levels must be in [1, 8]");
  if (!(reach_m > 0) || !(candidate_sigmas > 0) || !(wide_window_ratio >= 1) ||
      !(stride_window_m > 0))
    return kernel::Status::Error(
        "reach_m, candidate_sigmas and stride_window_m must be positive, wide_window_ratio >= 1");
  if (!(tell_apart_alpha >= 0 && tell_apart_alpha <= 1))
    return kernel::Status::Error("tell_apart_alpha must be in [0, 1]");
  if (!(max_misfit_fraction >= 0 && max_misfit_fraction <= 1))
    return kernel::Status::Error("max_misfit_fraction must be in [0, 1]");
  if (!(seen_free_score >= -10 && seen_free_score <= 0))
    return kernel::Status::Error("seen_free_score must be in [-10, 0]");
  if (!(truncation_m <= 10) || !(seen_margin_m >= 0) || !(normal_max_gap_m > 0))
    return kernel::Status::Error(
        "truncation_m at most 10 m, seen_margin_m >= 0, normal_max_gap_m > 0");
  return kernel::Status::Ok();
}

void LoopClosureOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Field("enabled", &enabled, "search for loop closures");
  v.Field("min_gap_keyframes", &min_gap_keyframes,
          "candidates are at least this many keyframes older");
  v.Field("radius_m", &radius_m, "candidate radius right after a closure, m");
  v.Field("radius_per_m", &radius_per_m,
          "candidate radius growth per metre travelled since the last closure");
  v.Field("max_radius_m", &max_radius_m, "candidate radius at most, m");
  v.Field("candidates", &candidates, "candidates searched per keyframe");
  v.Field("near_window_m", &near_window_m, "first search window half-width at most, m");
  v.Field("window_rad", &window_rad, "search heading half-width after a closure, rad");
  v.Field("window_rad_per_m", &window_rad_per_m,
          "heading half-width growth per metre travelled, rad/m");
  v.Field("max_window_rad", &max_window_rad, "heading half-width at most, rad");
  v.Field("max_window_m", &max_window_m, "wide search: window half-width at most, m");
  v.Field("query_keyframes", &query_keyframes, "query: the new keyframe and this many before it");
  v.Field("target_keyframes", &target_keyframes,
          "target: the candidate and this many keyframes either side");
  v.Field("resolution_m", &resolution_m, "loop search grid cell size, in [0.01, 1] m");
  v.Field("sigma_m", &sigma_m, "correlative likelihood sigma, m");
  v.Field("min_score", &min_score, "closure test: correlative score at least");
  v.Field("min_overlap", &min_overlap,
          "closure test: fraction of the query's points where the target has seen, at least");
  v.Field("ambiguity_ratio", &ambiguity_ratio,
          "closure refused when a distinct pose scores this fraction of the best");
  v.Field("max_rms_m", &max_rms_m, "closure test: registration inlier RMS at most, m");
  v.Field("confirm_keyframes", &confirm_keyframes,
          "a closure that moves the graph waits this many keyframes for another that agrees (0: "
          "none needed)");
  v.Field("max_chi2", &max_chi2,
          "two closures, or a closure and the graph, agree when their whitened squared "
          "difference is at most this");
  v.Nested("registration", "fine registration of a closure", &registration);
  v.Field("sigma_floor_m", &sigma_floor_m, "closure edge sigma floor, m");
  v.Field("sigma_floor_rad", &sigma_floor_rad, "closure edge sigma floor, rad");
  v.Field("optimize_every_keyframes", &optimize_every_keyframes,
          "closures found go to the back end together this many keyframes after the first");
  v.Field("background_search", &background_search,
          "search on a second thread beside the front end (same result either way)");
  v.Nested("advanced", "knobs to tune", &advanced);
  for (const char* key : {"reach_m", "candidate_sigmas", "wide_window_ratio", "stride_window_m",
                          "levels", "tell_apart_alpha", "max_misfit_fraction", "seen_free_score"})
    v.Moved(key, std::string("advanced.") + key);
}

kernel::Status LoopClosureOptions::Validate() const {
  if (kernel::Status e = registration.Validate(); !e.ok()) return e;
  if (kernel::Status e = advanced.Validate(); !e.ok()) return e.Prefixed("advanced");
  if (min_gap_keyframes < 1 || candidates < 1 || query_keyframes < 0 || target_keyframes < 0 ||
      confirm_keyframes < 0 || optimize_every_keyframes < 0)
    return kernel::Status::Error("min_gap_keyframes, candidates >= 1; keyframe counts >= 0");
  if (!(radius_m > 0) || !(radius_per_m >= 0) || !(max_radius_m >= radius_m) ||
      !(near_window_m > 0) || !(max_window_m >= near_window_m) || !(window_rad >= 0) ||
      !(window_rad_per_m >= 0) || !(max_window_rad >= window_rad) || !(sigma_m > 0) ||
      !(max_window_m <= 1000) || !(max_window_rad <= kernel::kPi))
    return kernel::Status::Error(
        "loop radii, windows and sigma must be positive and ordered, max_window_m at most 1000, "
        "max_window_rad at most pi");
  // Cells finer than a centimetre resolve nothing a laser measures and make the grid huge.
  if (!(resolution_m >= 0.01 && resolution_m <= 1))
    return kernel::Status::Error("loop resolution_m must be in [0.01, 1] m");
  if (!(advanced.truncation_m > resolution_m))
    return kernel::Status::Error("advanced.truncation_m must exceed resolution_m");
  if (!(min_score > 0 && min_score <= 1) || !(min_overlap > 0 && min_overlap <= 1) ||
      !(ambiguity_ratio > 0 && ambiguity_ratio <= 1) || !(max_rms_m > 0) || !(max_chi2 > 0) ||
      !(sigma_floor_m > 0) || !(sigma_floor_rad > 0))
    return kernel::Status::Error("loop tests: score and ratio in (0, 1], bounds positive");
  return kernel::Status::Ok();
}

void BackEndOptions::Advanced::VisitFields(kernel::FieldVisitor& v) {
  v.Field("deferred_optimization_fraction", &deferred_optimization_fraction,
          "closures that agree with the graph wait for its whole optimisation until it has grown "
          "by this fraction since the last (0: every flush optimises it whole)");
  v.Field("local_optimization_keyframes", &local_optimization_keyframes,
          "closures that wait optimise only this many last keyframes meanwhile (0: none)");
}

kernel::Status BackEndOptions::Advanced::Validate() const {
  if (!(deferred_optimization_fraction >= 0 && deferred_optimization_fraction <= 10))
    return kernel::Status::Error("deferred_optimization_fraction must be in [0, 10]");
  if (local_optimization_keyframes < 0)
    return kernel::Status::Error("local_optimization_keyframes must be >= 0");
  return kernel::Status::Ok();
}

void BackEndOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Nested("pose_graph", "pose-graph optimisation", &pose_graph);
  v.Field("max_chi2", &max_chi2,
          "a closure agrees with the graph when its whitened squared residual is at most this; "
          "after an optimisation those that do not are removed");
  v.Field("trim_spacing_m", &trim_spacing_m,
          "an old keyframe this close to an earlier one keeps only its pose (0: never), m");
  v.Field("trim_spacing_rad", &trim_spacing_rad, "and turned less than this from it, rad");
  v.Field("merge_trimmed_keyframes", &merge_trimmed_keyframes,
          "merge a trimmed keyframe's node into the earlier one beside it, so that the graph "
          "follows the map");
  v.Nested("advanced", "knobs to tune", &advanced);
}

kernel::Status BackEndOptions::Validate() const {
  if (kernel::Status e = pose_graph.Validate(); !e.ok()) return e;
  if (kernel::Status e = advanced.Validate(); !e.ok()) return e.Prefixed("advanced");
  if (!(max_chi2 > 0)) return kernel::Status::Error("max_chi2 must be positive");
  if (!(trim_spacing_m >= 0) || !(trim_spacing_rad >= 0))
    return kernel::Status::Error("trim spacings must be >= 0");
  return kernel::Status::Ok();
}

void GlobalLocalizationOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Field("max_range_m", &max_range_m, "the query's points within this range, m");
  v.Field("resolution_m", &resolution_m, "the map field's cell size, in [0.01, 1] m");
  v.Field("sigma_m", &sigma_m, "likelihood sigma, m");
  v.Field("levels", &levels, "resolution levels of the search");
  v.Field("seen_free_score", &seen_free_score,
          "score of a point where the map's returning beams passed, away from an outline (in "
          "[-10, 0])");
  v.Field("min_score", &min_score, "accepted: the best pose's mean likelihood at least");
  v.Field("ambiguity_ratio", &ambiguity_ratio,
          "refused when a distinct pose scores this fraction of the best");
  v.Field("tell_apart_alpha", &tell_apart_alpha,
          "... unless the points fitting only one of the two favour the best at this "
          "significance (sign test; 0: never)");
}

kernel::Status GlobalLocalizationOptions::Validate() const {
  if (!(max_range_m > 0 && max_range_m <= 100) || !(resolution_m >= 0.01 && resolution_m <= 1) ||
      !(sigma_m > 0) || levels < 1 || levels > 8 ||
      !(seen_free_score >= -10 && seen_free_score <= 0))
    return kernel::Status::Error(
        "global localisation: max_range_m in (0, 100], resolution_m in [0.01, 1] m, sigma_m "
        "positive, levels in [1, 8], seen_free_score in [-10, 0]");
  if (!(min_score > 0 && min_score <= 1) || !(ambiguity_ratio > 0 && ambiguity_ratio <= 1) ||
      !(tell_apart_alpha >= 0 && tell_apart_alpha <= 1))
    return kernel::Status::Error(
        "global localisation: min_score and ambiguity_ratio in (0, 1], tell_apart_alpha in "
        "[0, 1]");
  return kernel::Status::Ok();
}

void MapLocalizationOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Field("map_radius_m", &map_radius_m,
          "the field registered against holds the map scans within this distance, m");
  v.Field("rebuild_distance_m", &rebuild_distance_m,
          "built anew once the robot is this far from where it was built, m");
  v.Field("initial_window_m", &initial_window_m,
          "the first scan is searched for within this distance of the start pose, m");
  v.Field("initial_window_rad", &initial_window_rad, "and this angle of its heading, rad");
  v.Field("sigma_m", &sigma_m, "likelihood sigma of that search, m");
  v.Field("levels", &levels, "resolution levels of that search");
  v.Nested("global", "the search of the whole map that confirms the start", &global);
  v.Field("confirm_every_scans", &confirm_every_scans,
          "the start is confirmed by a search of the whole map every this many scans");
  v.Field("confirm_scans", &confirm_scans, "... of the first this many (0: never)");
}

kernel::Status MapLocalizationOptions::Validate() const {
  if (!(map_radius_m > 0) || !(rebuild_distance_m > 0) || !(initial_window_m >= 0) ||
      !(initial_window_rad >= 0) || !(sigma_m > 0) || levels < 1 || levels > 8)
    return kernel::Status::Error(
        "localization: map_radius_m, rebuild_distance_m and sigma_m must be positive, the "
        "initial windows >= 0, levels in [1, 8]");
  if (confirm_every_scans < 1 || confirm_scans < 0)
    return kernel::Status::Error("localization: confirm_every_scans >= 1, confirm_scans >= 0");
  return global.Validate();
}

namespace {

// The keys of the graph section before the options were split by part (2026-12), and where
// each went: a file or --set that names an old key is refused with the new one.
constexpr std::pair<const char*, const char*> kMovedKeys[] = {
    {"extraction", "front_end.extraction"},
    {"max_range_m", "front_end.max_range_m"},
    {"keyframe_distance_m", "front_end.keyframe_distance_m"},
    {"keyframe_angle_rad", "front_end.keyframe_angle_rad"},
    {"submap_keyframes", "front_end.submap_keyframes"},
    {"submap_insert_keyframes", "front_end.advanced.submap_insert_keyframes"},
    {"grid_resolution_m", "front_end.grid_resolution_m"},
    {"truncation_m", "front_end.truncation_m"},
    {"raster_curves", "front_end.advanced.raster_curves"},
    {"signed_distance", "front_end.advanced.signed_distance"},
    {"raster_points", "front_end.advanced.raster_points"},
    {"mask_unseen", "front_end.advanced.mask_unseen"},
    {"seen_margin_m", "front_end.advanced.seen_margin_m"},
    {"moving", "front_end.moving"},
    {"moving_keyframes", "front_end.moving_keyframes"},
    {"normal_max_gap_m", "front_end.normal_max_gap_m"},
    {"line_tolerance_m", "front_end.advanced.line_tolerance_m"},
    {"registration", "front_end.registration"},
    {"odometry_prior", "front_end.odometry_prior"},
    {"odometry", "front_end.odometry"},
    {"odometry_outlier_probability", "front_end.advanced.odometry_outlier_probability"},
    {"recovery_window_m", "front_end.recovery_window_m"},
    {"recovery_window_rad", "front_end.recovery_window_rad"},
    {"recovery_step_rad", "front_end.advanced.recovery_step_rad"},
    {"verify_misfit_fraction", "front_end.advanced.verify_misfit_fraction"},
    {"robust_recovery_edges", "front_end.advanced.robust_recovery_edges"},
    {"edge_sigma_m", "front_end.edge.sigma_m"},
    {"edge_sigma_per_m", "front_end.edge.per_m"},
    {"edge_sigma_rad", "front_end.edge.sigma_rad"},
    {"edge_sigma_per_rad", "front_end.edge.per_rad"},
    {"map_spacing_m", "front_end.map_spacing_m"},
    {"map_spacing_rad", "front_end.map_spacing_rad"},
    {"optimize_every_keyframes", "loop.optimize_every_keyframes"},
    {"background_loop_search", "loop.background_search"},
    {"deferred_optimization_fraction", "back_end.advanced.deferred_optimization_fraction"},
    {"local_optimization_keyframes", "back_end.advanced.local_optimization_keyframes"},
    {"pose_graph", "back_end.pose_graph"},
    {"trim_spacing_m", "back_end.trim_spacing_m"},
    {"trim_spacing_rad", "back_end.trim_spacing_rad"},
    {"merge_trimmed_keyframes", "back_end.merge_trimmed_keyframes"},
};

}  // namespace

void GraphSlamOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Nested("front_end", "registration, submap, moving objects, keyframes (GraphFrontEnd)",
           &front_end);
  v.Nested("loop", "loop closure: candidates, search, tests (LoopCloser)", &loop);
  v.Nested("back_end", "pose graph, optimisation schedule, trimming (GraphBackEnd)", &back_end);
  v.Nested("localization", "localisation in a saved map (--load-state --localize-only)",
           &localization);
  for (const auto& [old_key, new_key] : kMovedKeys) v.Moved(old_key, new_key);
}

kernel::Status GraphSlamOptions::Validate() const {
  if (kernel::Status e = front_end.Validate(); !e.ok()) return e.Prefixed("front_end");
  if (kernel::Status e = loop.Validate(); !e.ok()) return e.Prefixed("loop");
  if (kernel::Status e = back_end.Validate(); !e.ok()) return e.Prefixed("back_end");
  return localization.Validate();
}

int TrimmedKeyframe(const GraphSlamOptions& options, int k) {
  const LoopClosureOptions& loop = options.loop;
  const int submap = options.front_end.submap_keyframes;
  return k - (loop.enabled ? std::max({submap, loop.query_keyframes + 1,
                                       loop.min_gap_keyframes + loop.target_keyframes})
                           : submap);
}

}  // namespace splam::estimation
