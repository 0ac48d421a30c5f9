#ifndef SPLAM_ESTIMATION_POSE_GRAPH_GRAPH_SLAM_OPTIONS_H_
#define SPLAM_ESTIMATION_POSE_GRAPH_GRAPH_SLAM_OPTIONS_H_

#include "estimation/models.h"
#include "estimation/pose_graph/moving_objects.h"
#include "estimation/pose_graph/pose_graph.h"
#include "estimation/pose_graph/scan_registration.h"
#include "kernel/options.h"
#include "kernel/spline_extraction.h"
#include "kernel/status.h"

// The graph SLAM's options (graph_slam.h), with their YAML form.
namespace splam::estimation {

// Loop closure of the graph SLAM (GraphSlamOptions::loop).
struct LoopClosureOptions {
  bool enabled = true;
  // The near search: the `candidates` nearest keyframes, min_gap_keyframes apart and older, within
  // radius_m + radius_per_m * (m travelled since the last closure), at most max_radius_m; window
  // that radius (at most near_window_m, m) and window_rad + window_rad_per_m * travel (at most
  // max_window_rad, rad). Why: docs/graph_slam_options.md#loopmin_gap_keyframes.
  int min_gap_keyframes = 60;
  double radius_m = 1.0;
  double radius_per_m = 0.05;
  double max_radius_m = 8.0;
  int candidates = 2;
  double near_window_m = 3.0;
  double window_rad = 0.2;
  double window_rad_per_m = 0.005;
  double max_window_rad = 0.8;
  // The wide search, where the near window was cut short and found nothing: candidates within
  // candidate_sigmas of the graph's relative covariance (plus reach_m^2, m), windows of as many
  // sigmas (at most max_window_m, m), only when wide_window_ratio (>= 1) times the near window, at
  // every ceil(window / stride_window_m)-th keyframe. Why: docs/graph_slam_options.md#loopreach_m.
  double reach_m = 3.0;
  double candidate_sigmas = 3.0;
  double max_window_m = 12.0;
  double wide_window_ratio = 2.0;
  double stride_window_m = 3.0;
  // Query: the points of the new keyframe and query_keyframes before it; target: the
  // candidate's submap (target_keyframes either side of it).
  int query_keyframes = 10;
  int target_keyframes = 15;
  // Correlative search on a likelihood exp(-d^2 / 2 sigma^2) with `levels` resolution levels,
  // on a grid of resolution_m cells (the distances are exact to the curves, so a coarser
  // grid than the front end's loses little and makes the search four times cheaper); the fine
  // registration uses the same grid.
  double resolution_m = 0.1;
  double sigma_m = 0.05;
  int levels = 5;
  // Tests: min_overlap (0-1) of the query's points matchable where the target saw, their mean
  // likelihood at least min_score (0-1); ambiguous when a distinct pose scores ambiguity_ratio
  // (0-1) of the best. Why: docs/graph_slam_options.md#loopmin_score.
  double min_score = 0.55;
  double min_overlap = 0.5;
  double ambiguity_ratio = 0.9;
  // ... unless a one-sided sign test on the points that fit only one of the two poses favours the
  // best at this significance (0-1; 0: never). Then: the fine registration's inlier RMS at most
  // max_rms_m (m), the closure's whitened squared residual after optimisation at most max_chi2
  // (chi^2(3) 99.9 %). Why: docs/graph_slam_options.md#looptell_apart_alpha.
  double tell_apart_alpha = 1e-3;
  double max_rms_m = 0.05;
  double max_chi2 = 16.27;
  // At most this fraction (0-1) of the query's points where the target saw free space, farther than
  // the registration's inlier distance from its outline. Why:
  // docs/graph_slam_options.md#loopmax_misfit_fraction.
  double max_misfit_fraction = 0.1;
  // The correlative score (-10 to 0) of a point where a returning beam of the target passed, three
  // cells or more from its outline (0: as where it never looked). Why:
  // docs/graph_slam_options.md#loopseen_free_score.
  double seen_free_score = -1.0;
  // A closure that would move the graph waits this many keyframes for a second that agrees (0:
  // every closure stands alone); the built-in AgreementAcceptance. Why:
  // docs/graph_slam_options.md#loopconfirm_keyframes.
  int confirm_keyframes = 20;
  RegistrationOptions registration = RegistrationDefaults();
  // Loop edge covariance: the registration's plus this floor (sigma, m and rad).
  double sigma_floor_m = 0.02;
  double sigma_floor_rad = 0.005;

  static RegistrationOptions RegistrationDefaults();
  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

// Localisation in a saved map (MapLocalizer, `slam --load-state --localize-only`).
struct MapLocalizationOptions {
  // The field registered against holds the map scans taken within this distance of the robot, m.
  double map_radius_m = 10.0;
  // It is built anew once the robot is this far from where it was last built, m.
  double rebuild_distance_m = 2.0;
  // The first scan is searched for within this distance of the start pose, m, and this angle of
  // its heading, rad (a correlative search: the start need only be roughly known).
  double initial_window_m = 1.0;
  double initial_window_rad = 0.5;

  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

struct GraphSlamOptions {
  // How keyframe curves are extracted (segmentation, fit, curvature, features).
  kernel::SplineExtractionOptions extraction;
  // Beams longer than this are not used (0: the laser's maximum range), metres.
  double max_range_m = 30.0;

  // A keyframe every keyframe_distance_m of travel or keyframe_angle_rad of turn. 0.3 m and
  // 0.25 rad: the next scan still overlaps the keyframe's by most of its beams, so the submap is
  // fresh, and a 1,000 m log makes a few thousand nodes, which Ceres optimises in tens of ms.
  double keyframe_distance_m = 0.3;
  double keyframe_angle_rad = 0.25;

  // Submap: the last submap_keyframes keyframes, rasterised at grid_resolution_m (0.01-1 m) into a
  // distance field truncated at truncation_m (m), from their curves' samples and scan points. Why:
  // docs/graph_slam_options.md#submap_keyframes.
  int submap_keyframes = 30;
  // New keyframes inserted into the submap before it is built anew (0-1000; 0: built anew at every
  // keyframe, the default for accuracy). Why: docs/graph_slam_options.md#submap_insert_keyframes.
  int submap_insert_keyframes = 0;
  double grid_resolution_m = 0.1;
  double truncation_m = 0.5;
  bool raster_curves = true;
  bool raster_points = true;
  double normal_max_gap_m = 0.3;
  // Scan points farther apart than normal_max_gap_m are one outline when a third on their line lies
  // within this (m; 0: off): grazing walls of long-range lasers. Why:
  // docs/graph_slam_options.md#line_tolerance_m.
  double line_tolerance_m = 0.03;
  bool signed_distance = false;  // see DistanceGrid::Build
  // The part of the submap its scans saw (DistanceGrid's `seen`): each scan's view, its hits
  // taken this far behind (a point just behind a wall is still matched to it), m. Not widened
  // sideways: along a wall seen to where the range ended, the points beyond must find nothing.
  bool mask_unseen = true;
  double seen_margin_m = 0.2;
  // Moving objects: each registered scan is compared with the last moving_keyframes keyframes'
  // scans; what one saw through is left out of both. Why: docs/graph_slam_options.md#moving.
  MovingObjectOptions moving;
  int moving_keyframes = 10;
  RegistrationOptions registration;
  // Each scan is registered alone and with the odometry increment as its prior (this noise model,
  // set from the sensors' noise); the fused pose stands unless the odometry is more probably an
  // outlier, odometry_outlier_probability (0-1) a priori. Why:
  // docs/graph_slam_options.md#odometry_prior.
  bool odometry_prior = true;
  OdometryNoiseModel odometry;
  double odometry_outlier_probability = 0.01;
  // A failed registration is searched again within these windows of the prediction (0-100 m, 0-pi
  // rad; 0 m: never), heading in steps of recovery_step_rad. Why:
  // docs/graph_slam_options.md#recovery_window_m.
  double recovery_window_m = 0.5;
  double recovery_window_rad = 1.2;
  double recovery_step_rad = 0.01;
  // A registration leaving more than this fraction (0-1; 1: never) of its points where the submap
  // saw free space is checked by the recovery search. Why:
  // docs/graph_slam_options.md#verify_misfit_fraction.
  double verify_misfit_fraction = 0.05;
  // The front-end edge across a recovered scan gets the closures' robust loss. Why:
  // docs/graph_slam_options.md#robust_recovery_edges.
  bool robust_recovery_edges = true;

  // Front-end edge between consecutive keyframes: sigma = base + per_m * distance travelled
  // (+ per_rad * turn for the heading).
  double edge_sigma_m = 0.02;
  double edge_sigma_per_m = 0.05;
  double edge_sigma_rad = 0.005;
  double edge_sigma_per_rad = 0.05;

  // Loop closure: candidates, correlative search, tests, edges.
  LoopClosureOptions loop;
  // Closures found are added and optimised together, this many keyframes after the first of
  // them (0: at once): on a revisit every keyframe closes, and one optimisation serves a few.
  int optimize_every_keyframes = 5;
  // Closures that agree with the graph wait in it unoptimised until it has grown by this fraction
  // (0-10; 0: every flush optimises it whole). Why:
  // docs/graph_slam_options.md#deferred_optimization_fraction.
  double deferred_optimization_fraction = 0.03;
  // Meanwhile the last this many keyframes are optimised (0: none). Why:
  // docs/graph_slam_options.md#local_optimization_keyframes.
  int local_optimization_keyframes = 100;
  // The loop search runs on a second thread beside the front end (the same trajectory either way).
  // Why: docs/graph_slam_options.md#background_loop_search.
  bool background_loop_search = true;
  PoseGraphOptions pose_graph;
  MapLocalizationOptions localization;

  // The map: curves of keyframes at least map_spacing_m or map_spacing_rad from every earlier
  // map keyframe.
  double map_spacing_m = 1.0;
  double map_spacing_rad = 0.5;

  // A keyframe that has left every window drops its data when an earlier one holding its own lies
  // within trim_spacing_m (m; 0: never) and trim_spacing_rad (rad). Why:
  // docs/graph_slam_options.md#trim_spacing_m.
  double trim_spacing_m = 0.3;
  double trim_spacing_rad = 0.5;
  // A trimmed keyframe's node is merged into the earlier one beside it once the graph ties them (a
  // reduced pose graph). Why: docs/graph_slam_options.md#merge_trimmed_keyframes.
  bool merge_trimmed_keyframes = true;

  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_POSE_GRAPH_GRAPH_SLAM_OPTIONS_H_
