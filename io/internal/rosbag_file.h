#ifndef SPLAM_IO_INTERNAL_ROSBAG_FILE_H_
#define SPLAM_IO_INTERNAL_ROSBAG_FILE_H_

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace rosbag {
class Bag;
}

// The messages of a ROS 1 bag that io::ReadRosBag and io::WriteRosBag use, in plain structs.
// rosbag_file.cc is the only file that includes ROS headers, and it is compiled as C++17: ROS 1's
// generated message headers use std::allocator<void>::rebind, which C++20 removed. So this
// header includes nothing of splam's.
namespace splam::io::internal {

struct RosPose {                        // nav_msgs/Odometry, or a geometry_msgs/TransformStamped
  double time_s = 0.0;                  // header.stamp
  std::string parent, child;            // header.frame_id, child_frame_id
  double x = 0.0, y = 0.0, yaw = 0.0;   // yaw of the quaternion
  double tv_mps = 0.0, rv_radps = 0.0;  // twist.linear.x, twist.angular.z (Odometry)
};

struct RosScan {  // sensor_msgs/LaserScan
  double time_s = 0.0;
  std::string frame;
  double angle_min = 0.0, angle_increment = 0.0, range_min = 0.0, range_max = 0.0;
  std::vector<float> ranges;
};

struct RosBagTopics {
  std::map<std::string, std::string> types;  // topic -> message type
  std::map<std::string, int> counts;         // topic -> messages
};

struct RosBagMessages {
  std::vector<RosScan> scans;
  std::vector<RosPose> odometry, truth;
  std::vector<RosPose> tf, tf_static;  // every transform of /tf and /tf_static
};

// A recording open for reading: the topics, then the messages of those chosen (ROS 1 bags here,
// ROS 2 bags in ros2_bag_file.h). Message types are named as ROS 1 names them
// ("sensor_msgs/LaserScan").
class BagReader {
 public:
  virtual ~BagReader() = default;
  virtual RosBagTopics Topics() const = 0;
  // The messages of the named topics, in time order (an empty topic name: none); /tf only with
  // read_tf. Throws std::exception on a message that does not decode.
  virtual RosBagMessages Messages(const std::string& scan_topic, const std::string& odom_topic,
                                  const std::string& truth_topic, bool read_tf) const = 0;
};

// A ROS 1 bag open for reading. One object serves both questions: rosbag::Bag's constructor crawls
// every ROS package on the machine for encryptor plugins (about 300 directories of /usr/share on
// Debian), the larger part of reading a small bag.
class RosBagFile : public BagReader {
 public:
  // Throws std::exception (rosbag's) when the file is not a readable bag.
  explicit RosBagFile(const std::string& path);
  ~RosBagFile();

  RosBagTopics Topics() const override;
  RosBagMessages Messages(const std::string& scan_topic, const std::string& odom_topic,
                          const std::string& truth_topic, bool read_tf) const override;

 private:
  std::unique_ptr<rosbag::Bag> bag_;
};

// Writes a bag: each scan on scan_topic, each odometry pose on odom_topic and each truth pose on
// truth_topic (nav_msgs/Odometry), the transforms on /tf and /tf_static. Throws std::exception.
// `bz2`: chunks compressed with bzip2 (rosbag's default is none).
void WriteMessages(const std::string& path, const std::string& scan_topic,
                   const std::string& odom_topic, const std::string& truth_topic,
                   const RosBagMessages& messages, bool bz2 = false);

}  // namespace splam::io::internal

#endif  // SPLAM_IO_INTERNAL_ROSBAG_FILE_H_
