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

struct Ros2Topic {
  std::string name, type;  // type as ROS 2 names it: "sensor_msgs/msg/LaserScan"
  std::string encoding;    // "cdr"
};

// A ROS 2 bag read in two passes over its storage files: the constructor finds the topics and
// counts their messages, Messages reads those of the topics chosen, decoding each as it comes.
// Only a chunk (or a small record) and the chosen topics' messages are held; the bounds are in
// ros2_bag_file.cc and docs/robustness.md. The files of a bag directory must be regular files
// inside it, each listed once.
// What one ROS 2 bag may make splam read or hold; past one, reading fails naming it.
struct Ros2ReadLimits {
  // One chunk decompressed (rosbag2 writes 768 KiB); a compressed one also at most 1000 times
  // its compressed size plus 1 MiB. Bytes.
  std::uint64_t max_chunk_bytes = std::uint64_t{256} << 20;
  // One message or other record read (a schema, a channel), one SQLite value. Bytes.
  std::uint64_t max_message_bytes = std::uint64_t{64} << 20;
  // All chunks of one pass over the bag together, decompressed: at most this many bytes plus
  // decompression_ratio times the size of the bag's storage files (sensor data compresses 2 to
  // 10 times; a 4.3 MB file of chunks of zeros decompressed to 5.3 GB). Bytes.
  std::uint64_t max_decompressed_bytes = std::uint64_t{1} << 30;
  std::uint64_t decompression_ratio = 100;
  // The messages of the topics read, each counted as at least 256 bytes: the most a text log
  // may hold too. The other topics' messages are counted, never held. Bytes.
  std::uint64_t max_held_bytes = std::uint64_t{4} << 30;
  std::size_t max_topics = 100000;        // over all storage files
  std::size_t max_storage_files = 10000;  // a bag directory's relative_file_paths
  // SQLite's virtual-machine steps per byte of a .db3 file (a table scan takes a few per row).
  std::uint64_t sqlite_steps_per_byte = 64;
};

class Ros2BagFile : public BagReader {
 public:
  // Throws std::runtime_error saying what is wrong when `path` is not a readable ROS 2 bag (bad
  // magic, a record past the end, an unknown compression, a CRC mismatch, a message on an unknown
  // channel, a view instead of a table, a bound passed, a storage file that is not a regular file
  // of the bag directory).
  explicit Ros2BagFile(const std::string& path, const Ros2ReadLimits& limits = {});
  RosBagTopics Topics() const override;
  RosBagMessages Messages(const std::string& scan_topic, const std::string& odom_topic,
                          const std::string& truth_topic, bool read_tf) const override;

 private:
  Ros2ReadLimits limits_;
  std::vector<std::string> files_;  // the storage files, in the order metadata.yaml lists them
  std::uint64_t decompression_budget_ = 0;  // bytes a pass may decompress
  std::vector<Ros2Topic> topics_;           // as the files define them (one name may recur)
  std::vector<std::int64_t> counts_;        // messages per topic
};

// Writes the messages as one storage file (a zstd-chunked MCAP, or a SQLite3 .db3): scans on
// scan_topic, odometry on odom_topic, truth on truth_topic, transforms on /tf and /tf_static.
// Throws std::runtime_error.
void WriteRos2Bag(const std::string& path, Ros2Storage storage, const std::string& scan_topic,
                  const std::string& odom_topic, const std::string& truth_topic,
                  const RosBagMessages& messages);

}  // namespace splam::io::internal

#endif  // SPLAM_IO_INTERNAL_ROS2_BAG_FILE_H_
