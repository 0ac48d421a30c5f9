#ifndef SPLAM_EXPLORATION_ROBOT_INTERFACE_H_
#define SPLAM_EXPLORATION_ROBOT_INTERFACE_H_

#include <optional>
#include <vector>

#include "kernel/pose2.h"
#include "kernel/scan.h"

// What an explorer needs from a robot, simulated or real: velocity commands, odometry, a laser
// and (optionally) a ring of sonars. The simulator is plugged in by a few lines of glue (see
// runtime/simulated_robot.h and examples/exploration).
namespace splam::exploration {

// The fixed facts about the robot that planning and perception use.
struct RobotDescription {
  double radius_m = 0.267;      // the robot is a disc of this radius (P3-DX swing radius)
  double time_step_s = 0.1;     // duration of one Step()
  kernel::Pose2 robot_T_laser;  // laser mounting pose
  std::vector<kernel::Pose2> robot_T_sonar;   // sonar mounting poses; empty when there are none
  double sonar_cone_half_angle_rad = 0.2618;  // each sonar sees a cone of +- this
  double sonar_max_range_m = 5.0;             // a sonar with no echo reads beyond this
};

// One reading of the robot.
struct Perception {
  double time_s = 0.0;
  kernel::Pose2 odometry_pose;             // integrated wheel odometry
  std::optional<kernel::Pose2> true_pose;  // ground truth: only a simulator has it
  kernel::Scan scan;                       // laser sweep; empty when only odometry was read
  std::vector<double> sonar_ranges_m;      // one per sonar (Scan::kNoReturn: no echo)
};

class RobotInterface {
 public:
  virtual ~RobotInterface() = default;
  virtual const RobotDescription& description() const = 0;
  // Drives at (v, w) for one time step. False when the robot refused (the motion would collide)
  // and did not move.
  virtual bool Step(double v_mps, double w_radps) = 0;
  // Odometry (and ground truth) only: cheap, for localisations that need no scans.
  virtual Perception ReadOdometry() = 0;
  // Odometry plus laser and sonar readings.
  virtual Perception Sense() = 0;
};

}  // namespace splam::exploration

#endif  // SPLAM_EXPLORATION_ROBOT_INTERFACE_H_
