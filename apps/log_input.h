#ifndef SPLAM_APPS_LOG_INPUT_H_
#define SPLAM_APPS_LOG_INPUT_H_

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "io/carmen.h"
#include "io/ros_bag.h"

namespace splam::apps {

// How the commands that take a log read it: a CARMEN file, or a ROS 1 bag (a path ending in
// .bag), with the options of each.
struct LogInput {
  double flaser_step_deg = 0.0;
  double flaser_max_range_m = 81.8;
  // Readings piled at the top of the range distribution are taken as no-returns
  // (io::FindNoReturnPile); off once --flaser-max-range is given.
  bool detect_no_returns = true;
  io::RosBagOptions bag;
  std::vector<double> laser_pose;  // x,y,theta of the laser on the robot (bags); empty: /tf_static
};

// --flaser-step-deg, --flaser-max-range, --scan-topic, --odom-topic, --truth-topic,
// --odom-frame, --base-frame, --laser-pose.
void AddLogInputOptions(CLI::App* cmd, LogInput* input);

// Reads `path` as a bag or a CARMEN log. A bag's read statistics are printed (topics used,
// scans dropped outside the odometry), and so is a pile of no-returns found in a CARMEN log.
io::CarmenReadResult ReadLogInput(const std::string& path, const LogInput& input);

}  // namespace splam::apps

#endif  // SPLAM_APPS_LOG_INPUT_H_
