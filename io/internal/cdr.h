#ifndef SPLAM_IO_INTERNAL_CDR_H_
#define SPLAM_IO_INTERNAL_CDR_H_

#include <cstdint>
#include <string>
#include <string_view>

#include "io/internal/rosbag_file.h"

// ROS 2's message serialisation (OMG CDR, XCDR1, as rmw writes it into bags): a 4-byte
// encapsulation header (0x00 0x01: little-endian, 0x00 0x00: big-endian), then the fields in
// order, each primitive aligned to its size counted from after the header; strings as a uint32
// length (with the terminating NUL) and the bytes; sequences as a uint32 count and the elements.
// Only what splam reads and writes: sensor_msgs/msg/LaserScan, nav_msgs/msg/Odometry and
// tf2_msgs/msg/TFMessage, into the plain structs of rosbag_file.h.
namespace splam::io::internal {

// Each returns false (leaving *out partly filled) when the bytes are not such a message: too
// short, a bad header, a count beyond the bytes, trailing garbage is allowed (padding).
bool DecodeLaserScan(std::string_view cdr, RosScan* out);
bool DecodeOdometry(std::string_view cdr, RosPose* out);
bool DecodeTransforms(std::string_view cdr, std::vector<RosPose>* out);  // TFMessage

// Little-endian CDR of the message (the twist and covariances of Odometry written as zeros but
// the two velocities; LaserScan without intensities).
std::string EncodeLaserScan(const RosScan& scan);
std::string EncodeOdometry(const RosPose& pose);
std::string EncodeTransforms(const std::vector<RosPose>& transforms);

// The message definitions (rosbag2's concatenated .msg text, as MCAP's "ros2msg" schemas hold).
extern const char kLaserScanDefinition[];
extern const char kOdometryDefinition[];
extern const char kTfMessageDefinition[];

}  // namespace splam::io::internal

#endif  // SPLAM_IO_INTERNAL_CDR_H_
