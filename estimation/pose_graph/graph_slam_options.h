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
  // Two searches. First the nearest `candidates` keyframes (kept min_gap_keyframes apart, at
  // least min_gap_keyframes older than the new one) within radius_m + radius_per_m * (distance
  // travelled since the last closure this search found, or any added to the graph), at most
  // max_radius_m, in a window of
  // translations within that radius, at most near_window_m, and headings within window_rad +
  // window_rad_per_m * that distance, at most max_window_rad.
  int min_gap_keyframes = 60;
  double radius_m = 1.0;
  double radius_per_m = 0.05;
  double max_radius_m = 8.0;
  int candidates = 2;
  double near_window_m = 3.0;
  double window_rad = 0.2;
  double window_rad_per_m = 0.005;
  double max_window_rad = 0.8;
  // Then, at a keyframe where that window was cut short by near_window_m and found nothing, a
  // wide search by the pose graph's own uncertainty (RelativeCovariances, the covariance of the
  // new keyframe relative to every earlier one): candidates are keyframes whose distance,
  // whitened by that covariance plus reach_m^2 (how far from its keyframe a target still sees
  // what the query sees), is at most candidate_sigmas, the most likely first; each candidate's
  // window covers candidate_sigmas standard deviations (radius_m + along the largest axis,
  // window_rad + the heading's), at most max_window_m and max_window_rad. The candidates whose
  // window is at least wide_window_ratio times the first are searched in one search (its target
  // is every keyframe around the query, whichever the candidate) over the widest of their
  // windows, anchored at the most likely, at every ceil(window / stride_window_m)-th keyframe. A
  // robot back at its start after a long loop can be metres off, beyond the first search's reach;
  // searching by the uncertainty alone (every keyframe) instead lets look-alike places near the
  // estimate in through the wider windows (measured in docs/graph_slam.md).
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
  // Tests: at the best pose, at least min_overlap of the query's points fall where the
  // target has seen and face as the target's outline there (Matchable), and their mean likelihood
  // at the fine registration's pose, with exact distances, is at least min_score (the correlative
  // score, over all the points on the cells' values, also counted the unmatched points' pull and
  // let a 3 m wrong closure through in an exploration of `complex`): the query's points where the
  // target never looked say nothing for or against the match (a revisit from the other direction
  // sees walls the target did not); refused as ambiguous when a distinct pose scores at least
  // ambiguity_ratio of the best; the fine registration passes `registration`'s quality test with an
  // inlier RMS at most max_rms_m; after the optimisation the closure's whitened squared residual is
  // at most max_chi2 (agreement with the other edges; chi^2(3) 99.9 %).
  double min_score = 0.55;
  double min_overlap = 0.5;
  double ambiguity_ratio = 0.9;
  // ... unless the points that fit one of the two poses and not the other favour the best at
  // this significance (a one-sided sign test on them): in a corridor whose door recesses fix
  // the pose, a pose 3 m along it scores 98 % of the true one (most points fit both), and the
  // recesses' points tell them apart. 0: never.
  double tell_apart_alpha = 1e-3;
  double max_rms_m = 0.05;
  double max_chi2 = 16.27;
  // Contradiction: at the fine registration's pose, at most max_misfit_fraction of the query's
  // points may lie where the target saw free space (DistanceGrid::SeenFree) farther than the
  // registration's inlier_distance_m from its outline. The tests above look at the points that
  // can be matched only, and a point where the target saw through a door is not one (no outline
  // faces it): exploring `office` (seed 4), the start's keyframes, which looked down the corridor
  // and never saw its end wall behind them, took a query 1 m along the corridor's axis (30 % of
  // its points in the target's open doors and free corridor; 1 % at the true pose), and four
  // such closures confirmed each other.
  double max_misfit_fraction = 0.1;
  // The correlative search scores a point where a beam of the target that returned from farther
  // passed (DistanceGrid::SeenFreeByHits), three of its cells (resolution_m) or more from the
  // target's outline, at this (<= 0; a point on an outline scores up to 1, one where the target
  // never looked its likelihood, about 0). Three cells: the search's poses are a cell and a
  // heading step (which moves the 90 % farthest point by a cell) apart, so the discrete pose
  // nearest the truth puts points up to about two cells off their outline, farther ones more; at
  // the registration's inlier distance (0.1 m) the campus loop's true closures lost to poses 3 m
  // along its corridors in 2 of 10 seeds. Scored as unseen (0), such points did not count against a
  // pose: back at the hospital floor's start from the side the start's keyframes never saw, the
  // search took the ward one period (6.2 m) along the corridor, where nearly all the query's
  // points fell on the target's walls and 34 of 346 where its beams had passed, over the truth,
  // where a third fell where it never looked and 2 where its beams had passed. What only
  // no-returns crossed does not count (glass, dark or grazing surfaces return nothing too;
  // docs/graph_slam.md).
  double seen_free_score = -1.0;
  // Agreement between closures. A closure that would move the graph (its whitened residual at
  // the current poses above max_chi2) is added only with another closure found within
  // confirm_keyframes keyframes of it that moves it the same way: both closures put the newer of
  // their keyframes at poses whose difference, whitened by both closures' covariances and the
  // front-end edges' between the two keyframes, is at most max_chi2. A closure that agrees with
  // the graph as it is needs no second. Of the closures found, the largest set that agrees
  // (the graph counting as one member) is added; the others wait for a second until they are
  // confirm_keyframes old. A wrong closure is a lone one: a place that looks like another from
  // one spot (a closure 0.29 m and 4 deg off after 146 keyframes, exploring `complex`, seed 4),
  // while a true revisit closes at every keyframe along it. A wide search's closure that
  // disagrees with a near search's of a keyframe at most confirm_keyframes away is left out: the
  // near window lies around the estimate, and the wide search's target (every keyframe in its
  // window) may cover a look-alike farther away better than the truth (the hospital floor at
  // four times the odometry noise: two wide closures one ward, 6.2 m, along the corridor
  // confirmed each other while the near searches found the truth). At the end of the data a
  // closure that had no keyframes left to be confirmed by stands alone only when it agrees with
  // the graph. 0: every closure stands alone.
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

  // Submap: the last submap_keyframes keyframes, rasterised at grid_resolution_m into a distance
  // field truncated at truncation_m (DistanceGrid), from their curves' samples (raster_curves)
  // and their scan points (raster_points). Every rasterised point stands for a piece of outline
  // along its tangent: a curve's, or for scan points the one through its neighbours at most
  // normal_max_gap_m away. 0.1 m cells: the pieces keep the sub-cell position of the outline, so
  // finer cells cost time without accuracy (docs/graph_slam.md).
  int submap_keyframes = 30;
  // With submap_insert_keyframes > 0 the submap is built anew from its last submap_keyframes
  // keyframes only after that many new keyframes (and when the graph has moved them, when moving
  // objects were taken out of them); each new keyframe is inserted into it as it comes
  // (DistanceGrid::Insert: its points join their cells' means, new cells make new pieces, its
  // view raises what the submap has seen). A build makes room for the inserts (its grid reaches
  // submap_insert_keyframes * keyframe_distance_m farther, at most 5 m); a keyframe that does
  // not fit makes a build. Off by default (0: built anew at every keyframe): inserting saves
  // submap time, but each change of the submap moves a long log's course of closures, which
  // cost accuracy on the long loops (docs/graph_slam.md, "Speed").
  int submap_insert_keyframes = 0;
  double grid_resolution_m = 0.1;
  double truncation_m = 0.5;
  bool raster_curves = true;
  bool raster_points = true;
  double normal_max_gap_m = 0.3;
  // Scan points farther apart than normal_max_gap_m are still one outline when they lie on a
  // line with a third neighbour within line_tolerance_m (LinkedToNext: a wall at grazing
  // incidence, its points metres apart with a SICK's 0.5-1 deg beams): their normals are fitted
  // together and the chord between them is rasterised. Without it such a wall is a row of
  // isolated points, each an outline piece across the wall (its normal the beam's), and a scan
  // registered against them is held where the submap's scan was: bench/long_range.sh's 1 deg
  // laser along 60 m corridors, 41 m off with it at 0, 0.09 m with it (docs/graph_slam.md;
  // 0 disables), m.
  double line_tolerance_m = 0.03;
  bool signed_distance = false;  // see DistanceGrid::Build
  // The part of the submap its scans saw (DistanceGrid's `seen`): each scan's view, its hits
  // taken this far behind (a point just behind a wall is still matched to it), m. Not widened
  // sideways: along a wall seen to where the range ended, the points beyond must find nothing.
  bool mask_unseen = true;
  double seen_margin_m = 0.2;
  // Moving objects (people walking, MovingObjectOptions): each registered scan is compared, at its
  // registered pose, with the scans of the last moving_keyframes keyframes. When one of them saw
  // through some of its objects, it is registered again from the prediction without them, and
  // its keyframe leaves them out; their objects that it sees through are taken out of those
  // keyframes (and of the submap): a person walking ahead of the robot stands where no scan has
  // yet seen free space, and is found only once a later scan sees the place empty. Kept in the
  // keyframes, people walking along a corridor dragged the registration along its loose axis
  // (docs/graph_slam.md, "Large simulated worlds"). At the prediction instead, a slip of the
  // odometry (0.2 rad in a turn) put its view beside static things, taken for moving ones.
  MovingObjectOptions moving;
  int moving_keyframes = 10;
  RegistrationOptions registration;
  // A scan is registered twice: with the registration's wide prior alone, and with the
  // odometry increment since the last scan as the prior (its covariance from this noise model,
  // set from the sensors' noise as for the EKFs). The fused result stands unless the odometry
  // is more probably an outlier (a slip) than not: the two registrations' evidences
  // (RegistrationResult::evidence_cost) differ by more than 2 ln((1 - p) / p), p the prior
  // probability of an outlier. The odometry then holds the directions a scan leaves loose (a
  // corridor, a round pillar, a smooth wall). 1 %: 9.2 cost units. A likelihood-ratio test on
  // the points' costs alone (chi^2(3) 99 %, up to commit 7508c85) took the scan alone's chance
  // minima along smooth walls: `complex` explorations 0.064 against 0.052 m (docs/graph_slam.md).
  bool odometry_prior = true;
  OdometryNoiseModel odometry;
  double odometry_outlier_probability = 0.01;
  // A registration that fails its quality test is searched again (correlative search on the
  // submap) within these windows around the odometry prediction, heading in steps of
  // recovery_step_rad, and refined; it is kept when it passes the test, unless a peak at another
  // heading scores within loop.ambiguity_ratio of the best and the points do not tell the two
  // apart (a scan of a few points fits some wall at many headings).
  double recovery_window_m = 0.5;
  double recovery_window_rad = 1.2;
  double recovery_step_rad = 0.01;
  // A registration that passes the test but leaves more than verify_misfit_fraction of the scan's
  // points where the submap saw, away from its outlines (RegistrationResult::misfit_fraction), is
  // suspect: the recovery search runs, and its pose replaces the registration's when more points
  // lie near the submap there and fewer contradict it. A right pose leaves a few per cent of a
  // scan so; a fast turn whose odometry heading was far off can converge to a local minimum that
  // leaves a fifth (docs/graph_slam.md). 1: never.
  double verify_misfit_fraction = 0.05;
  // The front-end edge into the next keyframe after a recovery gets the loop closures' robust
  // loss: a search over a window can take the wrong basin (a 16 deg turn where the robot drove
  // straight, exploring `complex`, seed 1), and closures that later find the robot elsewhere then
  // break that one edge instead of bending the whole graph around it (the map was 0.47 m off).
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
  // Closures that all agree with the graph as it is (each within loop.max_chi2 at the current
  // poses, and with those already waiting their sum within chi^2(3m) 99.9 % for m closures) are
  // added to it without a whole optimisation while the graph has grown by less than
  // deferred_optimization_fraction of its nodes since its last one; closures that would move the
  // graph, a graph grown by that much, and the end of the data (Finish) optimise it whole, and
  // every closure added since its last whole optimisation must then agree with it (else it is
  // removed). On a revisit every few keyframes close, and a whole optimisation's cost grows with
  // the graph. Optimised again only after fraction * n new keyframes, a graph of n nodes whose
  // optimisation costs c per node costs at most c / fraction per keyframe, whatever the log's
  // length (a geometric schedule). 0: every flush optimises the whole graph.
  double deferred_optimization_fraction = 0.03;
  // Meanwhile the closures that wait optimise the last local_optimization_keyframes keyframes
  // (and at least each closure's newer keyframe), the earlier ones held, so that the front end's
  // recent keyframes are pulled onto the map as at every flush and its submaps do not drift from
  // it; the next whole optimisation takes out what holding the rest bent. 100 keyframes (30 m of
  // path) hold the submap and the keyframes a flush closes. 0: none. Both defaults are measured
  // in docs/graph_slam.md ("Speed").
  int local_optimization_keyframes = 100;
  // A keyframe's loop-closure search reads the graph as it was when the keyframe was made, and
  // what it found is added when the next keyframe is made (before it), so that the search can run
  // on a second thread while the front end registers the scans in between. With this true it
  // does, unless loop.min_gap_keyframes <= moving_keyframes (the front end then still edits
  // keyframes a search reads); false runs it at once on the calling thread. Both give the same
  // trajectory: the search sees the same data and its closures enter the graph at the same point.
  bool background_loop_search = true;
  PoseGraphOptions pose_graph;
  MapLocalizationOptions localization;

  // The map: curves of keyframes at least map_spacing_m or map_spacing_rad from every earlier
  // map keyframe.
  double map_spacing_m = 1.0;
  double map_spacing_rad = 0.5;

  // Keyframe trimming, so that memory follows the mapped area, not the path: a keyframe that has
  // left the recent window (the submap's, the loop query's and the youngest loop targets'
  // keyframes: loop.min_gap_keyframes + loop.target_keyframes) drops its points, raster and
  // view, keeping its pose and edges, when an earlier keyframe that still holds them
  // lies within trim_spacing_m and trim_spacing_rad of it: on a revisit the older keyframe
  // describes the place as well, and loop closures are searched against it. Map keyframes are
  // kept whole. 0.3 m is the keyframe spacing, so that a first pass along a path keeps its
  // keyframes (of those made turning on the spot, the ones within 0.5 rad of an earlier one go);
  // 0.5 rad keeps revisits from another direction, which see other walls. Without loop closure
  // (loop.enabled false: the topological SLAM's front end) every keyframe but the map's drops its
  // data once it leaves the submap, so that memory follows the map alone. 0 disables.
  double trim_spacing_m = 0.3;
  double trim_spacing_rad = 0.5;
  // A keyframe trimmed for the earlier keyframe beside it is then merged into that keyframe's
  // node (PoseGraph::MergeNode) after the next whole optimisation, once the graph ties the two
  // (their relative pose known to a third of trim_spacing_m, as after a closure there) and no
  // closure waiting for confirmation reaches it: its scans and marked nodes follow that node
  // from then on, its edges go to it, and
  // edges between the same two places are fused, so that the graph, its optimisation and its
  // memory follow the map, not the path (a reduced pose graph, Johannsson et al. 2013). Needs
  // loop closure (loop.enabled).
  bool merge_trimmed_keyframes = true;

  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_POSE_GRAPH_GRAPH_SLAM_OPTIONS_H_
