#ifndef SPLAM_SIM_ROBOT_H_
#define SPLAM_SIM_ROBOT_H_

#include <string>

#include "kernel/options.h"
#include "kernel/pose2.h"
#include "kernel/random.h"
#include "kernel/status.h"

namespace splam::sim {

// A differential-drive robot the size of a Pioneer P3-DX, collision-checked as a disc.
struct RobotOptions {
  double radius_m = 0.267;               // P3-DX swing radius
  double max_linear_speed_mps = 1.2;     // |v| limit applied to every command
  double max_angular_speed_radps = 5.2;  // |w| limit (300 deg/s)

  // Describes every field (key, unit, comment) to a visitor: the YAML form.
  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

// Odometry error model (SPEC §2): Gaussian noise on the increment (dx, dy, dtheta) between two
// poses, with standard deviations proportional to the motion, after the odometry models of
// Stage and Thrun et al. with errors of a few per cent:
//   sigma_dx  = forward_per_m * d,   sigma_dy = lateral_per_m * d,
//   sigma_dth = rotation_per_rad * |dtheta| + rotation_per_m * d,   d = |(dx, dy)|.
struct OdometryNoiseOptions {
  double forward_per_m = 0.03;     // m of forward error per m travelled (3 %)
  double lateral_per_m = 0.01;     // m of sideways error per m travelled (1 %)
  double rotation_per_rad = 0.03;  // rad of heading error per rad turned (3 %)
  double rotation_per_m = 0.01;    // rad of heading error per m travelled (0.57 deg/m)

  // Describes every field (key, unit, comment) to a visitor: the YAML form.
  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
  static OdometryNoiseOptions Noiseless() { return {0.0, 0.0, 0.0, 0.0}; }
  // Every sigma times `factor`.
  OdometryNoiseOptions Scaled(double factor) const {
    return {forward_per_m * factor, lateral_per_m * factor, rotation_per_rad * factor,
            rotation_per_m * factor};
  }
};

using kernel::UnicycleIncrement;  // the motion model lives in kernel/pose2.h

// The increment as odometry measures it: `increment` plus noise drawn from `options`.
kernel::Pose2 CorruptIncrement(const kernel::Pose2& increment, const OdometryNoiseOptions& options,
                               kernel::Random* random);

}  // namespace splam::sim

#endif  // SPLAM_SIM_ROBOT_H_
