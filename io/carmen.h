#ifndef SPLAM_IO_CARMEN_H_
#define SPLAM_IO_CARMEN_H_

#include <map>
#include <string>
#include <variant>
#include <vector>

#include "io/result.h"
#include "kernel/angle.h"
#include "kernel/pose2.h"
#include "kernel/scan.h"

namespace splam::io {

// CARMEN log files (the text format of the CARMEN robot toolkit and of the Freiburg SLAM
// benchmark logs). One message per line, '#' starts a comment line. Supported messages:
//
//   FLASER n r_1..r_n x y theta odom_x odom_y odom_theta ipc_timestamp hostname logger_timestamp
//   ROBOTLASER1 laser_type start_angle field_of_view angular_resolution maximum_range accuracy
//       remission_mode n r_1..r_n m e_1..e_m laser_x laser_y laser_theta robot_x robot_y
//       robot_theta tv rv forward_safety_dist side_safety_dist turn_axis ipc_timestamp hostname
//       logger_timestamp
//   ODOM x y theta tv rv accel ipc_timestamp hostname logger_timestamp
//   TRUEPOS true_x true_y true_theta odom_x odom_y odom_theta ipc_timestamp hostname
//       logger_timestamp                       (ground truth, as CARMEN's simulator writes it)
//   SONAR cone_angle n r_1..r_n m x_1 y_1 theta_1..x_m y_m theta_m ipc_timestamp hostname
//       logger_timestamp                       (range and mounting pose of each sonar)
//
// Other message types (PARAM, SYNC, NMEA, ...) are skipped and counted. Laser poses are the
// odometric poses the robot believed at the time; TRUEPOS is what the simulator knows.
//
// Range conventions (see kernel::Scan): on reading, a value at or above the maximum range (the
// ROBOTLASER1 field, or CarmenReadOptions::flaser_max_range_m) is a no-return (+inf), a value
// <= 0 or "nan" is an invalid reading (NaN). On writing, no-return is written as the maximum
// range and an invalid reading as 0, so that writing then reading gives back the same scan.
// ROBOTLASER1 does not store a minimum range: its scans read back with min_range_m = 0.

struct LogStamp {
  double ipc_timestamp_s = 0.0;
  std::string hostname = "splam";
  double logger_timestamp_s = 0.0;
  bool operator==(const LogStamp&) const = default;
};

struct OdometryMessage {
  kernel::Pose2 pose;
  double tv_mps = 0.0, rv_radps = 0.0, accel_mps2 = 0.0;
  LogStamp stamp;
};

struct LaserMessage {
  enum class Format { kFlaser, kRobotLaser1 };
  Format format = Format::kRobotLaser1;
  kernel::Scan scan;         // scan.timestamp_s == stamp.ipc_timestamp_s
  kernel::Pose2 laser_pose;  // odometric pose of the laser
  kernel::Pose2 robot_pose;  // odometric pose of the robot
  // ROBOTLASER1 only.
  int laser_type = 0;
  double accuracy_m = 0.0;
  int remission_mode = 0;
  std::vector<double> remissions;
  double tv_mps = 0.0, rv_radps = 0.0;
  double forward_safety_dist_m = 0.0, side_safety_dist_m = 0.0, turn_axis = 0.0;
  LogStamp stamp;
};

struct TruePoseMessage {
  kernel::Pose2 true_pose;
  kernel::Pose2 odometry_pose;
  LogStamp stamp;
};

struct SonarMessage {
  double cone_angle_rad = 0.0;
  std::vector<double> ranges_m;  // kNoReturn where nothing echoed
  std::vector<kernel::Pose2> robot_T_sonar;
  LogStamp stamp;
};

using LogMessage = std::variant<OdometryMessage, LaserMessage, TruePoseMessage, SonarMessage>;

struct CarmenLog {
  std::vector<std::string> comments;  // comment lines without the leading '#'
  std::vector<LogMessage> messages;   // in file order

  std::vector<const LaserMessage*> Lasers() const;
  std::vector<const OdometryMessage*> Odometry() const;
  std::vector<const TruePoseMessage*> TruePoses() const;
};

struct CarmenReadOptions {
  // FLASER lines carry no beam geometry; it is assumed from these.
  double flaser_start_angle_rad = -kernel::kPi / 2.0;
  // 0 selects by beam count: pi / n for an even count (180 beams -> 1 deg, as in intel.clf), pi /
  // (n - 1) for an odd count (181 or 361 beams over 180 deg, as in mit-csail.clf).
  double flaser_angular_step_rad = 0.0;
  double flaser_max_range_m = 81.8;  // FLASER readings at or above this are no-returns
  double flaser_min_range_m = 0.0;
  // Skip malformed lines (counted in the stats) instead of failing on the first one.
  bool skip_malformed_lines = false;
};

struct CarmenReadStats {
  int lines = 0;
  int malformed_lines = 0;  // only with skip_malformed_lines
  int no_return_readings = 0;
  int invalid_readings = 0;
  // Readings found piled at the top of the range distribution and taken as no-returns
  // (FindNoReturnPile, applied by the command line unless --flaser-max-range is given): from
  // this range up (0: none), how many, and their share of the hits.
  double piled_no_return_from_m = 0.0;
  long piled_no_return_readings = 0;
  double piled_no_return_share = 0.0;
  std::map<std::string, int> skipped_messages;  // unknown message type -> count
};

struct CarmenReadResult {
  Result<CarmenLog> log;
  CarmenReadStats stats;
  // When `log` failed on a malformed line: the messages of the lines before it (a caller may
  // process them and say that it stopped early).
  CarmenLog before_error;
};

// Reads a log; fails with "path:line: what is wrong" on the first malformed line.
CarmenReadResult ReadCarmenLog(const std::string& path, const CarmenReadOptions& options = {});
// Parses log text; `name` stands for the path in messages.
CarmenReadResult ParseCarmenLog(const std::string& text, const std::string& name,
                                const CarmenReadOptions& options = {});

std::string FormatCarmenLog(const CarmenLog& log);
// Ok, else why the file could not be written.
kernel::Status WriteCarmenLog(const std::string& path, const CarmenLog& log);

}  // namespace splam::io

#endif  // SPLAM_IO_CARMEN_H_
