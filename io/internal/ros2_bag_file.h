#ifndef SPLAM_IO_INTERNAL_ROS2_BAG_FILE_H_
#define SPLAM_IO_INTERNAL_ROS2_BAG_FILE_H_

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "io/internal/rosbag_file.h"

// ROS 2 bags (rosbag2) in both storage formats, read and written here: no Debian package reads
// them. SQLite3 (.db3: tables `topics` and `messages`, through Debian's libsqlite3) and MCAP
// (.mcap: records, chunks uncompressed or compressed with zstd or lz4 through Debian's libzstd
// and liblz4, CRCs checked), messages in CDR (cdr.h). A bag directory holds metadata.yaml and its
// storage files.
namespace splam::io::internal {

enum class Ros2Storage { kSqlite3, kMcap };

// A ROS 2 bag at `path`: a .db3 or .mcap file, or a directory with a metadata.yaml.
bool IsRos2BagPath(const std::string& path);

// One message as stored: its topic (an index into the topics), receive time and CDR bytes.
struct Ros2Message {
  int topic = 0;
  std::int64_t time_ns = 0;
  std::string data;
};
struct Ros2Topic {
  std::string name, type;  // type as ROS 2 names it: "sensor_msgs/msg/LaserScan"
  std::string encoding;    // "cdr"
};
struct Ros2Content {
  std::vector<Ros2Topic> topics;
  std::vector<Ros2Message> messages;
};

// The topics and messages of an MCAP file's bytes; throws std::runtime_error saying what is
// wrong (bad magic, a record past the end, an unknown compression, a CRC mismatch, a message on
// an unknown channel).
Ros2Content ParseMcap(std::string_view bytes);

class Ros2BagFile : public BagReader {
 public:
  // Throws std::runtime_error when `path` is not a readable ROS 2 bag.
  explicit Ros2BagFile(const std::string& path);
  RosBagTopics Topics() const override;
  RosBagMessages Messages(const std::string& scan_topic, const std::string& odom_topic,
                          const std::string& truth_topic, bool read_tf) const override;

 private:
  Ros2Content content_;
};

// Writes the messages as one storage file (a zstd-chunked MCAP, or a SQLite3 .db3): scans on
// scan_topic, odometry on odom_topic, truth on truth_topic, transforms on /tf and /tf_static.
// Throws std::runtime_error.
void WriteRos2Bag(const std::string& path, Ros2Storage storage, const std::string& scan_topic,
                  const std::string& odom_topic, const std::string& truth_topic,
                  const RosBagMessages& messages);

}  // namespace splam::io::internal

#endif  // SPLAM_IO_INTERNAL_ROS2_BAG_FILE_H_
