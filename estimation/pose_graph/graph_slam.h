#ifndef SPLAM_ESTIMATION_POSE_GRAPH_GRAPH_SLAM_H_
#define SPLAM_ESTIMATION_POSE_GRAPH_GRAPH_SLAM_H_

#include <Eigen/Core>
#include <array>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <vector>

#include "estimation/map_spline.h"
#include "estimation/models.h"
#include "estimation/pose_graph/background.h"
#include "estimation/pose_graph/correlative_matcher.h"
#include "estimation/pose_graph/distance_grid.h"
#include "estimation/pose_graph/moving_objects.h"
#include "estimation/pose_graph/pose_graph.h"
#include "estimation/pose_graph/scan_registration.h"
#include "kernel/options.h"
#include "kernel/pose2.h"
#include "kernel/scan.h"
#include "kernel/spline_extraction.h"
#include "kernel/status.h"

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

// Graph SLAM on curve maps: keyframes keep their scan's B-spline curves and points;
// every scan is registered against a submap rasterised from the curves of recent keyframes;
// each new keyframe searches earlier ones for a loop closure; a Ceres pose graph over the
// keyframes is optimised when closures are accepted and re-anchors the map.
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

// Agreement of two loop closures on keyframe c, the newer of their `to` keyframes. The older
// closure puts its own keyframe b at by_older (covariance older_covariance, of a right
// perturbation, as a closure edge's) and c at by_older * chain, where chain = b_T_c is the
// front-end chain between them (covariance chain_covariance, at c); the newer puts c at by_newer.
// Returns the difference of the two poses of c, whitened by the sum of the three covariances
// propagated to c: chi^2(3) when both closures are right.
double ClosureDisagreementChi2(const kernel::Pose2& by_older,
                               const Eigen::Matrix3d& older_covariance, const kernel::Pose2& chain,
                               const Eigen::Matrix3d& chain_covariance,
                               const kernel::Pose2& by_newer,
                               const Eigen::Matrix3d& newer_covariance);

// The largest set of closures 0..n-1 that agree pairwise (agree(i, j)), the graph as it is
// counting as one more member of a set whose every closure agrees with it (with_graph[i]); grown
// greedily from each member in turn, the graph first (so it wins ties). Empty when no set has two
// members.
std::vector<int> LargestAgreeingSet(const std::vector<bool>& with_graph,
                                    const std::function<bool(int, int)>& agree);

// Of `placed` (a query's points placed in the target's frame), the fraction that lie where the
// target saw free space (DistanceGrid::SeenFree) at least inlier_distance_m from its outline:
// points that contradict the pose (a point where the target did not look says nothing). 0 when
// `placed` is empty.
double SeenFreeMisfitFraction(const DistanceGrid& target, const std::vector<OrientedPoint>& placed,
                              double inlier_distance_m);

// Loop-closure counters.
struct LoopClosureCounts {
  long searches = 0;  // candidates searched (proposals)
  long accepted = 0;
  long rejected_score = 0, rejected_ambiguous = 0, rejected_registration = 0, rejected_misfit = 0,
       rejected_disagreement = 0, rejected_unconfirmed = 0;
};

// The graph SLAM front end's registration of a scan's points (robot frame) against a field
// (world frame) from the predicted pose: the scan alone and with the odometry increment since
// the last scan as its prior (the fused pose unless the odometry is an outlier); when that fails
// its test or looks suspect (misfit above verify_misfit_fraction), a correlative search over the
// recovery window on `scores` (made on first need) and a wide registration from its best pose,
// taken when it fits at least as well. GraphSlam registers against its submap, MapLocalizer
// against a saved map.
struct FrontEndRegistration {
  RegistrationResult result;
  bool searched = false;   // the recovery search ran
  bool recovered = false;  // and its pose was taken
};
FrontEndRegistration RegisterFrontEnd(const std::vector<OrientedPoint>& points,
                                      const DistanceGrid& field,
                                      const std::function<const LikelihoodPyramid&()>& scores,
                                      const kernel::Pose2& predicted,
                                      const kernel::Pose2& odometry_since,
                                      const GraphSlamOptions& options);

class GraphSlam {
 public:
  struct Keyframe {
    kernel::Pose2 pose;        // world_T_robot, optimised
    double travelled_m = 0.0;  // path length at this keyframe
    int scan = 0;              // the scan that made it (0-based, input order)
    bool in_map = false;
    bool trimmed = false;  // its data dropped (trim_spacing_m)
    // The views rasterised on the lattice at `pose` (RasteriseView; by_hits from seen_by_hits),
    // for the submap ([0], the front end's thread) and the loop targets ([1], the loop search's):
    // made again only when the keyframe has moved or its view changed (GraphSlam::ViewsOf).
    struct ViewRaster {
      bool valid = false;
      kernel::Pose2 pose;
      ViewCells seen;
      bool by_hits_valid = false;
      ViewCells by_hits;
    };
    // What a keyframe holds until it is trimmed: on its own allocation, so that a trimmed
    // keyframe (most of them on a long revisiting run) keeps only the 56 bytes above.
    struct Data {
      std::vector<OrientedPoint> points;          // the scan's hits, robot frame, with normals
      std::vector<OrientedPoint> raster;          // curve samples (+ points), robot frame
      std::vector<kernel::SplineCurve> curves;    // robot frame; map keyframes only
      std::vector<Eigen::Vector2d> seen;          // the scan's view: sensor, then beam ends
      std::vector<Eigen::Vector2d> seen_by_hits;  // the view of its beams that returned
      // That scan, clipped, its moving objects read as NaN, and its mounting; kept while the
      // keyframe is among the last moving_keyframes (empty after).
      kernel::Scan reading;
      BeamRanges candidates;  // the reading's (ForegroundObjects)
      kernel::Pose2 robot_T_laser;
      mutable std::array<ViewRaster, 2> rasters;
    };
    std::unique_ptr<Data> data;  // null once trimmed
  };

  GraphSlam(const kernel::Pose2& start, const GraphSlamOptions& options);
  // A loop search may be running on `this`.
  GraphSlam(const GraphSlam&) = delete;
  GraphSlam& operator=(const GraphSlam&) = delete;
  ~GraphSlam();

  void Predict(const kernel::Pose2& odometry_increment);
  void Update(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser);
  // As Update, but the scan was localised by another front end (the topological SLAM, method
  // topological-graph) at `pose`: no registration; keyframes, loop closure and the pose graph
  // work as in Update.
  void UpdateAt(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser,
                const kernel::Pose2& pose);
  // As Update, but `correct` turns the registered pose (or the odometry's, when registered() is
  // false) into the pose the scan's keyframe and the next prediction start from: another method
  // corrects the front end (the topological SLAM against its curve map), and the submap is then
  // built at the corrected poses.
  void UpdateCorrected(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser,
                       const std::function<kernel::Pose2(const kernel::Pose2&)>& correct);
  // An exploration node at the current estimate: the next scan makes a keyframe, to which the
  // node is anchored, so that the node moves with the keyframe when the graph is optimised.
  void MarkNode();
  // The nodes marked so far, where the graph now puts them.
  std::vector<kernel::Pose2> NodePoses() const;
  // The data has ended: optimises the pending closures and the whole graph once more.
  void Finish();

  // Uncertainty (PoseGraph::JointCovariance: poses (x, y, theta) in the world frame, the first
  // keyframe held, closures still waiting for confirmation not counted). Keyframe k's marginal
  // covariance; nullopt when k is not a keyframe.
  std::optional<Eigen::Matrix3d> KeyframeCovariance(int k) const;
  // The current pose's: the newest keyframe's moved to the pose, plus TravelCovariance for the
  // path since. nullopt before the first keyframe.
  std::optional<Eigen::Matrix3d> PoseCovariance() const;
  // The front-end edges' model (edge_sigma_m, ...) over path_m of straight travel: one edge per
  // keyframe_distance_m, independent.
  Eigen::Matrix3d TravelCovariance(double path_m) const;
  // Expected information of a revisit (active loop closing) to each marked node: the robot drives
  // path_m[i] to nodes[i] (TravelCovariance) and a loop closure registers it against the node's
  // keyframe (covariance: the loop edges' floor, loop.sigma_floor_m and _rad) there;
  // InformationGain(PoseCovariance(), CovarianceAfterRevisit(...)), nats, negative when the
  // drive costs more than the closure gives. nullopt for a node not yet anchored to a keyframe,
  // or all of them when the graph has no covariance (nothing marked, a single keyframe).
  std::vector<std::optional<double>> RevisitInformation(const std::vector<int>& nodes,
                                                        const std::vector<double>& path_m) const;

  const kernel::Pose2& pose() const { return pose_; }
  const GraphSlamOptions& options() const { return options_; }
  const std::vector<Keyframe>& keyframes() const { return keyframes_; }
  const PoseGraph& graph() const { return graph_; }
  // Every scan's pose as now estimated (its keyframe's optimised pose times the offset).
  std::vector<kernel::Pose2> Trajectory() const;
  std::vector<MapSpline> MapSplines() const;
  std::size_t num_map_curves() const { return map_curves_; }
  std::size_t num_map_control_points() const { return map_control_points_; }
  long trimmed_keyframes() const { return trimmed_; }
  // Keyframes whose nodes were merged into earlier ones (merge_trimmed_keyframes).
  long merged_keyframes() const { return graph_.num_nodes() - graph_.num_live_nodes(); }
  // Submaps built anew, and keyframes inserted into one (submap_insert_keyframes).
  long submap_builds() const { return submap_builds_; }
  long submap_inserts() const { return submap_inserts_; }
  // Flushes whose closures were added without an optimisation (deferred_optimization_fraction).
  long deferred_optimizations() const { return deferred_optimizations_; }

  // Whether the last scan's registration stood (Update; false after a fallback to odometry, and
  // after UpdateAt).
  bool registered() const { return registered_; }
  long registrations() const { return registrations_; }
  long registration_fallbacks() const { return fallbacks_; }
  // Registrations searched again after failing, and those recovered that way.
  long recovery_searches() const { return recoveries_; }
  long recovered() const { return recovered_; }
  const LoopClosureCounts& loops() const { return loops_; }
  // Beams of scans and keyframes left out as moving objects (MovingObjectOptions).
  long moving_beams() const { return moving_beams_; }
  // Every loop-closure search, in order.
  std::vector<LoopSearch> loop_searches() const { return {searches_.begin(), searches_.end()}; }
  const std::vector<PoseGraphSummary>& optimizations() const { return optimizations_; }
  // Wall time spent in each part, ms. The loop search may run beside the others
  // (background_loop_search); loop_wait_ms is how long the front end waited for it.
  struct Times {
    double registration_ms = 0, keyframe_ms = 0, moving_ms = 0, submap_ms = 0, loop_search_ms = 0,
           loop_wait_ms = 0, optimization_ms = 0;
  };
  const Times& times() const { return times_; }
  kernel::Status health() const { return health_; }

 private:
  // Whether the loop search runs on the second thread (background_loop_search).
  bool BackgroundLoopSearch() const;
  // Update, registering the scan when `localised` is null, else taking that pose.
  void Step(const kernel::Scan& raw_scan, const kernel::Pose2& robot_T_laser,
            const kernel::Pose2* localised,
            const std::function<kernel::Pose2(const kernel::Pose2&)>* correct = nullptr);
  // `scan` is clipped to the usable range.
  void AddKeyframe(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser,
                   std::vector<OrientedPoint> points);
  // The keyframe's points, curves, raster and view from its reading (points: already computed).
  void FillKeyframe(std::vector<OrientedPoint> points, Keyframe* kf);
  // The scan's points (robot frame, with normals).
  std::vector<OrientedPoint> ScanPoints(const kernel::Scan& scan,
                                        const kernel::Pose2& robot_T_laser) const;
  // The beams of `scan` (clipped, at pose_, registered) on objects that the last
  // moving_keyframes keyframes' scans saw through, sorted; takes out of those keyframes the
  // objects that `scan` sees through.
  std::vector<std::size_t> MovingBeams(const kernel::Scan& scan,
                                       const kernel::Pose2& robot_T_laser);
  // Drops the keyframe's reading: it has left the last moving_keyframes, or was trimmed.
  static void ForgetReading(Keyframe* kf);
  // Beams longer than this are not used: max_range_m, or the laser's range when it is 0.
  double UsableRange(const kernel::Scan& scan) const;
  // The raster of these keyframes in the world frame (trimmed ones add nothing).
  std::vector<OrientedPoint> WorldRaster(const std::vector<int>& keyframes) const;
  // Their views (or those of their beams that returned) rasterised at resolution_m, from their
  // Keyframe::rasters[slot] (0: the submap's, 1: the loop targets'), made again where stale.
  std::vector<const ViewCells*> ViewsOf(const std::vector<int>& keyframes, int slot,
                                        double resolution_m, bool by_hits = false) const;
  // A loop target: the candidate and up to loop.target_keyframes keyframes holding data on
  // either side of it, none newer than `newest`.
  std::vector<int> TargetKeyframes(int candidate, int newest) const;
  // A wide search's target: every keyframe holding data within radius_m of `center`, none newer
  // than `newest`. Around a candidate alone, a target of a few metres of path shares more with a
  // query shifted towards it than with the query where it is, and the correlative score, which
  // counts every query point, prefers the shift (docs/graph_slam.md, "Large simulated worlds").
  std::vector<int> AreaKeyframes(const Eigen::Vector2d& center, double radius_m, int newest) const;
  // Brings the submap up to the last keyframe: inserts the new keyframes or builds it anew (see
  // submap_insert_keyframes).
  void UpdateSubmap();
  // Drops keyframe j's data when an earlier keyframe holding its own is near (trim_spacing_m).
  void TrimKeyframe(int j);
  // Registers a scan at the predicted pose against the submap (see recovery_window_m).
  RegistrationResult RegisterScan(const std::vector<OrientedPoint>& points);
  // One loop-closure search (MatchLoop): its record, and the closure when it passed the tests.
  struct LoopFinding {
    LoopSearch record;
    std::optional<PoseGraphEdge> edge;
    bool near = false;  // by the first search (see AddFinding)
  };
  // The searches of keyframe k, made when the front end had travelled travelled_m.
  struct LoopSearchRun {
    int keyframe = -1;
    double travelled_m = 0.0;
    std::vector<LoopFinding> findings;  // in search order
    double time_ms = 0.0;
  };
  // Starts the searches of the new keyframe k (background_loop_search), to be collected at the
  // next keyframe; none before keyframe loop.min_gap_keyframes. Only one runs at a time.
  void StartLoopSearch(int k);
  // Waits for the running search and adds what it found (pending_, counters, FlushClosures).
  void CollectLoopSearch();
  // Searches keyframe k against earlier ones, `since_m` travelled since the last closure, with
  // `query` (its points and those of the loop.query_keyframes before it, in its frame, thinned
  // to loop.resolution_m). Reads keyframes up to k - loop.min_gap_keyframes, keyframe k's pose
  // and the graph, and writes nothing but the loop targets' cache and those keyframes' view
  // rasters for loop targets (Keyframe::rasters[1]): it may run beside the front end.
  LoopSearchRun SearchLoopClosures(int k, double travelled_m, double since_m,
                                   const std::vector<OrientedPoint>& query);
  // Adds the largest set of pending closures that agree (confirm_keyframes), optimises, and
  // removes those that then disagree with the graph. Unconfirmed closures older than
  // confirm_keyframes, or all when `final`, are dropped. `travelled_m`: the travel at the
  // keyframe whose search found the latest closures.
  void FlushClosures(bool final, double travelled_m);
  // Whether closures a and b put the newer of their keyframes at the same pose.
  bool Agree(const PoseGraphEdge& a, const PoseGraphEdge& b) const;
  // The front-end edge model (edge_sigma_m, ...) for this travel and turn.
  Eigen::Matrix3d EdgeCovariance(double distance_m, double turn_rad) const;
  // Covariance of the front-end edge from keyframe `to` - 1 to `to`.
  Eigen::Matrix3d FrontEndCovariance(int to) const;
  // Searches keyframe k's query against the candidate's target within the windows; the closure
  // when the match passes the tests. Records the search in *record.
  std::optional<PoseGraphEdge> MatchLoop(int k, const std::vector<OrientedPoint>& query,
                                         int candidate, double window_m, double window_rad,
                                         LoopSearch* record);
  // The wide search of LoopClosureOptions at keyframe k, whose first window was near_m wide.
  void SearchWide(int k, const std::vector<OrientedPoint>& query, double near_m,
                  std::vector<LoopFinding>* findings);
  // Records a search of keyframe k; a closure it found waits in pending_. One found by the first
  // (`near`) search restarts, at travelled_m, the travel that widens that search's radius.
  void AddFinding(int k, LoopFinding finding, double travelled_m);
  // Optimises the keyframes from first_free on (all: 0), then moves the current pose with its
  // keyframe.
  void Optimize(int first_free = 0);
  // Adds `closures` (found by these searches_) and optimises the whole graph; then removes the
  // closures that disagree with it (those added and those that waited in it unoptimised) and
  // optimises again from where it was. `travelled_m` as for FlushClosures.
  void AddAndOptimize(const std::vector<PoseGraphEdge>& closures,
                      const std::vector<int>& closure_searches, double travelled_m);
  // The first keyframe that a local optimisation for these closures frees: the last
  // local_optimization_keyframes keyframes and each closure's newer one (0: the whole graph).
  int LocalWindow(const std::vector<PoseGraphEdge>& closures) const;
  // Merges the queued keyframes (merge_queue_) that may be merged; called after a whole
  // optimisation, when every closure in the graph has been checked against it.
  void MergeTrimmed();
  // Whether closures that each agree with the graph (whitened squared residuals summing to chi2)
  // wait unoptimised: the graph has grown by less than deferred_optimization_fraction since its
  // last whole optimisation, and with those waiting already they still agree with it as a whole.
  bool DeferOptimization(double chi2, int closures) const;
  // A loop target's field and likelihood pyramid, built from these keyframes at these poses;
  // kept for the next searches of the same keyframes until one of them moves (an optimisation
  // of part of the graph leaves the older keyframes where they were).
  struct LoopTarget {
    std::vector<int> keyframes;
    std::vector<Eigen::Vector3d> poses;  // PosesOf(keyframes) when it was built
    std::unique_ptr<DistanceGrid> grid;
    std::unique_ptr<LikelihoodPyramid> pyramid;  // of *grid
  };
  const LoopTarget& Target(const std::vector<int>& keyframes);
  // The keyframes' poses (x, y, theta).
  std::vector<Eigen::Vector3d> PosesOf(const std::vector<int>& keyframes) const;

  GraphSlamOptions options_;
  kernel::Pose2 pose_;
  std::vector<Keyframe> keyframes_;
  PoseGraph graph_;
  DistanceGrid submap_;
  std::unique_ptr<LikelihoodPyramid> submap_scores_;  // of submap_
  bool submap_dirty_ = true;                          // to be built anew
  int submap_first_ = 0, submap_last_ = -1;           // its first and last keyframe
  long submap_builds_ = 0, submap_inserts_ = 0;
  bool force_keyframe_ = false;
  bool recovered_since_keyframe_ = false;  // a recovery search placed a scan since the last one
  // A marked node: keyframe_T_node of its keyframe, or (keyframe -1, until the next keyframe is
  // made) its pose in the world.
  struct NodeAnchor {
    int keyframe = -1;
    kernel::Pose2 pose;
  };
  std::vector<NodeAnchor> nodes_;
  double travelled_m_ = 0.0;
  kernel::Pose2 since_update_;  // odometry since the last registered scan
  bool registered_ = false;
  long moving_beams_ = 0;
  // Every scan's pose, as the run's record (Trajectory): keyframe^-1 * scan pose, in floats (a
  // scan lies within metres of its keyframe: micrometres), 16 bytes a scan; in a deque, which
  // grows by blocks where a vector would double.
  struct ScanAnchor {
    int keyframe;
    float x, y, theta;
  };
  std::deque<ScanAnchor> scans_;
  std::vector<PoseGraphEdge> pending_;  // closures found, not yet in the graph
  std::vector<int> pending_searches_;   // their searches_ indices
  std::deque<LoopSearch> searches_;     // the run's record of every search
  double closure_at_m_ = 0.0;           // travelled when the last closure was found
  std::vector<LoopTarget> targets_;     // the last loop targets built (Target; loop search only)
  int unflushed_since_ = -1;            // keyframe of the first closure found since the last flush
  long registrations_ = 0, fallbacks_ = 0, recoveries_ = 0, recovered_ = 0, trimmed_ = 0;
  int optimized_nodes_ = 0;  // the graph's nodes at its last whole optimisation
  // Keyframes trimmed for an earlier one beside it, with that one: merged after a whole
  // optimisation (MergeTrimmed), when no closure still waiting for confirmation reaches them and
  // the graph ties them to that one; dropped (kept as nodes) after two such checks.
  struct QueuedMerge {
    int keyframe, into;
    int checks = 0;
  };
  std::vector<QueuedMerge> merge_queue_;
  // The closures added since then without an optimisation: their edges (indices, ascending),
  // their searches (searches_ indices) and the sum of their whitened squared residuals.
  std::vector<int> deferred_edges_, deferred_searches_;
  double deferred_chi2_ = 0.0;
  long deferred_optimizations_ = 0;
  LoopClosureCounts loops_;
  std::vector<PoseGraphSummary> optimizations_;
  Times times_;
  std::size_t map_curves_ = 0, map_control_points_ = 0;
  kernel::Status health_;
  // The loop search's thread (background_loop_search); null when it runs on the calling thread.
  std::unique_ptr<Background> background_;
  // The latest keyframe's loop search (StartLoopSearch), waited for by the destructor.
  std::future<LoopSearchRun> loop_run_;
};

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_POSE_GRAPH_GRAPH_SLAM_H_
