#include "exploration/motion.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernel/angle.h"

namespace splam::exploration {
namespace {

// Distance from p to the segment a-b.
double DistanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                         const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len_sq = ab.squaredNorm();
  const double t = len_sq > 0.0 ? std::clamp((p - a).dot(ab) / len_sq, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

}  // namespace

kernel::Status MotionOptions::Validate() const {
  if (linear_speeds_mps.empty() || angular_speeds_radps.empty())
    return kernel::Status::Error("list_U needs at least one linear and one angular speed");
  const bool any_forward = std::any_of(linear_speeds_mps.begin(), linear_speeds_mps.end(),
                                       [](double v) { return v > 0.0; });
  const bool any_turn = std::any_of(angular_speeds_radps.begin(), angular_speeds_radps.end(),
                                    [](double w) { return w != 0.0; });
  if (!any_forward || !any_turn)
    return kernel::Status::Error("list_U needs a positive linear and a nonzero angular speed");
  // Bounds: a robot, not a projectile; each judged input is simulated over the horizon.
  for (double v : linear_speeds_mps) {
    if (!(std::abs(v) <= 10.0))
      return kernel::Status::Error("linear speeds must be in [-10, 10] m/s");
  }
  // A nonzero rate below 1e-3 rad/s (a full turn in 1.7 hours) would make TurnTowards' bound,
  // a full turn at the slowest rate, 10^8 steps and more.
  for (double w : angular_speeds_radps) {
    if (!(std::abs(w) <= 10.0) || (w != 0.0 && std::abs(w) < 1e-3))
      return kernel::Status::Error("angular speeds must be 0 or of magnitude in [0.001, 10] rad/s");
  }
  if (linear_speeds_mps.size() * angular_speeds_radps.size() > 10000)
    return kernel::Status::Error("list_U has at most 10000 inputs");
  if (!(horizon_s > 0.0 && horizon_s <= 100.0))
    return kernel::Status::Error("horizon_s must be in (0, 100] s");
  if (!(turn_in_place_above_rad > 0.0))
    return kernel::Status::Error("turn_in_place_above_rad must be positive");
  if (back_off_steps < 0 || back_off_steps > 1000)
    return kernel::Status::Error("back_off_steps must be in [0, 1000]");
  if (!(heading_weight_m_per_rad >= 0.0) || !(cross_track_weight >= 0.0))
    return kernel::Status::Error("cost weights must be >= 0");
  if (!(goal_tolerance_m > 0.0) || !(waypoint_tolerance_m > 0.0))
    return kernel::Status::Error("tolerances must be positive");
  if (!(timeout_base_s > 0.0 && timeout_base_s <= 1e5) ||
      !(timeout_per_meter_s >= 0.0 && timeout_per_meter_s <= 1e4))
    return kernel::Status::Error(
        "timeout_base_s must be in (0, 1e5] s and timeout_per_meter_s in [0, 1e4] s/m");
  return kernel::Status::Ok();
}

std::vector<ControlInput> MotionOptions::ListU() const {
  std::vector<ControlInput> list;
  for (double v : linear_speeds_mps) {
    for (double w : angular_speeds_radps) {
      if (v != 0.0 || w != 0.0) list.push_back({v, w});
    }
  }
  return list;
}

ControlInput BestU(const kernel::Pose2& pose, const Eigen::Vector2d& leg_start,
                   const Eigen::Vector2d& goal, const std::vector<ControlInput>& list_u,
                   const MotionOptions& options) {
  ControlInput best;
  double best_cost = std::numeric_limits<double>::infinity();
  const Eigen::Vector2d to_goal_now = goal - pose.translation();
  const bool turn_first =
      to_goal_now.norm() > options.goal_tolerance_m &&
      std::abs(kernel::WrapAngle(std::atan2(to_goal_now.y(), to_goal_now.x()) - pose.theta())) >
          options.turn_in_place_above_rad;
  for (const ControlInput& u : list_u) {
    if (turn_first && u.v_mps != 0.0) continue;
    const kernel::Pose2 next =
        pose * kernel::UnicycleIncrement(u.v_mps, u.w_radps, options.horizon_s);
    const Eigen::Vector2d to_goal = goal - next.translation();
    const double distance = to_goal.norm();
    const double bearing = kernel::WrapAngle(std::atan2(to_goal.y(), to_goal.x()) - next.theta());
    const double cost =
        distance +
        options.heading_weight_m_per_rad * std::abs(bearing) * std::min(1.0, distance / 0.5) +
        options.cross_track_weight * DistanceToSegment(next.translation(), leg_start, goal);
    if (cost < best_cost) {
      best_cost = cost;
      best = u;
    }
  }
  return best;
}

namespace {

// Reads the robot after a step (with the laser when the localisation needs scans) and traces it.
void Localize(RobotInterface* robot, Localization* localization, kernel::Pose2* estimate,
              std::vector<TraceSample>* trace) {
  const Perception perception =
      localization->needs_scans() ? robot->Sense() : robot->ReadOdometry();
  *estimate = localization->Update(perception);
  trace->push_back({perception.time_s, *estimate, perception.odometry_pose,
                    perception.true_pose.value_or(*estimate)});
}

}  // namespace

bool TurnTowards(const Eigen::Vector2d& target, const MotionOptions& options, RobotInterface* robot,
                 Localization* localization, kernel::Pose2* estimate,
                 std::vector<TraceSample>* trace) {
  const double dt = robot->description().time_step_s;
  // A full turn at the slowest rate, and some: the loop ends even when the robot slips.
  double slowest = std::numeric_limits<double>::infinity();
  for (const double w : options.angular_speeds_radps)
    if (w != 0.0) slowest = std::min(slowest, std::abs(w));
  if (!std::isfinite(slowest)) return false;
  const int max_steps = static_cast<int>(std::ceil(2.0 * 2.0 * kernel::kPi / (slowest * dt)));
  for (int step = 0; step < max_steps; ++step) {
    const Eigen::Vector2d to = target - estimate->translation();
    const double error = kernel::WrapAngle(std::atan2(to.y(), to.x()) - estimate->theta());
    // The rate whose step leaves the smallest error; none: facing it as well as a step can.
    double best_w = 0.0, best_error = std::abs(error);
    for (const double w : options.angular_speeds_radps) {
      if (std::abs(error - w * dt) < best_error) {
        best_error = std::abs(error - w * dt);
        best_w = w;
      }
    }
    if (best_w == 0.0) return true;
    if (!robot->Step(0.0, best_w)) return false;
    Localize(robot, localization, estimate, trace);
  }
  return false;
}

MoveResult MoveTo(const std::vector<Eigen::Vector2d>& waypoints, const Eigen::Vector2d& start,
                  const MotionOptions& options, RobotInterface* robot, Localization* localization,
                  kernel::Pose2* estimate, std::vector<TraceSample>* trace) {
  MoveResult result;
  const std::vector<ControlInput> list_u = options.ListU();
  double length = 0.0;
  Eigen::Vector2d previous = start;
  for (const Eigen::Vector2d& w : waypoints) {
    length += (w - previous).norm();
    previous = w;
  }
  const double dt = robot->description().time_step_s;
  // In doubles, saturated: a path of kilometres at a long timeout is more steps than an int.
  const int max_steps = static_cast<int>(std::min(
      std::ceil((options.timeout_base_s + options.timeout_per_meter_s * length) / dt), 1e9));
  Eigen::Vector2d leg_start = start;
  std::size_t next = 0;
  const auto localize = [&] { Localize(robot, localization, estimate, trace); };
  while (next < waypoints.size()) {
    const bool last = next + 1 == waypoints.size();
    const double tolerance = last ? options.goal_tolerance_m : options.waypoint_tolerance_m;
    if ((estimate->translation() - waypoints[next]).norm() <= tolerance) {
      leg_start = waypoints[next++];
      ++result.waypoints_reached;
      continue;
    }
    if (result.steps >= max_steps) {
      result.message = "timeout: goal not reached within the move's time budget";
      return result;
    }
    const ControlInput u = BestU(*estimate, leg_start, waypoints[next], list_u, options);
    if (!robot->Step(u.v_mps, u.w_radps)) {
      result.blocked = true;
      result.message = "blocked: the robot refused a step that would collide";
      for (int k = 0; k < options.back_off_steps && robot->Step(-0.1, 0.0); ++k) localize();
      return result;
    }
    ++result.steps;
    localize();
  }
  result.reached = true;
  return result;
}

void MotionOptions::VisitFields(kernel::FieldVisitor& v) {
  v.Field("linear_speeds_mps", &linear_speeds_mps, "list_U: candidate v, m/s");
  v.Field("angular_speeds_radps", &angular_speeds_radps, "list_U: candidate w, rad/s");
  v.Field("horizon_s", &horizon_s, "look-ahead used to judge an input, s");
  v.Field("turn_in_place_above_rad", &turn_in_place_above_rad,
          "bearing error above which the robot only turns in place, rad");
  v.Field("back_off_steps", &back_off_steps, "steps backed off after a refused step");
  v.Field("heading_weight_m_per_rad", &heading_weight_m_per_rad,
          "cost per rad of bearing error, m");
  v.Field("cross_track_weight", &cross_track_weight, "cost per m off the leg");
  v.Field("goal_tolerance_m", &goal_tolerance_m, "last waypoint reached within, m");
  v.Field("waypoint_tolerance_m", &waypoint_tolerance_m,
          "intermediate waypoints reached within, m");
  v.Field("timeout_base_s", &timeout_base_s, "a move gives up after base + per_meter * length, s");
  v.Field("timeout_per_meter_s", &timeout_per_meter_s, "... s per m of path");
}

}  // namespace splam::exploration
