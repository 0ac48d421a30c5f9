#ifndef SPLAM_IO_SIMULATION_LOG_H_
#define SPLAM_IO_SIMULATION_LOG_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "io/carmen.h"
#include "io/result.h"
#include "io/trajectory.h"
#include "sim/simulator.h"

namespace splam::io {

// CARMEN's laser types (carmen_laser_laser_type_t), written in ROBOTLASER1 lines.
inline constexpr int kCarmenSickLms = 0;
inline constexpr int kCarmenHokuyoUrg = 2;
inline constexpr int kCarmenSimulatedLaser = 3;
int CarmenLaserType(const std::string& model);

// A simulated run as a CARMEN log: per frame one ODOM (the noisy odometry), one TRUEPOS (ground
// truth) and one ROBOTLASER1 (the scan, with the odometric laser and robot poses), and a SONAR
// line when the frame has sonar readings; all three share the frame's timestamp. `comments` go
// to the top of the file.
CarmenLog MakeCarmenLog(const std::vector<sim::SensorFrame>& frames,
                        const sim::SimulatorOptions& options,
                        const std::vector<std::string>& comments = {});

// Ground truth and odometry of a log: from TRUEPOS lines when there are any, else empty truth;
// odometry from ODOM lines, else from the laser messages' robot poses.
Trajectory TrueTrajectory(const CarmenLog& log);
Trajectory OdometryTrajectory(const CarmenLog& log);

// A route file: one waypoint "x y" per line ('#' comments). The first line may be "x y theta":
// then it is the start pose rather than a waypoint. Without it the robot starts at the first
// waypoint facing the second.
struct Route {
  kernel::Pose2 start;
  std::vector<Eigen::Vector2d> waypoints;
};
Result<Route> ReadRoute(const std::string& path);
Result<Route> ParseRoute(const std::string& text, const std::string& name);

}  // namespace splam::io

#endif  // SPLAM_IO_SIMULATION_LOG_H_
