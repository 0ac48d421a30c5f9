#ifndef SPLAM_ESTIMATION_TOPOLOGICAL_TOPOLOGICAL_SLAM_H_
#define SPLAM_ESTIMATION_TOPOLOGICAL_TOPOLOGICAL_SLAM_H_

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "estimation/models.h"
#include "estimation/pose_graph/graph_slam.h"
#include "estimation/spline_association.h"
#include "estimation/topological/topological_correction.h"
#include "kernel/local_safe_region.h"
#include "kernel/options.h"
#include "kernel/pose2.h"
#include "kernel/scan.h"
#include "kernel/spline_extraction.h"
#include "kernel/status.h"

namespace splam::estimation {

// How the pose is corrected from the associated curves.
enum class TopologicalCorrection {
  // Heading and position together, from the distances of points along every matched stretch to
  // their map curves (SolvePoseCorrection), the projections re-computed kPointToCurveIterations
  // times: a position error is not read as a heading error.
  kPointToCurve,
  // Paper 003 eqs. 7-10: the heading from the chords of the matched stretches, then the
  // translation from their points at that heading.
  kPaper,
};

// Where each scan's prediction comes from.
enum class TopologicalPrediction {
  // The odometry increment refined by registering the scan against a submap of recent scans
  // (the graph SLAM's front end, without its loop closure and pose graph).
  kScanMatching,
  // Paper 003: the odometry increment.
  kOdometry,
};

struct TopologicalSlamOptions {
  // The prediction. scan_matching, because the curves alone localise too few scans to hold the
  // odometry's drift on real logs: most scans pair no point with a map curve (the map is only
  // extended after a localisation), and with the odometry's prediction the method ends worse
  // than odometry in rotation (docs/real_data.md).
  TopologicalPrediction prediction = TopologicalPrediction::kScanMatching;
  // scan_matching: the front end (registration, submap, odometry test, recovery search). Its
  // loop closure is off; `topological-graph` adds the graph SLAM's loop closure behind the
  // topological SLAM instead.
  GraphSlamOptions scan_matching = ScanMatchingDefaults();
  // scan_matching: the prediction's covariance grows with the odometry noise model's sigmas
  // times this factor while the scans register (and with the model itself when a scan falls
  // back to odometry). 0.1: in REG explorations of `complex` (seeds 1-10) the front end alone
  // drifted 0.13 deg and 6 mm per metre travelled (0.58 rad turned), the scaled model allows
  // 0.16 deg and 3 mm; the odometry itself drifted 0.38 deg.
  double scan_matching_noise_scale = 0.1;
  // scan_matching: the corrected pose goes back to the front end before the scan becomes one of
  // its keyframes, so that its submap is built at the corrected poses (GraphFrontEnd::
  // Settle). Without it the front end registers on its own, in a frame that drifts from
  // the curve map's, and only its increments are used: in REG explorations the corrections then
  // held the heading 0.5-1 deg off against the front end's drift (`complex` seeds 1-10: 0.082 m
  // mean position RMSE; `halls` seeds 1-3: 0.076, 0.112, 0.160 m). With it: 0.065 m; 0.033,
  // 0.050, 0.034 m. But the front end then follows the curve map wherever it is wrong, and only
  // a back end that moves the map (topological-graph, where it is on) undoes that: alone, on the
  // real logs, intel went from 0.645 to 0.932 m and mit-csail from 0.058 to 1.577 m (relations
  // metric; its map drawn twice, turned). false: the front end stays an independent check.
  bool scan_matching_feedback = false;

  // How curves are extracted from every scan (segmentation, fit, curvature, features).
  kernel::SplineExtractionOptions extraction;
  // Paper 000's curvature association (inflection points and corners paired by type and
  // curvature), with its coarse test of mu_min control points within d_min.
  SplineAssociationOptions association;
  // Beams longer than this are not used for curves, metres (0: the laser's maximum range).
  double max_curve_range_m = 0.0;

  // The local region (SPEC §10): association only against the map curves that have a point
  // inside the LSR of the last exploration node, widened by this margin (the curves lie on the
  // LSR's boundary), metres.
  double region_margin_m = 0.3;
  // Without an explorer (a log), or when the robot has driven more than alpha r from
  // the last node's LSR (REG's FIND_PATH through the graph), the LSR of radius r
  // of the current scan becomes the region: a virtual node. REG's r and alpha r, metres.
  // REG's r and alpha r; set from the explorer's options (or the local_region section of a
  // configuration) through SlamContext, so both use the same values.
  kernel::LocalRegionOptions region;

  TopologicalCorrection correction = TopologicalCorrection::kPointToCurve;
  // Point-to-curve: a direction of the pose is corrected only when the points constrain it at
  // least as much as this many points whose curve normal lies along it (SolvePoseCorrection):
  // along one straight wall the fitted curves' normals wobble by a few degrees, and without
  // this test the pose slid 0.1 m along the wall per correction (`complex` route, seed 9).
  double min_information = 3.0;
  // Point-to-curve: the corrected pose is fused with the prediction as a measurement (a pose-only
  // Kalman update) whose information is sum_i C_i J_i^T J_i / point_sigma_m^2 over the verified
  // points (every point_spacing_m along the stretches), in the directions they constrain; the
  // prediction's covariance grows with the odometry noise model. The gain then follows how much
  // the odometry and the curves each know, where a constant gain (correction_gain, the paper
  // formulation) passed the centimetre noise of every scan's curves into the heading while
  // odometry drifted by a tenth of a degree (`complex` route, seed 6, along the south wall).
  // sigma: range noise, fit and map errors of a point together, metres.
  double point_sigma_m = 0.03;
  OdometryNoiseModel odometry;
  // Associate and correct; repeated this many times, each round associating at the pose the
  // previous one corrected.
  int correction_rounds = 2;
  // The start and end points of a matched stretch are taken this far inside it: the last span of
  // a fitted B-spline bends with the noise of the last few points (metres).
  double end_trim_m = 0.2;
  // Chords shorter than this give no heading (their direction is noise), metres.
  double min_chord_length_m = 0.5;
  // The translational correction pairs the start and end points of every matched stretch and,
  // between them, points this far apart along it (and the paired features); 0: only the start
  // and end points, as paper 003 writes eqs. 9-10. Intermediate points average the range noise
  // that makes the two end points alone jitter by centimetres. Metres.
  double point_spacing_m = 0.2;
  // Reliability C_i of a matched stretch (eq. 8): curves whose features paired weigh most, then
  // straight stretches (no sample farther than line_flatness_m from the chord), then smooth
  // curves. The weight of a chord is C_i times its squared length in m^2 (the direction error of a
  // chord falls as 1 / length).
  double feature_weight = 3.0;
  double line_weight = 2.0;
  double curve_weight = 1.0;
  double line_flatness_m = 0.02;
  CorrectionLossOptions loss;

  // Fraction of the verified correction applied at each scan (1: all of it, as paper 003 does
  // at its nodes). Applied at every scan of a 10 Hz laser, the full correction passes the
  // centimetre jitter of the two-step solution into the pose and, through map extension, into
  // the map; a gain below 1 averages it over a few scans (a constant-gain observer).
  double correction_gain = 0.3;
  // A correction larger than this cannot come from odometry drift since the last update: it is
  // a wrong association (a round obstacle fits any rotation about its centre) and fails
  // verification. Radians and metres.
  double max_heading_correction_rad = 0.1;
  double max_translation_correction_m = 0.3;
  // VERIFY_LOCALIZATION: after the correction every matched start and end point must lie within
  // this distance of its map curve, and every paired feature of its map feature, metres.
  double verify_threshold_m = 0.15;
  // A localisation that verifies fewer curves than this keeps the odometric prediction.
  int min_verified_curves = 2;
  // ... and the root mean square distance of the stretch's points to the map curve must stay
  // under this (0: not checked), metres.
  double verify_rms_m = 0.05;
  // ... and the verified stretches must lie closer to their map curves (mean squared distance of
  // points every 0.1 m) at the corrected pose than at the prediction. Paper 003 checks only the
  // corrected pose: a raw 4 deg turn of two short curves passed it on the `complex` route (seed 5,
  // scan 201) and the map then agreed with the wrong heading. With this test the route's seeds
  // 1-10 went from 0.074-0.346 m (3 worse than odometry) to 0.037-0.135 m with the paper's
  // correction (docs/methods.md). With the point-to-curve correction it does not help: REG
  // explorations of `complex` (seeds 1-10) averaged 0.158 m with it, 0.139 m without. false: the
  // paper's test.
  bool verify_improves = false;

  // Dense refinement (point_to_curve): after the association, the points of every observed curve
  // (every point_spacing_m between its trimmed ends, not only the associated stretches) are
  // paired with the nearest local map curve, within max_translation_correction_m in the first
  // of kPointToCurveIterations rounds and verify_threshold_m in the others, where the two
  // curves run alike (tangents within dense_max_angle_rad), and the pose is solved again from
  // all of them. It stands, and is fused in place of the associated stretches' correction, when
  // at least dense_min_points points pair, their RMS distance is at most verify_rms_m and the
  // correction stays within the plausible bounds. The curvature association pairs a scan's curve
  // with a map curve only when its features or its coarse test agree; a scan whose curves the
  // association misses (clutter, a short view of a wall) is still measured against the map.
  bool dense_refinement = true;
  int dense_min_points = 10;
  double dense_max_angle_rad = 0.5;

  // The map is extended when the robot has moved this far or turned this much since the last
  // extension (and at every exploration node), metres and radians.
  double map_update_distance_m = 0.5;
  double map_update_angle_rad = 0.35;
  // A curve no map curve comes near (no point within association.d_min_m) becomes a new object
  // when it is at least this long and has this many points.
  double min_new_curve_length_m = 0.5;
  int min_new_curve_points = 10;
  // A map curve whose matched stretch reaches its end (within end_tolerance_m) is extended by
  // splicing when the observation continues at least min_extension_length_m beyond it, metres.
  double min_extension_length_m = 0.3;
  double end_tolerance_m = 0.1;
  int max_control_points = 400;  // a map curve stops growing here

  // Side of the grid cells that index the map curves, metres.
  double index_cell_m = 1.0;

  static GraphSlamOptions ScanMatchingDefaults();
  // Describes every field (key, unit, comment) to a visitor: the YAML form.
  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

struct TopologicalUpdateReport {
  int observed_curves = 0;
  int local_map_curves = 0;  // map curves in the local region
  int associated_curves = 0;
  bool localized = false;          // a correction passed VERIFY_LOCALIZATION
  bool used_fallback = false;      // ... with individual curves, after the whole set failed
  bool scan_matched = false;       // the prediction's registration stood (scan_matching)
  bool dense = false;              // the dense refinement stood (dense_refinement)
  int dense_points = 0;            // ... from this many points
  bool refused_no_better = false;  // verified, but no closer to the map than the prediction
  int verified_curves = 0;
  double heading_correction_rad = 0.0;
  Eigen::Vector2d translation_correction = Eigen::Vector2d::Zero();
  bool map_updated = false;
  int added_curves = 0, extended_curves = 0;
  SolverCounts solver;  // the corrections' least-squares solves
};

// Topological B-spline SLAM (SPEC §10, paper 003 §3.2): no covariance. The pose is predicted
// with odometry, corrected by the curves associated in the local region (heading, then
// translation, as weighted least squares), and the map of curves grows by new objects and by
// splicing control points onto the curves that the robot sees continue. The cost of an update
// depends on the curves in the local region, not on the size of the map: the map curves are
// found through a uniform grid.
class TopologicalSlam {
 public:
  // Invalid options leave it unhealthy (health() says why); it then ignores input.
  explicit TopologicalSlam(const kernel::Pose2& initial_pose,
                           const TopologicalSlamOptions& options = {});

  void Predict(const kernel::Pose2& odometry_increment);
  // The LSR of the newest exploration node (world frame, placed at the estimate); the map is
  // extended at the next update.
  void SetLocalRegion(const kernel::LocalSafeRegion& region);
  TopologicalUpdateReport Update(const kernel::Scan& scan,
                                 const kernel::Pose2& robot_T_laser = kernel::Pose2());

  kernel::Pose2 pose() const { return pose_; }
  // scan_matching: the scan matcher (nullptr with the odometry's prediction).
  const GraphSlam* scan_matcher() const { return scan_matcher_.get(); }
  GraphSlam* scan_matcher() { return scan_matcher_.get(); }
  std::size_t num_curves() const { return curves_.size(); }
  std::size_t num_control_points() const;
  // The map curves with their samples, curvature and features (world frame).
  const std::vector<kernel::SplineCurve>& curves() const { return curves_; }
  std::vector<MapSpline> MapSplines() const;
  bool healthy() const { return health_.ok(); }
  const kernel::Status& health() const { return health_; }
  const TopologicalSlamOptions& options() const { return options_; }

  // Adds a curve to the map as it is (world frame), e.g. a prior map or a benchmark's.
  void AddMapCurve(kernel::SplineCurve curve);

  // After a pose-graph optimisation behind this SLAM (method topological-graph): every map curve
  // i moves rigidly by the world-frame correction correction(i) (new = correction(i) * old), the
  // pose becomes `pose`, and the local region moves with the pose.
  void Reanchor(const std::function<kernel::Pose2(int curve)>& correction,
                const kernel::Pose2& pose);

 private:
  struct Association;
  // The local region as a star-shaped radial function: the range of its boundary by bearing.
  struct RegionShape {
    Eigen::Vector2d center = Eigen::Vector2d::Zero();
    std::vector<double> bearings_rad, ranges_m;  // sorted by bearing in (-pi, pi]
    bool full_circle = false;
    double radius_m = 0.0;
    // True when p lies inside the region or within margin_m beyond its boundary (the boundary
    // taken at the larger range of the two vertices around p's bearing).
    bool Near(const Eigen::Vector2d& p, double margin_m) const;
  };
  void SetRegion(const kernel::LocalSafeRegion& region);

  std::vector<int> LocalCurves() const;
  std::vector<Association> Associate(const std::vector<kernel::SplineCurve>& observed,
                                     const kernel::Pose2& pose,
                                     const std::vector<int>& local) const;
  // The correction of `pose` from the associations (options_.correction).
  kernel::Pose2 Correct(const std::vector<kernel::SplineCurve>& observed,
                        const std::vector<Association>& associations, const kernel::Pose2& pose,
                        SolverCounts* solver) const;
  kernel::Pose2 CorrectPointToCurve(const std::vector<kernel::SplineCurve>& observed,
                                    const std::vector<Association>& associations,
                                    const kernel::Pose2& pose, SolverCounts* solver) const;
  // The points of the matched stretches (robot frame), every point_spacing_m between their trimmed
  // ends, with their map curve and weight C_i; and the paired features.
  struct CurvePoints {
    struct Sample {
      Eigen::Vector2d robot;
      const kernel::CubicBSpline* map;
      double weight;
    };
    std::vector<Sample> samples;
    std::vector<PointPair> features;
  };
  CurvePoints PointsOf(const std::vector<kernel::SplineCurve>& observed,
                       const std::vector<Association>& associations) const;
  // Each point paired with its map curve linearised at its projection from `pose`.
  std::vector<CurvePointPair> PairsAt(const CurvePoints& points, const kernel::Pose2& pose) const;
  // The dense refinement from `start` (see dense_refinement): the refined pose and its pairs, or
  // nullopt when it does not stand.
  struct DenseResult {
    kernel::Pose2 pose;
    std::vector<CurvePointPair> pairs;
  };
  std::optional<DenseResult> RefineDense(const std::vector<kernel::SplineCurve>& observed,
                                         const std::vector<int>& local, const kernel::Pose2& start,
                                         const kernel::Pose2& predicted,
                                         SolverCounts* solver) const;
  // scan_matching: pose_ and covariance_ from the front end's registration of the scan, when it
  // stands.
  void PredictByScanMatching(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser,
                             TopologicalUpdateReport* report);
  // From pose_ (the prediction): associates, corrects pose_ and covariance_, extends the map.
  void CorrectAndMap(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser,
                     const std::vector<kernel::SplineCurve>& observed,
                     TopologicalUpdateReport* report);
  // The pose-only Kalman update of pose_ and covariance_ (see point_sigma_m).
  void Fuse(const kernel::Pose2& predicted, const kernel::Pose2& corrected,
            const PoseInformation& information);
  kernel::Pose2 CorrectAsPaper(const std::vector<kernel::SplineCurve>& observed,
                               const std::vector<Association>& associations,
                               const kernel::Pose2& pose, SolverCounts* solver) const;
  bool Verifies(const kernel::SplineCurve& observed, const Association& association,
                const kernel::Pose2& pose) const;
  // The squared distances (m^2) of the matched stretch's points every spacing_m (its trimmed
  // ends included) at `pose` to the map curve, summed; *count grows by their number.
  double SquaredDistances(const kernel::SplineCurve& observed, const Association& association,
                          const kernel::Pose2& pose, double spacing_m, int* count) const;
  // Mean squared distance of the associated stretches' points (every 0.1 m) at `pose` to their
  // map curves, m^2.
  double MeanSquaredDistance(const std::vector<kernel::SplineCurve>& observed,
                             const std::vector<Association>& associations,
                             const kernel::Pose2& pose) const;
  // True when some map curve other than `except` passes within d_min of a point.
  bool NearMap(const std::vector<Eigen::Vector2d>& points, int except) const;
  void ExtendMap(const std::vector<kernel::SplineCurve>& observed,
                 const std::vector<Association>& verified, TopologicalUpdateReport* report);
  void Register(int curve);
  void Unregister(int curve);
  std::int64_t CellKey(const Eigen::Vector2d& p) const;
  static std::int64_t CellKey(std::int64_t ix, std::int64_t iy) {
    return (ix << 32) ^ (iy & 0xffffffff);
  }

  TopologicalSlamOptions options_;
  kernel::Status health_;
  CurvatureAssociation association_;
  kernel::Pose2 pose_;
  Eigen::Matrix3d covariance_ = Eigen::Matrix3d::Zero();  // of pose_ (point_to_curve)
  // scan_matching: the front end, the odometry since the last update, and pose_'s covariance
  // grown with the scaled noise model instead (see scan_matching_noise_scale).
  std::unique_ptr<GraphSlam> scan_matcher_;
  kernel::Pose2 since_update_;  // odometry since the last update, without the feedback
  // scan_matching_feedback: this SLAM's frame seen from the front end's (pose_ = front_frame_ *
  // the front end's pose); it changes only when Reanchor moves the map.
  kernel::Pose2 front_frame_;
  Eigen::Matrix3d scan_matched_covariance_ = Eigen::Matrix3d::Zero();
  std::vector<kernel::SplineCurve> curves_;
  std::vector<int> observations_;
  std::unordered_map<std::int64_t, std::vector<int>> cells_;
  std::vector<std::vector<std::int64_t>> curve_cells_;
  std::optional<RegionShape> region_;
  bool node_pending_ = false;  // a node was set: extend the map at the next update
  std::optional<kernel::Pose2> last_map_update_;
};

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_TOPOLOGICAL_TOPOLOGICAL_SLAM_H_
