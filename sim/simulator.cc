#include "sim/simulator.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <sstream>

#include "kernel/angle.h"

namespace splam::sim {

kernel::Status SimulatorOptions::Validate() const {
  if (!(time_step_s > 0.0)) return kernel::Status::Error("time_step_s must be positive");
  if (kernel::Status s = kernel::FirstError(robot.Validate(), odometry.Validate(), laser.Validate(),
                                            enable_sonar ? sonar.Validate() : kernel::Status::Ok());
      !s.ok())
    return s;
  return kernel::Status::Ok();
}

Simulator::Simulator(const RayCaster& caster, const SimulatorOptions& options,
                     const kernel::Pose2& start, std::uint64_t seed)
    : caster_(caster), options_(options), random_(seed), true_pose_(start), odometry_pose_(start) {
  assert(options.Validate().ok());
}

bool Simulator::IsFree(const kernel::Pose2& pose) const {
  return !caster_.Collides(pose.translation(), options_.robot.radius_m);
}

bool Simulator::Step(double v_mps, double w_radps) {
  const double v =
      std::clamp(v_mps, -options_.robot.max_linear_speed_mps, options_.robot.max_linear_speed_mps);
  const double w = std::clamp(w_radps, -options_.robot.max_angular_speed_radps,
                              options_.robot.max_angular_speed_radps);
  const kernel::Pose2 increment = UnicycleIncrement(v, w, options_.time_step_s);
  const kernel::Pose2 next = true_pose_ * increment;
  if (!IsFree(next)) return false;
  true_pose_ = next;
  odometry_pose_ = odometry_pose_ * CorruptIncrement(increment, options_.odometry, &random_);
  time_s_ += options_.time_step_s;
  last_v_ = v;
  last_w_ = w;
  return true;
}

SensorFrame Simulator::Sense() {
  SensorFrame frame;
  frame.time_s = time_s_;
  frame.true_pose = true_pose_;
  frame.odometry_pose = odometry_pose_;
  frame.linear_velocity_mps = last_v_;
  frame.angular_velocity_radps = last_w_;
  std::vector<kernel::Circle2> people;
  people.reserve(people_.size());
  for (const Walker& w : people_) people.push_back({w.PositionAt(time_s_), w.radius_m});
  frame.scan = SimulateLaser(caster_, options_.laser.Sweep(sweeps_++), true_pose_, time_s_,
                             &random_, &frame.beam_obstacles, people);
  if (options_.enable_sonar) {
    frame.sonar_ranges_m = SimulateSonar(caster_, options_.sonar, true_pose_, &random_);
  }
  return frame;
}

kernel::Status RouteOptions::Validate() const {
  if (!(max_linear_speed_mps > 0.0) || !(max_angular_speed_radps > 0.0)) {
    return kernel::Status::Error("route speeds must be positive");
  }
  if (!(heading_gain > 0.0) || !(turn_in_place_above_rad > 0.0)) {
    return kernel::Status::Error("route heading_gain and turn_in_place_above_rad must be positive");
  }
  if (!(waypoint_tolerance_m > 0.0))
    return kernel::Status::Error("route waypoint_tolerance_m must be positive");
  if (max_steps < 1) return kernel::Status::Error("route max_steps must be at least 1");
  return kernel::Status::Ok();
}

RouteRun FollowRoute(Simulator* simulator, const std::vector<Eigen::Vector2d>& waypoints,
                     const RouteOptions& options, const std::function<bool()>& stop) {
  assert(options.Validate().ok());
  RouteRun run;
  run.frames.push_back(simulator->Sense());
  const double dt = simulator->options().time_step_s;
  std::size_t next = 0;
  for (int step = 0; next < waypoints.size(); ++step) {
    const kernel::Pose2 pose = simulator->true_pose();
    Eigen::Vector2d to_goal = waypoints[next] - pose.translation();
    if (to_goal.norm() < options.waypoint_tolerance_m) {
      ++next;
      ++run.waypoints_reached;
      continue;
    }
    if (stop && stop()) {
      std::ostringstream msg;
      msg << "interrupted at t = " << simulator->time_s() << " s before waypoint " << next;
      run.message = msg.str();
      return run;
    }
    if (step >= options.max_steps) {
      std::ostringstream msg;
      msg << "stopped after max_steps = " << options.max_steps << " time steps before waypoint "
          << next << " (" << waypoints[next].x() << ", " << waypoints[next].y() << ")";
      run.message = msg.str();
      return run;
    }
    const double error = kernel::WrapAngle(std::atan2(to_goal.y(), to_goal.x()) - pose.theta());
    // Do not overshoot the heading within one step.
    double w = std::clamp(options.heading_gain * error, -options.max_angular_speed_radps,
                          options.max_angular_speed_radps);
    if (std::abs(w * dt) > std::abs(error)) w = error / dt;
    double v = 0.0;
    if (std::abs(error) <= options.turn_in_place_above_rad) {
      const bool last = next + 1 == waypoints.size();
      const double distance = to_goal.norm();
      v = std::min(options.max_linear_speed_mps,
                   last ? distance / dt : options.max_linear_speed_mps);
      v *= std::cos(error);
    }
    if (!simulator->Step(v, w)) {
      std::ostringstream msg;
      msg << "collision at t = " << simulator->time_s() << " s near (" << pose.x() << ", "
          << pose.y() << ") on the way to waypoint " << next << " (" << waypoints[next].x() << ", "
          << waypoints[next].y() << ")";
      run.message = msg.str();
      return run;
    }
    run.distance_m += (simulator->true_pose().translation() - pose.translation()).norm();
    run.frames.push_back(simulator->Sense());
  }
  run.completed = true;
  return run;
}

void SimulatorOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Field("time_step_s", &time_step_s, "one control and sensing cycle, s");
  v.Nested("robot", "differential-drive robot", &robot);
  v.Nested("odometry", "odometry noise (the estimators' model is scaled alike)", &odometry);
  v.Nested("laser", "laser range finder (default: URG-04LX)", &laser);
  v.Field("enable_sonar", &enable_sonar, "simulate the sonar ring");
  v.Nested("sonar", "sonar ring (Pioneer P3-DX)", &sonar);
}

void RouteOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Field("max_linear_speed_mps", &max_linear_speed_mps, "forward speed along the route, m/s");
  v.Field("max_angular_speed_radps", &max_angular_speed_radps, "turn rate limit, rad/s");
  v.Field("heading_gain", &heading_gain, "w = gain * heading error, 1/s");
  v.Field("turn_in_place_above_rad", &turn_in_place_above_rad,
          "heading error above which the robot turns in place, rad");
  v.Field("waypoint_tolerance_m", &waypoint_tolerance_m, "a waypoint is reached within, m");
  v.Field("max_steps", &max_steps, "cap on 0.1 s time steps");
}

}  // namespace splam::sim
