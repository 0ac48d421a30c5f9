#ifndef SPLAM_SIM_SIMULATOR_H_
#define SPLAM_SIM_SIMULATOR_H_

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "kernel/options.h"
#include "kernel/pose2.h"
#include "kernel/random.h"
#include "kernel/scan.h"
#include "kernel/status.h"
#include "sim/laser.h"
#include "sim/ray_caster.h"
#include "sim/robot.h"
#include "sim/sonar.h"

namespace splam::sim {

struct SimulatorOptions {
  double time_step_s = 0.1;  // one control and sensing cycle (the 10 Hz scan rate)
  RobotOptions robot;
  OdometryNoiseOptions odometry;
  LaserOptions laser = LaserOptions::Urg04lx();
  bool enable_sonar = false;
  SonarOptions sonar;

  // Describes every field (key, unit, comment) to a visitor: the YAML form.
  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

// What the robot perceives at one instant, with the simulator's ground truth.
struct SensorFrame {
  double time_s = 0.0;
  kernel::Pose2 true_pose;      // world_T_robot
  kernel::Pose2 odometry_pose;  // the integrated noisy odometry (starts at the true start pose)
  double linear_velocity_mps = 0.0;
  double angular_velocity_radps = 0.0;
  kernel::Scan scan;
  std::vector<int> beam_obstacles;     // World obstacle truly hit by each beam, -1 for none
  std::vector<double> sonar_ranges_m;  // empty unless sonar is enabled
};

// The robot in a world, advanced one time step at a time by velocity commands. All randomness
// (odometry and sensor noise) comes from one generator seeded at construction.
class Simulator {
 public:
  // `caster` must outlive the simulator.
  Simulator(const RayCaster& caster, const SimulatorOptions& options, const kernel::Pose2& start,
            std::uint64_t seed);

  // People walking through the world, seen by the laser from now on (World::people).
  void SetPeople(std::vector<Walker> people) { people_ = std::move(people); }

  // True when the robot's disc at `pose` is free of obstacles.
  bool IsFree(const kernel::Pose2& pose) const;
  // Drives at (v, w), clamped to the robot's limits, for one time step. Returns false and leaves
  // the robot where it is (time does not advance) when the motion would collide.
  bool Step(double v_mps, double w_radps);
  // Laser (and sonar) readings at the current true pose and time.
  SensorFrame Sense();

  const kernel::Pose2& true_pose() const { return true_pose_; }
  const kernel::Pose2& odometry_pose() const { return odometry_pose_; }
  double time_s() const { return time_s_; }
  const SimulatorOptions& options() const { return options_; }

 private:
  const RayCaster& caster_;
  SimulatorOptions options_;
  kernel::Random random_;
  kernel::Pose2 true_pose_;
  kernel::Pose2 odometry_pose_;
  double time_s_ = 0.0;
  double last_v_ = 0.0, last_w_ = 0.0;
  long long sweeps_ = 0;  // laser sweeps so far (their interlace phase)
  std::vector<Walker> people_;
};

// A simple waypoint follower: turn in place towards the next waypoint when it is far off the
// heading, otherwise drive with a proportional heading correction, slowing down near the last
// waypoint.
struct RouteOptions {
  double max_linear_speed_mps = 0.4;
  double max_angular_speed_radps = 0.8;
  double heading_gain = 1.5;             // w = gain * heading error, 1/s
  double turn_in_place_above_rad = 0.5;  // heading error above which v = 0
  double waypoint_tolerance_m = 0.1;     // a waypoint closer than this is reached
  int max_steps = 20000;                 // cap on time steps (2000 s at 10 Hz)

  void VisitFields(kernel::FieldVisitor& v);
  kernel::Status Validate() const;
};

struct RouteRun {
  std::vector<SensorFrame> frames;  // the first one at the start, then one per time step
  bool completed = false;           // all waypoints reached
  std::string message;              // why the run stopped early, empty when completed
  int waypoints_reached = 0;
  double distance_m = 0.0;  // true distance travelled
};

// Senses at the start, then steps towards each waypoint in turn, sensing after every step.
// Stops early, with a message, on a collision, when max_steps is reached or when `stop` (polled
// before every step) says so.
RouteRun FollowRoute(Simulator* simulator, const std::vector<Eigen::Vector2d>& waypoints,
                     const RouteOptions& options, const std::function<bool()>& stop = {});

}  // namespace splam::sim

#endif  // SPLAM_SIM_SIMULATOR_H_
