#include "io/simulation_log.h"

#include <cmath>
#include <sstream>

#include "io/text.h"

namespace splam::io {

int CarmenLaserType(const std::string& model) {
  if (model == "LMS-200") return kCarmenSickLms;
  if (model == "URG-04LX") return kCarmenHokuyoUrg;
  return kCarmenSimulatedLaser;
}

CarmenLog MakeCarmenLog(const std::vector<sim::SensorFrame>& frames,
                        const sim::SimulatorOptions& options,
                        const std::vector<std::string>& comments) {
  CarmenLog log;
  log.comments = comments;
  for (const sim::SensorFrame& f : frames) {
    LogStamp stamp;
    stamp.ipc_timestamp_s = f.time_s;
    stamp.hostname = "splam-sim";
    stamp.logger_timestamp_s = f.time_s;

    OdometryMessage odom;
    odom.pose = f.odometry_pose;
    odom.tv_mps = f.linear_velocity_mps;
    odom.rv_radps = f.angular_velocity_radps;
    odom.stamp = stamp;
    log.messages.push_back(odom);

    TruePoseMessage truth;
    truth.true_pose = f.true_pose;
    truth.odometry_pose = f.odometry_pose;
    truth.stamp = stamp;
    log.messages.push_back(truth);

    LaserMessage laser;
    laser.format = LaserMessage::Format::kRobotLaser1;
    laser.scan = f.scan;
    laser.laser_pose = f.odometry_pose * options.laser.robot_T_laser;
    laser.robot_pose = f.odometry_pose;
    laser.laser_type = CarmenLaserType(options.laser.model);
    laser.accuracy_m = options.laser.noise_floor_m;
    laser.tv_mps = f.linear_velocity_mps;
    laser.rv_radps = f.angular_velocity_radps;
    laser.stamp = stamp;
    log.messages.emplace_back(std::in_place_type<LaserMessage>, std::move(laser));

    if (!f.sonar_ranges_m.empty()) {
      SonarMessage sonar;
      sonar.cone_angle_rad = 2.0 * options.sonar.cone_half_angle_rad;
      sonar.ranges_m = f.sonar_ranges_m;
      sonar.robot_T_sonar = options.sonar.robot_T_sonar;
      sonar.stamp = stamp;
      log.messages.push_back(std::move(sonar));
    }
  }
  return log;
}

Trajectory TrueTrajectory(const CarmenLog& log) {
  Trajectory out;
  for (const TruePoseMessage* m : log.TruePoses())
    out.push_back({m->stamp.ipc_timestamp_s, m->true_pose});
  return out;
}

Trajectory OdometryTrajectory(const CarmenLog& log) {
  Trajectory out;
  for (const OdometryMessage* m : log.Odometry())
    out.push_back({m->stamp.ipc_timestamp_s, m->pose});
  if (out.empty()) {
    for (const LaserMessage* m : log.Lasers())
      out.push_back({m->stamp.ipc_timestamp_s, m->robot_pose});
  }
  return out;
}

Result<Route> ParseRoute(const std::string& text, const std::string& name) {
  Route route;
  bool has_start = false;
  std::vector<double> v;
  const kernel::Status error =
      ForEachDataLine(text, [&](int line, const std::vector<std::string_view>& tokens) {
        const bool first = route.waypoints.empty() && !has_start;
        if (tokens.size() != 2 && !(first && tokens.size() == 3)) {
          return FileError(
              name, line,
              first ? "expected 'x y' or a start pose 'x y theta'" : "expected a waypoint 'x y'");
        }
        if (kernel::Status bad = ParseFiniteNumbers(tokens, &v); !bad.ok()) {
          return FileError(name, line, bad.message());
        }
        if (v.size() == 3) {
          route.start = kernel::Pose2(v[0], v[1], v[2]);
          has_start = true;
        } else {
          route.waypoints.emplace_back(v[0], v[1]);
        }
        return kernel::Status::Ok();
      });
  if (!error.ok()) return Result<Route>::Fail(error);
  if (!has_start) {
    if (route.waypoints.size() < 2) {
      return Result<Route>::Fail(
          FileError(name, 0,
                    "a route needs a start pose 'x y theta' and a waypoint, or "
                    "at least two waypoints"));
    }
    const Eigen::Vector2d d = route.waypoints[1] - route.waypoints[0];
    route.start = kernel::Pose2(route.waypoints[0], std::atan2(d.y(), d.x()));
    route.waypoints.erase(route.waypoints.begin());
  }
  if (route.waypoints.empty())
    return Result<Route>::Fail(FileError(name, 0, "the route has no waypoint"));
  return Result<Route>::Ok(std::move(route));
}

Result<Route> ReadRoute(const std::string& path) {
  std::string text;
  if (kernel::Status error = ReadTextFile(path, &text); !error.ok())
    return Result<Route>::Fail(error);
  return ParseRoute(text, path);
}

}  // namespace splam::io
