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
  io::RosBagOptions bag;
  std::vector<double> laser_pose;  // x,y,theta of the laser on the robot (bags); empty: /tf_static
};

// --flaser-step-deg, --flaser-max-range, --scan-topic, --odom-topic, --truth-topic,
// --odom-frame, --base-frame, --laser-pose.
void AddLogInputOptions(CLI::App* cmd, LogInput* input);

// Reads `path` as a bag or a CARMEN log. A bag's read statistics are printed (topics used,
// scans dropped outside the odometry).
io::CarmenReadResult ReadLogInput(const std::string& path, const LogInput& input);

}  // namespace splam::apps

#endif  // SPLAM_APPS_LOG_INPUT_H_
