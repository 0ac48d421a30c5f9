#ifndef SPLAM_EXPLORATION_MOTION_H_
#define SPLAM_EXPLORATION_MOTION_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "exploration/localization.h"
#include "exploration/robot_interface.h"
#include "kernel/options.h"
#include "kernel/pose2.h"
#include "kernel/status.h"

namespace splam::exploration {

struct ControlInput {
  double v_mps = 0.0;
  double w_radps = 0.0;
};

// MOVE_TO of SRT and REG (paper 003 Fig. 2): at every time step BEST_U picks, from a fixed list
// of control inputs list_U, the one whose predicted motion (held for horizon_s, exact unicycle
// arcs) ends with the lowest cost
//   |goal - p'| + heading_weight * |bearing error'| * min(1, |goal - p'| / 0.5 m)
//              + cross_track_weight * (distance of p' from the line from the leg's start to goal),
// and applies it for one step. The bearing term turns the robot towards the goal before it
// drives (it fades out near the goal, where the bearing is ill-defined); the cross-track term
// keeps it on the straight leg that the planner checked for clearance.
struct MotionOptions {
  std::vector<double> linear_speeds_mps = {0.0, 0.1, 0.25, 0.4};  // list_U: every v ...
  std::vector<double> angular_speeds_radps = {-0.8, -0.4, -0.15, 0.0, 0.15, 0.4, 0.8};  // x w
  double horizon_s = 0.5;  // look-ahead used to judge an input, s
  // While the bearing to the goal is off by more than this, only turns in place are candidates,
  // so that the robot stays on the straight leg that was checked for clearance, rad.
  double turn_in_place_above_rad = 0.35;
  // After a refused step the robot backs off by up to this many steps at -0.1 m/s.
  int back_off_steps = 10;
  double heading_weight_m_per_rad = 0.3;  // m of cost per rad of bearing error
  double cross_track_weight = 2.0;        // m of cost per m off the leg
  double goal_tolerance_m = 0.05;         // the last waypoint is reached within this, m
  double waypoint_tolerance_m = 0.15;     // intermediate waypoints, m
  // A move gives up (reason "timeout") after base + per_meter * path length simulated seconds.
  double timeout_base_s = 30.0;
  double timeout_per_meter_s = 10.0;

  // Describes every field (key, unit, comment) to a visitor: the YAML form.
  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
  std::vector<ControlInput> ListU() const;
};

// BEST_U: the input of list_u with the lowest cost for driving from `pose` to `goal` along the
// leg that starts at `leg_start`.
ControlInput BestU(const kernel::Pose2& pose, const Eigen::Vector2d& leg_start,
                   const Eigen::Vector2d& goal, const std::vector<ControlInput>& list_u,
                   const MotionOptions& options);

// One time step of the robot as the explorer saw it.
struct TraceSample {
  double time_s = 0.0;
  kernel::Pose2 estimate;  // what the localisation said
  kernel::Pose2 odometry;  // raw odometry
  kernel::Pose2 truth;     // ground truth when the robot has it, else the estimate
};

struct MoveResult {
  bool reached = false;  // every waypoint reached
  bool blocked = false;  // the robot refused a step (it would have collided)
  std::string message;   // why it stopped early
  int steps = 0;
  int waypoints_reached = 0;
};

// Drives through `waypoints` (world frame; the robot starts near the first leg's start,
// `start`) by BEST_U, localising after every step; appends every step to `trace` and leaves the
// latest estimate in *estimate. Stops after the timeout, or at the first refused step, after
// backing off from the obstacle (MotionOptions::back_off_steps).
MoveResult MoveTo(const std::vector<Eigen::Vector2d>& waypoints, const Eigen::Vector2d& start,
                  const MotionOptions& options, RobotInterface* robot, Localization* localization,
                  kernel::Pose2* estimate, std::vector<TraceSample>* trace);

// Turns the robot in place until it faces `target` as well as one step of angular_speeds_radps
// can, localising after every step and appending it to `trace`; false when a step was refused or
// the turn did not converge.
bool TurnTowards(const Eigen::Vector2d& target, const MotionOptions& options, RobotInterface* robot,
                 Localization* localization, kernel::Pose2* estimate,
                 std::vector<TraceSample>* trace);

}  // namespace splam::exploration

#endif  // SPLAM_EXPLORATION_MOTION_H_
