#include "apps/log_input.h"

#include <fmt/core.h>

#include "apps/commands.h"
#include "io/no_return_pile.h"
#include "kernel/angle.h"

namespace splam::apps {

void AddLogInputOptions(CLI::App* cmd, LogInput* input) {
  cmd->add_option(
         "--flaser-step-deg", input->flaser_step_deg,
         "CARMEN FLASER beam spacing in degrees (0: 180/n for even n, 180/(n-1) for odd n)")
      ->check(FiniteNonNegative())
      ->capture_default_str();
  cmd->add_option("--flaser-max-range", input->flaser_max_range_m,
                  "CARMEN FLASER readings at or above this are no-returns; without it, readings "
                  "piled at the top of the log's range distribution are also taken as no-returns")
      ->check(FinitePositive())
      ->each([input](const std::string&) { input->detect_no_returns = false; })
      ->capture_default_str();
  cmd->add_option("--scan-topic", input->bag.scan_topic,
                  "ROS bag: the sensor_msgs/LaserScan topic (default: the only one)");
  cmd->add_option("--odom-topic", input->bag.odom_topic,
                  "ROS bag: the nav_msgs/Odometry topic (default: the only one, else /tf)");
  cmd->add_option("--truth-topic", input->bag.truth_topic,
                  "ROS bag: ground truth as nav_msgs/Odometry, read when present")
      ->capture_default_str();
  cmd->add_option("--odom-frame", input->bag.odom_frame,
                  "ROS bag: odometry from /tf is the transform odom-frame -> base-frame")
      ->capture_default_str();
  cmd->add_option("--base-frame", input->bag.base_frame, "ROS bag: the robot's frame")
      ->capture_default_str();
  AddPoseOption(cmd, "--laser-pose", &input->laser_pose,
                "ROS bag: the laser's pose on the robot, X,Y,THETA (m, m, rad); default: from "
                "/tf_static");
}

io::CarmenReadResult ReadLogInput(const std::string& path, const LogInput& input) {
  if (!io::IsRosBagPath(path)) {
    io::CarmenReadOptions options;
    options.flaser_angular_step_rad = kernel::DegToRad(input.flaser_step_deg);
    options.flaser_max_range_m = input.flaser_max_range_m;
    io::CarmenReadResult read = io::ReadCarmenLog(path, options);
    if (!input.detect_no_returns || !read.log.ok()) return read;
    if (const std::optional<io::NoReturnPile> pile = io::FindNoReturnPile(*read.log.value)) {
      io::MarkNoReturns(pile->from_m, &*read.log.value);
      read.stats.piled_no_return_from_m = pile->from_m;
      read.stats.piled_no_return_readings = pile->readings;
      read.stats.piled_no_return_share = pile->share;
      fmt::print(
          "{}: {} readings ({:.1f} % of the hits) pile at {:.2f}-{:.2f} m, the top of the range "
          "distribution: taken as no-returns (--flaser-max-range sets the limit instead)\n",
          path, pile->readings, 100 * pile->share, pile->from_m, pile->to_m);
    }
    return read;
  }
  io::RosBagOptions options = input.bag;
  if (input.laser_pose.size() == 3)
    options.base_T_laser =
        kernel::Pose2(input.laser_pose[0], input.laser_pose[1], input.laser_pose[2]);
  io::RosBagReadResult read = io::ReadRosBag(path, options);
  io::CarmenReadResult result;
  result.log = std::move(read.log);
  if (result.log.ok()) {
    fmt::print("{}: {} scans, {} odometry poses, {} true poses read from the bag", path,
               read.stats.scans, read.stats.odometry, read.stats.true_poses);
    if (read.stats.scans_outside_odometry > 0)
      fmt::print("; {} scans outside the odometry's time span dropped",
                 read.stats.scans_outside_odometry);
    fmt::print("\n");
  }
  return result;
}

}  // namespace splam::apps
