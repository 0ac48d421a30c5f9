#ifndef SPLAM_ESTIMATION_EKF_EKF_BSPLINE_SLAM_H_
#define SPLAM_ESTIMATION_EKF_EKF_BSPLINE_SLAM_H_

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "estimation/ekf/bspline_models.h"
#include "estimation/ekf/ekf_core.h"
#include "estimation/ekf/landmark_candidates.h"
#include "estimation/map_spline.h"
#include "estimation/models.h"
#include "estimation/spline_association.h"
#include "kernel/bspline.h"
#include "kernel/options.h"
#include "kernel/pose2.h"
#include "kernel/scan.h"
#include "kernel/spline_extraction.h"
#include "kernel/status.h"

namespace splam::estimation {

struct EkfBSplineSlamOptions {
  OdometryNoiseModel odometry;
  // How curves are extracted from every scan (segmentation, fit, curvature, features).
  kernel::SplineExtractionOptions extraction;
  // "pedraza" or "curvature" (SPEC §7), and their parameters.
  std::string association = "curvature";
  SplineAssociationOptions association_options;
  // How map splines are fitted when they are created or extended (their control points are the
  // state): one control point per this much curve, metres, at most max_control_points per spline.
  kernel::BSplineFitOptions map_fit = {.control_point_spacing_m = 0.3, .max_control_points = 120};

  // Range noise of one beam, as the simulator's lasers: sigma = floor + fraction * range, plus
  // model_sigma_m in quadrature. The model error stands for what the independent-beam model
  // leaves out: a cubic spline is not the obstacle, and the beams of one curve share its error.
  // 0.08 m was calibrated on the `complex` route (mean pose NEES about 3 for 3 dof over 4 seeds;
  // 0.02 m gave 7.8, with the same accuracy). Defaults: the URG-04LX.
  double range_sigma_floor_m = 0.0;
  double range_sigma_fraction = 0.01;
  double model_sigma_m = 0.08;
  // Beams used in one correction are at least this far apart along the observed curve, metres,
  // and at most max_beams_per_match of them.
  double beam_spacing_m = 0.1;
  int max_beams_per_match = 30;
  // A beam is used only when the map point it is predicted to hit (ray-spline intersection) lies
  // within this distance of the map point the association paired with its measured point: the
  // expected and measured points must be the same physical point (the fragility paper 000 notes).
  double max_correspondence_distance_m = 0.15;
  // ... and when its innovation passes a chi-square gate (1 dof) at this probability.
  double beam_gate_probability = 0.99;
  // Which matches correct the state: "longest" (the longest stretches first, one mostly covered
  // by an accepted stretch of the same observed curve dropped: a duplicate map spline of the
  // obstacle), or "jcbb": the largest set of those matches whose selected beams are jointly
  // compatible (joint_compatibility.h; its gate chi^2(beams) at beam_gate_probability), no two of
  // one curve overlapping by half, the longest first in the search.
  std::string match_selection = "longest";
  // Beams meeting the map curve at a grazing angle (sine below this) are not used.
  double min_incidence_sine = 0.2;

  // A curve that no map spline comes near (no control points within d_min) is new. It becomes a
  // candidate when it is at least this long and has this many points, and a map spline once a
  // candidate has been seen (a curve within d_min of it) in min_observations_to_add scans, none
  // more than candidate_max_age_scans after the previous. People and clutter seen once never
  // enter the state. 1 adds new curves at once.
  double min_new_curve_length_m = 0.5;
  int min_new_curve_points = 10;
  int min_observations_to_add = 3;
  int candidate_max_age_scans = 10;
  // Beams longer than this are not used for curves, metres (0: the laser's maximum range):
  // far points are sparse and their curves poor.
  double max_curve_range_m = 0.0;
  // A map spline whose matched stretch reaches its end is extended by the observed curve's
  // continuation when that is at least this long, metres.
  double min_extension_length_m = 0.2;
  // The map stretch "reaches the end" when it ends within this distance of it, metres.
  double end_tolerance_m = 0.05;
  // The old curve enters the refit of an extension as samples this far apart, metres.
  double extension_sample_spacing_m = 0.05;
  // Standard deviation added in quadrature to x and y of every new control point, metres: the
  // fit's covariance from the range noise alone ignores the model error.
  double control_point_sigma_floor_m = 0.01;

  // Describes every field (key, unit, comment) to a visitor: the YAML form.
  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

// One observed curve paired with one map spline in an update.
struct SplineAssociationRecord {
  std::size_t observed_curve = 0;  // index into the scan's curves
  int map_spline = 0;              // id of the map spline
  bool used_features = false;      // paper 000's association paired features
  // Beams of the matched stretch considered for the correction (spaced along it), and those
  // used: the others failed the correspondence test or the innovation gate.
  std::vector<std::size_t> matched_beams;
  std::vector<std::size_t> beams;
  int rejected_beams = 0;
};
// A new map spline, or one extended, and the beams that made it.
struct SplineChangeRecord {
  int map_spline = 0;
  std::vector<std::size_t> beams;
};

struct BSplineUpdateReport {
  int observed_curves = 0;
  int matched_curves = 0;  // observed curves used in at least one correction
  int beams_used = 0;
  int beams_rejected = 0;
  std::vector<SplineAssociationRecord> associations;
  std::vector<SplineChangeRecord> created, extended;
  int ignored_curves = 0;  // near the map but not associated, or too small to start a spline
  int candidates = 0;      // new curves kept as (or matched to) candidates
};

// EKF-SLAM with B-spline obstacles (SPEC §8, Pedraza et al. 2009; paper 000 for the curvature
// association). State X = [x, y, th, X_1,x, X_1,y, ...]: the pose and the control points of every
// map spline, each spline contiguous. The measurement of a beam is its range; its prediction is
// where the beam meets the associated map spline (PredictBeam), with analytic Jacobians.
class EkfBSplineSlam {
 public:
  // Invalid options leave the filter unhealthy (health() says why); it then ignores input.
  EkfBSplineSlam(const kernel::Pose2& initial_pose, const Eigen::Matrix3d& initial_covariance,
                 const EkfBSplineSlamOptions& options = {});

  void Predict(const kernel::Pose2& odometry_increment);
  // Extracts curves from the scan (laser at robot_T_laser), associates them with the map,
  // corrects the state with the associated beams (one batch correction), then extends partially
  // associated splines and adds new ones.
  BSplineUpdateReport Update(const kernel::Scan& scan,
                             const kernel::Pose2& robot_T_laser = kernel::Pose2());

  kernel::Pose2 pose() const { return ekf_.pose(); }
  Eigen::Matrix3d pose_covariance() const { return ekf_.pose_covariance(); }
  const Eigen::VectorXd& state() const { return ekf_.state(); }
  const Eigen::MatrixXd& covariance() const { return ekf_.covariance(); }
  std::size_t num_splines() const { return splines_.size(); }
  std::size_t num_control_points() const { return (ekf_.state().size() - 3) / 2; }
  std::vector<MapSpline> MapSplines() const;
  bool healthy() const { return ekf_.healthy(); }
  const kernel::Status& health() const { return ekf_.health(); }
  const EkfBSplineSlamOptions& options() const { return options_; }

 private:
  struct Landmark {
    int id;
    Eigen::Index index;  // of X_0.x in the state
    std::vector<double> knots;
    int observations;
    Eigen::Index size() const { return static_cast<Eigen::Index>(knots.size() - 4) * 2; }
  };
  struct Match;
  struct ScanContext;

  // The steps of Update. Association at the predicted pose: every observed curve against the
  // map splines whose control points come within d_min (coarse test), then the fine one.
  void Associate(ScanContext* c) const;
  // Longest stretches first; one mostly covered by an accepted stretch of the same observed
  // curve (a duplicate map spline of the same obstacle) is dropped.
  void AcceptLongestMatches(ScanContext* c) const;
  // match_selection "jcbb": of those, the largest jointly compatible set.
  void AcceptJointlyCompatibleMatches(ScanContext* c) const;
  // One EKF correction with the selected beams of every accepted match.
  void CorrectWithBeams(ScanContext* c, BSplineUpdateReport* report);
  // Map splines whose matched stretch reaches their end grow by the observed continuation.
  void ExtendMatchedSplines(const ScanContext& c, BSplineUpdateReport* report);
  // Curves no map spline comes near become candidates, and map splines once seen often enough.
  void AddNewSplines(const ScanContext& c, BSplineUpdateReport* report);

  // The spline of a landmark from the state; SplineOf needs a healthy filter.
  std::optional<kernel::CubicBSpline> TrySplineOf(const Landmark& landmark) const;
  kernel::CubicBSpline SplineOf(const Landmark& landmark) const;
  // Corrects with the beams of `observed` inside the match; fills the record.
  // The rows of one correction: per beam, its Jacobian by the pose and by the 8 control
  // coordinates that shape the curve where it hits, its innovation and variance.
  struct BeamBatch {
    Eigen::MatrixXd h_robot = Eigen::MatrixXd(0, 3);  // first nu.size() rows in use
    std::vector<JacobianBlock> blocks;
    std::vector<double> nu, variance;
  };
  // Adds the beams of `observed` inside the match that pass the correspondence test and the
  // innovation gate; fills the record. `observed` is in the world frame, `beams` its points'
  // beam indices, `map_spline` the matched landmark's curve at the current state.
  void SelectBeams(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser,
                   const kernel::SplineCurve& observed, const std::vector<std::size_t>& beams,
                   const Match& match, const kernel::CubicBSpline& map_spline,
                   SplineAssociationRecord* record, BeamBatch* batch) const;
  // The beams' points at the current pose, and their range variances.
  BeamPoints Beams(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser,
                   const std::vector<std::size_t>& beams) const;
  Eigen::VectorXd RangeVariances(const kernel::Scan& scan,
                                 const std::vector<std::size_t>& beams) const;
  // Appends the control points fitted to the beams' points as a new spline.
  bool AddSpline(const kernel::Scan& scan, const kernel::Pose2& robot_T_laser,
                 const std::vector<std::size_t>& beams);
  // Refits spline `landmark` to its old curve plus the beams' points (continuing it at its start
  // or at its end) and replaces its control points. False when the refit fails.
  bool ExtendSpline(Landmark* landmark, const kernel::Scan& scan,
                    const kernel::Pose2& robot_T_laser, const std::vector<std::size_t>& beams,
                    bool at_end);

  EkfBSplineSlamOptions options_;
  std::unique_ptr<SplineAssociation> association_;
  double beam_gate_ = 0.0;
  EkfCore ekf_;
  std::vector<Landmark> splines_;
  int next_id_ = 0;
  // Candidate map splines: the control points of the last sighting, world frame.
  LandmarkCandidates<std::vector<Eigen::Vector2d>> candidates_;
  std::size_t scans_ = 0;
};

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_EKF_EKF_BSPLINE_SLAM_H_
