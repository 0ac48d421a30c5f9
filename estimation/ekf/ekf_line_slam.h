#ifndef SPLAM_ESTIMATION_EKF_EKF_LINE_SLAM_H_
#define SPLAM_ESTIMATION_EKF_EKF_LINE_SLAM_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "estimation/ekf/ekf_core.h"
#include "estimation/ekf/landmark_candidates.h"
#include "estimation/map_line.h"
#include "estimation/models.h"
#include "kernel/lines.h"
#include "kernel/options.h"
#include "kernel/pose2.h"
#include "kernel/scan.h"
#include "kernel/status.h"

namespace splam::estimation {

// How an EKF pairs observations with landmarks inside the gate.
enum class EkfAssociation {
  kNearestNeighbour,    // one pairing at a time, nearest first (paper 001)
  kJointCompatibility,  // JCBB: the largest jointly compatible set (joint_compatibility.h)
};

struct EkfLineSlamOptions {
  OdometryNoiseModel odometry;
  // How lines and corners are extracted from every scan (kernel::ExtractLines).
  kernel::LineExtractionOptions extraction;
  bool use_corners = true;  // corners as point landmarks (the classic EKF of paper 003 §2.2)

  // Measurement noise: a line's covariance is the TLS covariance from the point noise, a corner's
  // is propagated from its two lines; both plus these floors (model error: real walls are not
  // perfectly straight, corners not perfectly sharp).
  double line_rho_floor_m = 0.01;
  double line_theta_floor_rad = 0.005;
  double corner_sigma_m = 0.02;

  // Association with the Mahalanobis distance, gated at this chi-square probability (2 dof;
  // 0.95 -> 5.99 as in paper 001): nearest neighbour, or JCBB over the pairings inside the gate
  // with its joint gate at the same probability (2k dof for k pairings).
  EkfAssociation association = EkfAssociation::kNearestNeighbour;
  double gate_probability = 0.95;
  // An unassociated observation becomes a new landmark only when it is outside this larger gate
  // of every landmark (0.999 -> 13.8); in between it is ambiguous and ignored.
  double new_landmark_probability = 0.999;
  // An unassociated observation that is clearly new becomes a candidate (kept outside the state,
  // in the world frame); it becomes a landmark when seen again in at least this many scans
  // within candidate_max_age_scans. Spurious lines (people, clutter, noise) never enter the state,
  // which keeps the filter small on long real logs. 1 adds landmarks at once.
  int min_observations_to_add = 3;
  int candidate_max_age_scans = 10;
  // Candidates match when their world lines differ by at most these, and corners by
  // corner_max_distance_m.
  double candidate_rho_tolerance_m = 0.15;
  double candidate_theta_tolerance_rad = 0.05;
  // New line landmarks need this much support.
  double min_new_line_length_m = 0.5;
  int min_new_line_points = 10;
  // A corner is compared only with corner landmarks within this distance (D_min of paper 003).
  double corner_max_distance_m = 0.5;
  // An observed segment associates with a line landmark only when it overlaps the landmark's
  // extent or extends it across a gap of at most this much.
  double max_extension_gap_m = 1.0;
  // ... and extends it only when both its ends lie within this distance of the corrected line.
  double max_extension_offset_m = 0.2;

  // Describes every field (key, unit, comment) to a visitor: the YAML form.
  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

// What one update did.
struct UpdateReport {
  int line_observations = 0;
  int corner_observations = 0;
  int associated = 0;  // observations used to correct the state
  int new_landmarks = 0;
  int ambiguous = 0;    // neither inside the gate nor clearly new
  int too_small = 0;    // unassociated lines too short to start a landmark
  int candidates = 0;   // clearly new observations kept as (or matched to) candidates
  long jcbb_nodes = 0;  // hypotheses JCBB tested (association: jcbb)
};

// EKF-SLAM with line (rho, theta) and corner (x, y) landmarks (SPEC §2-4, paper 001 and the
// classic EKF of paper 003 §2.2). State X = [x, y, th, landmarks...], P its full covariance.
class EkfLineSlam {
 public:
  EkfLineSlam(const kernel::Pose2& initial_pose, const Eigen::Matrix3d& initial_covariance,
              const EkfLineSlamOptions& options = {});

  // Prediction with an odometry increment (dx, dy, dth) in the robot frame (SPEC §2): only the
  // robot block and the robot-landmark cross-covariances change.
  void Predict(const kernel::Pose2& odometry_increment);
  // Extracts lines (and corners) from a scan taken by a laser at robot_T_laser, associates them,
  // corrects the state (EkfCore::Correct) and adds new landmarks.
  UpdateReport Update(const kernel::Scan& scan,
                      const kernel::Pose2& robot_T_laser = kernel::Pose2());
  // The same from already extracted features, given in the laser frame.
  UpdateReport Update(const kernel::LineExtraction& features, const kernel::Pose2& robot_T_laser);

  kernel::Pose2 pose() const { return ekf_.pose(); }
  Eigen::Matrix3d pose_covariance() const { return ekf_.pose_covariance(); }
  const Eigen::VectorXd& state() const { return ekf_.state(); }
  const Eigen::MatrixXd& covariance() const { return ekf_.covariance(); }
  std::size_t num_lines() const { return lines_.size(); }
  std::size_t num_corners() const { return corners_.size(); }
  std::vector<MapLine> MapLines() const;
  std::vector<MapCorner> MapCorners() const;
  // False once the state or covariance is not finite or P lost positive diagonal entries; the
  // message says what happened. An unhealthy filter ignores further input.
  bool healthy() const { return ekf_.healthy(); }
  const kernel::Status& health() const { return ekf_.health(); }

 private:
  struct LineLandmark {
    Eigen::Index index;   // of rho in the state; theta follows
    double s_min, s_max;  // extent along the line direction (-sin theta, cos theta)
    int observations;
  };
  struct CornerLandmark {
    Eigen::Index index;
    int observations;
  };
  struct Observation;

  // Keeps line landmark `index` in normal form (rho >= 0, theta wrapped) after a correction.
  void NormaliseLine(LineLandmark* landmark);
  void ExtendLine(LineLandmark* landmark, const Eigen::Vector2d& a_world,
                  const Eigen::Vector2d& b_world);

  EkfLineSlamOptions options_;
  double gate_ = 0.0, new_gate_ = 0.0;
  EkfCore ekf_;
  std::vector<LineLandmark> lines_;
  std::vector<CornerLandmark> corners_;
  // Candidate landmarks: a line (rho, theta) or a corner (x, y), world frame.
  struct Candidate {
    bool is_line;
    Eigen::Vector2d value;
  };
  LandmarkCandidates<Candidate> candidates_;
  std::size_t scans_ = 0;
};

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_EKF_EKF_LINE_SLAM_H_
