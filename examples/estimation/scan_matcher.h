// A SLAM variant of one's own, in one header and one source file: odometry corrected by aligning
// every scan with a recent keyframe scan (point-to-line ICP). It has no map; it only shows the
// shape every method of splam has (an options struct with VisitFields and Validate, and a class
// that implements estimation::SlamMethod).
#ifndef SPLAM_EXAMPLES_ESTIMATION_SCAN_MATCHER_H_
#define SPLAM_EXAMPLES_ESTIMATION_SCAN_MATCHER_H_

#include <string>
#include <vector>

#include "estimation/slam_method.h"
#include "kernel/status.h"

namespace my_lab {

struct ScanMatcherOptions {
  int iterations = 10;                    // ICP rounds (Gauss-Newton steps) per scan
  int beam_step = 5;                      // every beam_step-th hit of the scan is paired
  int normal_half_window = 6;             // keyframe normals from 2 w + 1 neighbouring hits
  double max_pair_distance_m = 0.1;       // nearest neighbours farther apart are not paired
  double point_sigma_m = 0.03;            // noise of a point-to-line distance, m
  double odometry_sigma_fraction = 0.03;  // odometry sigma per m travelled and rad turned
  double odometry_sigma_floor = 0.002;    // m and rad
  int min_pairs = 30;                     // fewer pairs: keep the odometry
  double keyframe_distance_m = 0.5;       // scans are aligned with the keyframe, renewed after
  double keyframe_angle_rad = 0.3;        // this much motion or turning
  double max_correction_m = 0.3;          // larger corrections than odometry are refused, m
  double max_correction_rad = 0.15;       // ... rad

  // The YAML form: `splam config print --method scan-matcher` lists these keys.
  void VisitFields(splam::kernel::FieldVisitor& v);
  splam::kernel::Status Validate() const;  // ok, or the first problem
};

class ScanMatcher : public splam::estimation::SlamMethod {
 public:
  ScanMatcher(const ScanMatcherOptions& options, const splam::estimation::SlamContext& context);

  void Predict(const splam::kernel::Pose2& odometry_increment) override;
  void Update(const splam::kernel::Scan& scan, const splam::kernel::Pose2& robot_T_laser) override;
  splam::kernel::Pose2 pose() const override { return pose_; }
  std::string MapDescription() const override { return "no map"; }
  splam::estimation::SlamStatistics Statistics() const override;

 private:
  ScanMatcherOptions options_;
  splam::kernel::Pose2 pose_;
  splam::kernel::Pose2 key_pose_;          // the estimate at the keyframe
  splam::kernel::Pose2 since_previous_;    // odometry since the keyframe (the ICP's guess)
  std::vector<Eigen::Vector2d> previous_;  // the keyframe's hits, robot frame, beam order
  std::vector<Eigen::Vector2d> normals_;   // their surface normals (zero: none)
  long aligned_ = 0, refused_ = 0;
};

}  // namespace my_lab

#endif  // SPLAM_EXAMPLES_ESTIMATION_SCAN_MATCHER_H_
