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

// The front-end edge between consecutive keyframes (EdgeCovariance): sigma = sigma_m + per_m *
// distance travelled for the translation, sigma_rad + per_rad * |turn| for the heading
// (diagonal). The loop closer chains it between two closures to tell whether they agree.
struct EdgeModel {
  double sigma_m = 0.02;
  double per_m = 0.05;
  double sigma_rad = 0.005;
  double per_rad = 0.05;

  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

// The front end's options (GraphFrontEnd, RegisterFrontEnd, MapLocalizer): registration,
// submap, moving objects, the keyframe decision and the front-end edge model.
struct FrontEndOptions {
  // How keyframe curves are extracted (segmentation, fit, curvature, features).
  kernel::SplineExtractionOptions extraction;
  // Beams longer than this are not used (0: the laser's maximum range), metres.
  double max_range_m = 30.0;

  // A keyframe every keyframe_distance_m of travel or keyframe_angle_rad of turn. 0.3 m and
  // 0.25 rad: the next scan still overlaps the keyframe's by most of its beams, so the submap is
  // fresh, and a 1,000 m log makes a few thousand nodes, which Ceres optimises in tens of ms.
  double keyframe_distance_m = 0.3;
  double keyframe_angle_rad = 0.25;

  // Submap: the last submap_keyframes keyframes, rasterised at grid_resolution_m (0.01-1 m) into
  // a distance field truncated at truncation_m (above the cell, at most 10 m), from their curves'
  // samples and scan points, a point's normal from neighbours at most normal_max_gap_m away. Why:
  // docs/graph_slam_options.md#front_endsubmap_keyframes.
  int submap_keyframes = 30;
  double grid_resolution_m = 0.1;
  double truncation_m = 0.5;
  double normal_max_gap_m = 0.3;
  // Moving objects: each registered scan is compared with the last moving_keyframes (0-1000)
  // keyframes' scans; what one saw through is left out of both. Why:
  // docs/graph_slam_options.md#front_endmoving.
  MovingObjectOptions moving;
  int moving_keyframes = 10;
  RegistrationOptions registration;
  // Each scan is registered alone and with the odometry increment as its prior (this noise model,
  // set from the sensors' noise). Why: docs/graph_slam_options.md#front_endodometry_prior.
  bool odometry_prior = true;
  OdometryNoiseModel odometry;
  // A failed registration is searched again within these windows of the prediction (0-100 m, 0-pi
  // rad; 0 m: never). Why: docs/graph_slam_options.md#front_endrecovery_window_m.
  double recovery_window_m = 0.5;
  double recovery_window_rad = 1.2;

  // The front-end edges' model.
  EdgeModel edge;

  // The map: curves of keyframes at least map_spacing_m or map_spacing_rad from every earlier
  // map keyframe.
  double map_spacing_m = 1.0;
  double map_spacing_rad = 0.5;

  // Knobs that exist to tune or to switch a mechanism off for a comparison.
  struct Advanced {
    // New keyframes inserted into the submap before it is built anew (0-1000; 0: built anew at
    // every keyframe, the default for accuracy). Why:
    // docs/graph_slam_options.md#front_endadvancedsubmap_insert_keyframes.
    int submap_insert_keyframes = 0;
    // What is rasterised into the submap: the curves' samples, the scan points.
    bool raster_curves = true;
    bool raster_points = true;
    // Scan points farther apart than normal_max_gap_m are one outline when a third on their line
    // lies within this (m; 0: off): grazing walls of long-range lasers. Why:
    // docs/graph_slam_options.md#front_endadvancedline_tolerance_m.
    double line_tolerance_m = 0.03;
    bool signed_distance = false;  // see DistanceGrid::Build
    // The part of the submap its scans saw (DistanceGrid's `seen`): each scan's view, its hits
    // taken seen_margin_m (m) behind (a point just behind a wall is still matched to it). Not
    // widened sideways: along a wall seen to where the range ended, the points beyond must find
    // nothing.
    bool mask_unseen = true;
    double seen_margin_m = 0.2;
    // The fused pose stands unless the odometry is more probably an outlier, this (0-1) a priori.
    double odometry_outlier_probability = 0.01;
    // The recovery search: heading steps (rad), its likelihood's sigma (m), and as the loop
    // closer's tests (LoopClosureOptions::ambiguity_ratio and advanced.tell_apart_alpha).
    double recovery_step_rad = 0.01;
    double recovery_sigma_m = 0.05;
    double recovery_ambiguity_ratio = 0.9;
    double recovery_tell_apart_alpha = 1e-3;
    // A registration leaving more than this fraction (0-1; 1: never) of its points where the
    // submap saw free space is checked by the recovery search. Why:
    // docs/graph_slam_options.md#front_endadvancedverify_misfit_fraction.
    double verify_misfit_fraction = 0.05;
    // The front-end edge across a recovered scan gets the closures' robust loss. Why:
    // docs/graph_slam_options.md#front_endadvancedrobust_recovery_edges.
    bool robust_recovery_edges = true;

    void VisitFields(kernel::FieldVisitor& v);
    kernel::Status Validate() const;
  } advanced;

  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

// The loop closer's options (LoopCloser, AgreementAcceptance): candidates, correlative search,
// tests, edges.
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
  // The wide search, where the near window was cut short and found nothing: windows at most
  // max_window_m (m). Why: docs/graph_slam_options.md#loopadvancedreach_m.
  double max_window_m = 12.0;
  // Query: the points of the new keyframe and query_keyframes before it; target: the
  // candidate's submap (target_keyframes either side of it).
  int query_keyframes = 10;
  int target_keyframes = 15;
  // Correlative search on a likelihood exp(-d^2 / 2 sigma^2) on a grid of resolution_m cells
  // (0.01-1 m; the distances are exact to the curves, so a coarser grid than the front end's
  // loses little and makes the search four times cheaper); the fine registration uses the same
  // grid.
  double resolution_m = 0.1;
  double sigma_m = 0.05;
  // Tests: min_overlap (0-1) of the query's points matchable where the target saw, their mean
  // likelihood at least min_score (0-1); ambiguous when a distinct pose scores ambiguity_ratio
  // (0-1) of the best; the fine registration's inlier RMS at most max_rms_m (m). Why:
  // docs/graph_slam_options.md#loopmin_score.
  double min_score = 0.55;
  double min_overlap = 0.5;
  double ambiguity_ratio = 0.9;
  double max_rms_m = 0.05;
  // A closure that would move the graph waits this many keyframes for a second that agrees with
  // it within max_chi2 (chi^2(3) 99.9 %; 0 keyframes: every closure stands alone); the built-in
  // AgreementAcceptance. Why: docs/graph_slam_options.md#loopconfirm_keyframes.
  int confirm_keyframes = 20;
  double max_chi2 = 16.27;
  RegistrationOptions registration = RegistrationDefaults();
  // Loop edge covariance: the registration's plus this floor (sigma, m and rad).
  double sigma_floor_m = 0.02;
  double sigma_floor_rad = 0.005;
  // Closures found are handed to the back end together, this many keyframes after the first of
  // them (0: at once): on a revisit every keyframe closes, and one optimisation serves a few.
  int optimize_every_keyframes = 5;
  // The search runs on a second thread beside the front end (the same trajectory either way).
  // Why: docs/graph_slam_options.md#loopbackground_search.
  bool background_search = true;

  // Knobs that exist to tune.
  struct Advanced {
    // The wide search: candidates within candidate_sigmas of the graph's relative covariance
    // (plus reach_m^2, m), windows of as many sigmas, only when wide_window_ratio (>= 1) times
    // the near window, at every ceil(window / stride_window_m)-th keyframe. Why:
    // docs/graph_slam_options.md#loopadvancedreach_m.
    double reach_m = 3.0;
    double candidate_sigmas = 3.0;
    double wide_window_ratio = 2.0;
    double stride_window_m = 3.0;
    // Resolution levels of the correlative search (1-8).
    int levels = 5;
    // An ambiguous match stands when a one-sided sign test on the points that fit only one of
    // the two poses favours the best at this significance (0-1; 0: never). Why:
    // docs/graph_slam_options.md#loopadvancedtell_apart_alpha.
    double tell_apart_alpha = 1e-3;
    // At most this fraction (0-1) of the query's points where the target saw free space, farther
    // than the registration's inlier distance from its outline. Why:
    // docs/graph_slam_options.md#loopadvancedmax_misfit_fraction.
    double max_misfit_fraction = 0.1;
    // The correlative score (-10 to 0) of a point where a returning beam of the target passed,
    // three cells or more from its outline (0: as where it never looked). Why:
    // docs/graph_slam_options.md#loopadvancedseen_free_score.
    double seen_free_score = -1.0;
    // The targets' fields: truncated at truncation_m (above resolution_m, at most 10 m), each
    // scan's view taken seen_margin_m (m) behind its hits; the query's normals from neighbours at
    // most normal_max_gap_m (m) away. As the front end's submap by default.
    double truncation_m = 0.5;
    double seen_margin_m = 0.2;
    double normal_max_gap_m = 0.3;

    void VisitFields(kernel::FieldVisitor& v);
    kernel::Status Validate() const;
  } advanced;

  static RegistrationOptions RegistrationDefaults();
  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

// The back end's options (GraphBackEnd): the pose graph, its optimisation schedule, and the
// trimming and merging of redundant keyframes.
struct BackEndOptions {
  PoseGraphOptions pose_graph;
  // A closure is consistent with the graph when its whitened squared residual is at most this
  // (chi^2(3) 99.9 %): closures that are wait unoptimised (advanced), and after an optimisation
  // those that are not are removed.
  double max_chi2 = 16.27;
  // A keyframe that has left every window drops its data when an earlier one holding its own lies
  // within trim_spacing_m (m; 0: never) and trim_spacing_rad (rad). Why:
  // docs/graph_slam_options.md#back_endtrim_spacing_m.
  double trim_spacing_m = 0.3;
  double trim_spacing_rad = 0.5;
  // A trimmed keyframe's node is merged into the earlier one beside it once the graph ties them (a
  // reduced pose graph). Why: docs/graph_slam_options.md#back_endmerge_trimmed_keyframes.
  bool merge_trimmed_keyframes = true;

  // Knobs that exist to tune.
  struct Advanced {
    // Closures that agree with the graph wait in it unoptimised until it has grown by this
    // fraction (0-10; 0: every flush optimises it whole). Why:
    // docs/graph_slam_options.md#back_endadvanceddeferred_optimization_fraction.
    double deferred_optimization_fraction = 0.03;
    // Meanwhile the last this many keyframes are optimised (0: none). Why:
    // docs/graph_slam_options.md#back_endadvancedlocal_optimization_keyframes.
    int local_optimization_keyframes = 100;

    void VisitFields(kernel::FieldVisitor& v);
    kernel::Status Validate() const;
  } advanced;

  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

// Global localisation in a saved map (GlobalLocalizer): no initial pose, any heading.
struct GlobalLocalizationOptions {
  // The query's points within this range of the robot, m: the farther points set the heading
  // step (one cell at the 90 % farthest point), and the whole-map search tries every heading.
  double max_range_m = 15.0;
  // The map's field: likelihood exp(-d^2 / 2 sigma^2) (sigma_m, m) on cells of resolution_m
  // (0.01-1 m), searched with `levels` resolution levels (1-8; the coarsest cells are
  // resolution_m * 2^(levels - 1) wide). A point where the map's returning beams passed, three
  // cells or more from an outline, scores seen_free_score (-10 to 0): evidence against the pose.
  double resolution_m = 0.1;
  double sigma_m = 0.05;
  int levels = 7;
  double seen_free_score = -1.0;
  // Accepted when the best pose's mean likelihood is at least min_score (0-1), no distinct pose
  // (0.5 m or 0.2 rad away) scores ambiguity_ratio (0-1) of it unless the points tell the two
  // apart at tell_apart_alpha (a sign test; 0-1), and the fine registration from it passes.
  double min_score = 0.5;
  double ambiguity_ratio = 0.9;
  double tell_apart_alpha = 1e-3;

  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

// Localisation in a saved map (MapLocalizer, `slam --load-state --localize-only`), which
// registers as the front end does (FrontEndOptions) against a field of the map's scans.
struct MapLocalizationOptions {
  // The field registered against holds the map scans taken within this distance of the robot, m.
  double map_radius_m = 10.0;
  // It is built anew once the robot is this far from where it was last built, m.
  double rebuild_distance_m = 2.0;
  // The first scan is searched for within this distance of the start pose, m, and this angle of
  // its heading, rad (a correlative search on a likelihood of this sigma, m, with this many
  // resolution levels, 1-8: the start need only be roughly known).
  double initial_window_m = 1.0;
  double initial_window_rad = 0.5;
  double sigma_m = 0.05;
  int levels = 5;
  // The start is confirmed by a search of the whole map at any heading (GlobalLocalizer, these
  // options) at every confirm_every_scans-th (>= 1) of the first confirm_scans (>= 0) scans,
  // until a fix: one elsewhere relocalises (a start that was wrong, the kidnapped robot).
  GlobalLocalizationOptions global;
  int confirm_every_scans = 5;
  int confirm_scans = 200;

  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

// The graph SLAM's options: one struct per part, each part taking only its own.
struct GraphSlamOptions {
  FrontEndOptions front_end;
  LoopClosureOptions loop;
  BackEndOptions back_end;
  MapLocalizationOptions localization;

  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

// The keyframe that the new keyframe k lets the back end trim: the newest that has left every
// window reading keyframe data (the front end's submap, and with loop closure the loop query's
// and the youngest loop targets').
int TrimmedKeyframe(const GraphSlamOptions& options, int k);

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_POSE_GRAPH_GRAPH_SLAM_OPTIONS_H_
