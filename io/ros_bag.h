#ifndef SPLAM_IO_ROS_BAG_H_
#define SPLAM_IO_ROS_BAG_H_

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "io/carmen.h"
#include "io/result.h"
#include "kernel/pose2.h"

namespace splam::io {

// ROS 1 bags (rosbag format 2.0, read and written with Debian's rosbag_storage) and ROS 2 bags
// (rosbag2: SQLite3 .db3 and MCAP .mcap files or bag directories, messages in CDR; read and
// written by io/internal/ros2_bag_file.cc; message types sensor_msgs/msg/LaserScan,
// nav_msgs/msg/Odometry, tf2_msgs/msg/TFMessage). A bag is read
// into the same in-memory log as a CARMEN file, so that every command taking a log takes a bag:
//   - scans: sensor_msgs/LaserScan; beam geometry, range limits and timestamps (header.stamp)
//     from each message. REP 117: +inf (or a range at or above range_max) is no return, NaN or
//     a range below range_min an invalid reading;
//   - odometry: nav_msgs/Odometry, or the odom_frame -> base_frame transforms of /tf
//     (tf2_msgs/TFMessage); the robot's pose at a scan is interpolated between the two odometry
//     poses around it (scans outside the odometry's time span are dropped and counted);
//   - the laser mounting base_frame -> the scan's frame_id: an option, else /tf_static (chains
//     of transforms are followed), else identity when the scan's frame is the base frame;
//   - ground truth (simulated runs): nav_msgs/Odometry on truth_topic, read as TRUEPOS.
// Writing does the reverse: /scan, /odom (every ODOM message and the odometric pose of every
// scan), /tf_static (the mounting of the first scan) and /ground_truth for TRUEPOS. Sonar
// messages have no ROS counterpart here and are counted, not written.
struct RosBagOptions {
  std::string scan_topic;  // empty: the bag's only sensor_msgs/LaserScan topic
  // Empty: the only nav_msgs/Odometry topic other than truth_topic, else /tf.
  std::string odom_topic;
  std::string truth_topic = "/ground_truth";
  std::string odom_frame = "odom";       // /tf odometry: the transform odom_frame -> base_frame
  std::string base_frame = "base_link";  // the robot's frame
  // base_frame -> laser; nullopt: from /tf_static.
  std::optional<kernel::Pose2> base_T_laser;
};

struct RosBagReadStats {
  int scans = 0, odometry = 0, true_poses = 0;
  int scans_outside_odometry = 0;     // dropped: before the first or after the last odometry
  std::map<std::string, int> topics;  // every topic with its message count
};

struct RosBagReadResult {
  Result<CarmenLog> log;
  RosBagReadStats stats;
};

// Fails with "path: what is wrong" (no such topic, several candidates: the topics are listed,
// no odometry, no mounting, a message that does not decode).
RosBagReadResult ReadRosBag(const std::string& path, const RosBagOptions& options = {});

struct RosBagWriteStats {
  int scans = 0, odometry = 0, true_poses = 0;
  int sonar_skipped = 0;
  bool write_failed = false;  // the error is the file's (a full disk), not the log's
};
// A ROS 1 bag for ".bag", ROS 2 for ".mcap" (chunks compressed with zstd) and ".db3" (SQLite3).
// Ok, else why the bag could not be written (*stats then says whether the log or
// the file was at fault).
kernel::Status WriteRosBag(const CarmenLog& log, const std::string& path,
                           const RosBagOptions& options = {}, RosBagWriteStats* stats = nullptr);

// True when `path` names a bag: ROS 1 (".bag") or ROS 2 (".db3", ".mcap", or a directory with a
// metadata.yaml).
bool IsRosBagPath(const std::string& path);
// Ok when the file's records are framed as rosbag 2.0 says (every length within its record and
// the file, also inside uncompressed chunks), else what is wrong. ReadRosBag checks this before
// Debian's rosbag reads the file: rosbag trusts the lengths (fuzz_bag found it reading past a
// buffer). Inside compressed chunks only rosbag's own checks apply.
kernel::Status RosBagFramingProblem(const std::string& path);

}  // namespace splam::io

#endif  // SPLAM_IO_ROS_BAG_H_
