#include "io/ros_bag.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string_view>
#include <utility>

#include "io/internal/plausible.h"
#include "io/internal/ros2_bag_file.h"
#include "io/internal/rosbag_file.h"
#include "io/text.h"
#include "kernel/angle.h"

namespace splam::io {
namespace {

constexpr char kLaserScanType[] = "sensor_msgs/LaserScan";
constexpr char kOdometryType[] = "nav_msgs/Odometry";
constexpr char kLaserFrame[] = "laser";
constexpr char kMapFrame[] = "map";

// tf frame ids may carry a leading '/' (tf1 style).
std::string Frame(const std::string& id) {
  return !id.empty() && id.front() == '/' ? id.substr(1) : id;
}

struct OdometrySample {
  double time_s = 0.0;
  kernel::Pose2 pose;
  double tv_mps = 0.0, rv_radps = 0.0;
};

// The odometry at time t, linear between the samples around it (the heading along the shorter
// arc); exactly a sample at its own time; nullopt outside their span.
std::optional<OdometrySample> Interpolate(const std::vector<OdometrySample>& samples, double t) {
  const auto after =
      std::lower_bound(samples.begin(), samples.end(), t,
                       [](const OdometrySample& s, double time) { return s.time_s < time; });
  if (after == samples.end()) return std::nullopt;
  if (after->time_s == t) return *after;
  if (after == samples.begin()) return std::nullopt;
  const OdometrySample& a = *(after - 1);
  const OdometrySample& b = *after;
  const double f = (t - a.time_s) / (b.time_s - a.time_s);
  OdometrySample s = a;
  s.time_s = t;
  s.pose = kernel::Pose2(a.pose.x() + f * (b.pose.x() - a.pose.x()),
                         a.pose.y() + f * (b.pose.y() - a.pose.y()),
                         a.pose.theta() + f * kernel::WrapAngle(b.pose.theta() - a.pose.theta()));
  return s;
}

LogStamp Stamp(double time_s) { return {time_s, "bag", time_s}; }

// "/scan (sensor_msgs/LaserScan, 300 messages), ..."
std::string TopicList(const std::map<std::string, std::string>& types,
                      const std::map<std::string, int>& counts) {
  std::string list;
  for (const auto& [topic, type] : types) {
    if (!list.empty()) list += ", ";
    list += topic + " (" + type + ", " + std::to_string(counts.at(topic)) + " messages)";
  }
  return list.empty() ? "none" : list;
}

// The topic of `type` named by `wanted`, else the only one of that type (not in `excluded`);
// an error names the candidates.
Result<std::string> ChooseTopic(const std::map<std::string, std::string>& types,
                                const std::map<std::string, int>& counts, const std::string& type,
                                const std::string& wanted, const std::string& option,
                                const std::string& excluded = "") {
  using R = Result<std::string>;
  if (!wanted.empty()) {
    const auto it = types.find(wanted);
    if (it == types.end())
      return R::Fail("no topic " + wanted + "; the bag's topics: " + TopicList(types, counts));
    if (it->second != type)
      return R::Fail("topic " + wanted + " holds " + it->second + ", not " + type);
    return R::Ok(wanted);
  }
  std::vector<std::string> candidates;
  for (const auto& [topic, t] : types)
    if (t == type && topic != excluded) candidates.push_back(topic);
  if (candidates.size() == 1) return R::Ok(candidates.front());
  return R::Fail((candidates.empty() ? "no " + type + " topic" : "several " + type + " topics") +
                 " (choose one with " + option +
                 "); the bag's topics: " + TopicList(types, counts));
}

// base_frame -> frame through the static transforms (child -> (parent, parent_T_child)).
Result<kernel::Pose2> Mounting(
    const std::map<std::string, std::pair<std::string, kernel::Pose2>>& static_transforms,
    const std::string& base_frame, const std::string& frame) {
  kernel::Pose2 base_T_frame;
  std::string current = frame;
  for (int depth = 0; current != base_frame; ++depth) {
    const auto it = static_transforms.find(current);
    if (it == static_transforms.end() || depth > 64)
      return Result<kernel::Pose2>::Fail(
          "no transform from " + base_frame + " to the scans' frame " + frame +
          " in /tf_static (give the laser's mounting with --laser-pose X,Y,THETA)");
    base_T_frame = it->second.second * base_T_frame;
    current = it->second.first;
  }
  return Result<kernel::Pose2>::Ok(base_T_frame);
}

// The scan of a LaserScan message in kernel::Scan's conventions (REP 117), beams in increasing
// angle.
kernel::Scan ScanOf(const internal::RosScan& m) {
  kernel::Scan scan;
  scan.timestamp_s = m.time_s;
  scan.start_angle_rad = m.angle_min;
  scan.angular_step_rad = m.angle_increment;
  scan.min_range_m = m.range_min;
  scan.max_range_m = m.range_max;
  for (const float r : m.ranges) {
    const double range = r;
    if (std::isnan(range) || range < scan.min_range_m) {
      scan.ranges_m.push_back(std::numeric_limits<double>::quiet_NaN());  // invalid, too close
    } else if (range >= scan.max_range_m) {
      scan.ranges_m.push_back(kernel::Scan::kNoReturn);  // +inf or beyond the range: no return
    } else {
      scan.ranges_m.push_back(range);
    }
  }
  if (scan.angular_step_rad < 0.0 && scan.size() > 0) {  // a laser mounted upside down
    scan.start_angle_rad += scan.angular_step_rad * static_cast<double>(scan.size() - 1);
    scan.angular_step_rad = -scan.angular_step_rad;
    std::reverse(scan.ranges_m.begin(), scan.ranges_m.end());
  }
  return scan;
}

// The little-endian integer at `at` of `bytes` (at + 4 <= bytes.size()).
std::uint32_t U32(std::string_view bytes, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(bytes[at + i]);
  return v;
}

// Bytes [at, at + n) of a file or a chunk; the caller has checked that they exist.
using ReadBytes = std::function<std::string(std::uint64_t at, std::uint64_t n)>;

// One record of a bag (rosbag format 2.0): its header fields, where it starts and where its data
// lies, in bytes from the start of the records.
struct BagRecord {
  std::map<std::string, std::string, std::less<>> fields;
  std::uint64_t at = 0;
  std::uint64_t data_at = 0;
  std::uint64_t data_len = 0;
  char op = 0;
};

// The little-endian integer of a header field, if it has exactly `bytes` bytes.
std::optional<std::uint64_t> FieldInteger(const BagRecord& record, std::string_view name,
                                          std::size_t bytes) {
  const auto it = record.fields.find(name);
  if (it == record.fields.end() || it->second.size() != bytes) return std::nullopt;
  std::uint64_t v = 0;
  for (std::size_t i = bytes; i-- > 0;) v = (v << 8) | static_cast<unsigned char>(it->second[i]);
  return v;
}

// Reads the fields of a header ("name=value", each after its length) into *fields; fails
// when a field runs past the header or has no '='.
kernel::Status HeaderFieldsProblem(std::string_view header,
                                   std::map<std::string, std::string, std::less<>>* fields) {
  for (std::size_t f = 0; f < header.size();) {
    if (f + 4 > header.size() || f + 4 + U32(header, f) > header.size())
      return kernel::Status::Error("a header field runs past its header");
    const std::string_view field = header.substr(f + 4, U32(header, f));
    const std::size_t equals = field.find('=');
    if (equals == std::string_view::npos)
      return kernel::Status::Error("a header field without '='");
    (*fields)[std::string(field.substr(0, equals))] = field.substr(equals + 1);
    f += 4 + field.size();
  }
  return {};
}

// Splits `size` bytes into records (header length, header fields "name=value" each with its
// length, an op field, data length, data), checking that every length stays inside.
kernel::Status SplitRecords(const ReadBytes& read, std::uint64_t size, const std::string& what,
                            std::vector<BagRecord>* records) {
  std::uint64_t at = 0;
  for (int number = 1; at < size; ++number) {
    const std::string where = what + " " + std::to_string(number);
    if (at + 4 > size) return kernel::Status::Error(where + ": its header runs past the end");
    const std::uint64_t header_len = U32(read(at, 4), 0);
    if (at + 4 + header_len + 4 > size)
      return kernel::Status::Error(where + ": its header runs past the end");
    const std::string header = read(at + 4, header_len);
    BagRecord record;
    if (kernel::Status problem = HeaderFieldsProblem(header, &record.fields); !problem.ok())
      return problem.Prefixed(where);
    record.at = at;
    record.data_at = at + 4 + header_len + 4;
    record.data_len = U32(read(record.data_at - 4, 4), 0);
    if (record.data_at + record.data_len > size)
      return kernel::Status::Error(where + ": its data runs past the end");
    const auto op = record.fields.find("op");
    if (op == record.fields.end() || op->second.size() != 1)
      return kernel::Status::Error(where + ": no op field");
    record.op = op->second[0];
    at = record.data_at + record.data_len;
    records->push_back(std::move(record));
  }
  return {};
}

constexpr char kMessageDataOp = 0x02;
constexpr char kBagHeaderOp = 0x03;
constexpr char kIndexDataOp = 0x04;
constexpr char kChunkOp = 0x05;
constexpr char kChunkInfoOp = 0x06;
constexpr char kConnectionOp = 0x07;
// The largest uncompressed size a compressed chunk may claim (rosbag writes 768 KiB chunks).
constexpr std::uint64_t kMaxChunkBytes = 256u << 20;

// The data of a connection record is the connection's own header (topic, type, md5sum,
// definition): rosbag reads the record's data length as that header's length. Ok when its
// fields fit.
kernel::Status ConnectionProblem(std::string_view data) {
  std::map<std::string, std::string, std::less<>> fields;
  return HeaderFieldsProblem(data, &fields).Prefixed("its connection header");
}

// Checks the framing of a bag's records and of the records inside its uncompressed chunks, the
// connection headers the connection records hold, and that every position the bag's indices give
// (the index position, chunk positions, message offsets in a chunk) is the start of a record of
// the right kind. Debian's rosbag trusts all of
// these: a field longer than its header made ros::Header::parse read past its buffer (in a record's
// header, and in a connection's), and an index offset past a chunk made
// Bag::readHeaderFromBuffer read outside it (all found by fuzz_bag).
// Reads the headers and the uncompressed chunks only, one at a time; `base` is the position of
// the first record in the file. Compressed chunks are left to rosbag. Ok when all hold.
kernel::Status RecordFramingProblem(const ReadBytes& read, std::uint64_t size, std::uint64_t base) {
  std::vector<BagRecord> records;
  if (kernel::Status problem = SplitRecords(read, size, "record", &records); !problem.ok())
    return problem;
  std::set<std::uint64_t> starts, chunk_starts;
  for (const BagRecord& r : records) {
    starts.insert(base + r.at);
    if (r.op == kChunkOp) chunk_starts.insert(base + r.at);
  }
  // Message data offsets of the last uncompressed chunk; nullopt after a compressed one.
  std::optional<std::set<std::uint64_t>> messages;
  for (std::size_t i = 0; i < records.size(); ++i) {
    const BagRecord& r = records[i];
    const std::string where = "record " + std::to_string(i + 1);
    if (r.op == kConnectionOp) {
      if (kernel::Status problem = ConnectionProblem(read(r.data_at, r.data_len)); !problem.ok())
        return problem.Prefixed(where);
    } else if (r.op == kBagHeaderOp) {
      const auto index_pos = FieldInteger(r, "index_pos", 8);
      if (!index_pos || (*index_pos != 0 && !starts.contains(*index_pos)))
        return kernel::Status::Error(where + ": its index position is not a record");
    } else if (r.op == kChunkInfoOp) {
      const auto chunk_pos = FieldInteger(r, "chunk_pos", 8);
      if (!chunk_pos || !chunk_starts.contains(*chunk_pos))
        return kernel::Status::Error(where + ": its chunk position is not a chunk");
    } else if (r.op == kChunkOp) {
      const auto compression = r.fields.find("compression");
      if (compression == r.fields.end())
        return kernel::Status::Error(where + ": a chunk without compression field");
      messages.reset();
      if (compression->second != "none") {
        // rosbag allocates what the chunk claims before it decompresses (4 GiB: an abort when
        // the allocation failed); its writer makes chunks of 768 KiB.
        const auto claimed = FieldInteger(r, "size", 4);
        if (!claimed || *claimed > kMaxChunkBytes)
          return kernel::Status::Error(where + ": a compressed chunk claiming " +
                                       (claimed ? std::to_string(*claimed) : std::string("no")) +
                                       " bytes uncompressed (at most 256 MiB)");
        continue;
      }
      if (FieldInteger(r, "size", 4) != r.data_len)
        return kernel::Status::Error(where +
                                     ": an uncompressed chunk whose size is not its length");
      const std::string chunk = read(r.data_at, r.data_len);
      const ReadBytes in_chunk = [&](std::uint64_t a, std::uint64_t n) {
        return chunk.substr(a, n);
      };
      std::vector<BagRecord> inner;
      if (kernel::Status problem = SplitRecords(in_chunk, chunk.size(), "chunk record", &inner);
          !problem.ok())
        return problem.Prefixed(where);
      messages.emplace();
      for (std::size_t k = 0; k < inner.size(); ++k) {
        const BagRecord& m = inner[k];
        if (m.op == kMessageDataOp) messages->insert(m.at);
        if (m.op != kConnectionOp) continue;
        if (kernel::Status problem = ConnectionProblem(chunk.substr(m.data_at, m.data_len));
            !problem.ok())
          return problem.Prefixed(where + ": chunk record " + std::to_string(k + 1));
      }
    } else if (r.op == kIndexDataOp && messages) {
      const auto count = FieldInteger(r, "count", 4);
      if (FieldInteger(r, "ver", 4) != 1 || !count || r.data_len != *count * 12)
        return kernel::Status::Error(where + ": an index whose length is not its count");
      const std::string entries = read(r.data_at, r.data_len);
      for (std::size_t e = 0; e < *count; ++e)
        if (!messages->contains(U32(entries, e * 12 + 8)))
          return kernel::Status::Error(where +
                                       ": an index entry that is not a message of its chunk");
    }
  }
  return {};
}

}  // namespace

kernel::Status RosBagFramingProblem(const std::string& path) {
  constexpr std::string_view kMagic = "#ROSBAG V2.0\n";
  std::ifstream in(path, std::ios::binary);
  std::string magic(kMagic.size(), '\0');
  if (!in.read(magic.data(), static_cast<std::streamsize>(magic.size())) || magic != kMagic)
    return kernel::Status::Error("does not start with #ROSBAG V2.0");
  std::error_code error;
  const std::uint64_t size = std::filesystem::file_size(path, error);
  if (error) return kernel::Status::Error("cannot read its size: " + error.message());
  const ReadBytes from_file = [&](std::uint64_t at, std::uint64_t n) {
    std::string bytes(n, '\0');
    in.seekg(static_cast<std::streamoff>(kMagic.size() + at));
    in.read(bytes.data(), static_cast<std::streamsize>(n));
    return bytes;
  };
  return RecordFramingProblem(from_file, size - kMagic.size(), kMagic.size());
}

bool IsRosBagPath(const std::string& path) {
  return path.ends_with(".bag") || internal::IsRos2BagPath(path);
}

RosBagReadResult ReadRosBag(const std::string& path, const RosBagOptions& options) {
  RosBagReadResult result;
  RosBagReadStats& stats = result.stats;
  const auto fail = [&](const std::string& message) {
    result.log = Result<CarmenLog>::Fail(FileError(path, 0, message));
    return result;
  };
  const bool ros2 = internal::IsRos2BagPath(path);
  if (std::filesystem::is_directory(path) && !ros2)
    return fail("is a directory, not a bag (a ROS 2 bag directory holds a metadata.yaml)");
  // A FIFO would block for ever, a device (a link to /dev/zero) never end.
  if (!std::filesystem::is_directory(path) && !std::filesystem::is_regular_file(path))
    return fail(std::filesystem::exists(path)
                    ? "is not a regular file (a FIFO or a device), not a bag"
                    : "no such file");
  internal::RosBagTopics topics;
  internal::RosBagMessages bag;
  std::string scan_topic;
  std::optional<std::string> odom_topic;
  bool has_truth = false;
  if (!ros2) {
    if (kernel::Status problem = RosBagFramingProblem(path); !problem.ok())
      return fail("not a readable ROS bag: " + problem.message());
  }
  try {
    const std::unique_ptr<internal::BagReader> reader =
        ros2 ? std::unique_ptr<internal::BagReader>(std::make_unique<internal::Ros2BagFile>(path))
             : std::make_unique<internal::RosBagFile>(path);
    const internal::BagReader& file = *reader;
    topics = file.Topics();
    stats.topics = topics.counts;
    const Result<std::string> chosen_scan = ChooseTopic(topics.types, topics.counts, kLaserScanType,
                                                        options.scan_topic, "--scan-topic");
    if (!chosen_scan.ok()) return fail(chosen_scan.error);
    scan_topic = *chosen_scan.value;
    const auto truth = topics.types.find(options.truth_topic);
    has_truth = truth != topics.types.end() && truth->second == kOdometryType &&
                options.odom_topic != options.truth_topic;
    // Odometry from the named or only Odometry topic; else from /tf.
    const bool has_tf = topics.types.contains("/tf");
    const Result<std::string> chosen_odom =
        ChooseTopic(topics.types, topics.counts, kOdometryType, options.odom_topic, "--odom-topic",
                    options.truth_topic);
    if (chosen_odom.ok()) {
      odom_topic = *chosen_odom.value;
    } else if (!options.odom_topic.empty() || !has_tf) {
      return fail(chosen_odom.error + (has_tf ? "" : "; and no /tf to read it from"));
    }
    bag = file.Messages(scan_topic, odom_topic.value_or(""), has_truth ? options.truth_topic : "",
                        !odom_topic);
  } catch (const std::exception& e) {
    return fail(std::string(ros2 ? "not a readable ROS 2 bag: " : "not a readable ROS bag: ") +
                e.what());
  }

  // Odometry, in time order.
  std::vector<OdometrySample> odometry;
  for (const internal::RosPose& p : bag.odometry)
    odometry.push_back({p.time_s, kernel::Pose2(p.x, p.y, p.yaw), p.tv_mps, p.rv_radps});
  for (const internal::RosPose& p : bag.tf) {
    if (Frame(p.parent) == options.odom_frame && Frame(p.child) == options.base_frame)
      odometry.push_back({p.time_s, kernel::Pose2(p.x, p.y, p.yaw), 0.0, 0.0});
  }
  std::stable_sort(
      odometry.begin(), odometry.end(),
      [](const OdometrySample& a, const OdometrySample& b) { return a.time_s < b.time_s; });
  if (odometry.empty()) {
    return fail("no odometry: " + (odom_topic ? "no message on " + *odom_topic
                                              : "no " + options.odom_frame + " -> " +
                                                    options.base_frame + " transform in /tf"));
  }
  for (const OdometrySample& s : odometry) {
    if (kernel::Status problem = internal::PoseProblem(s.pose, "odometry pose"); !problem.ok())
      return fail(problem.message());
  }
  std::map<std::string, std::pair<std::string, kernel::Pose2>> static_transforms;
  for (const internal::RosPose& p : bag.tf_static) {
    const kernel::Pose2 parent_T_child(p.x, p.y, p.yaw);
    // A mounting of NaN or 1e300 m placed every scan there; the run ended far from the input.
    if (kernel::Status problem = internal::PoseProblem(
            parent_T_child, "/tf_static: the transform " + OneLine(Frame(p.parent)) + " -> " +
                                OneLine(Frame(p.child)));
        !problem.ok())
      return fail(problem.message());
    static_transforms[Frame(p.child)] = {Frame(p.parent), parent_T_child};
  }

  // The scans, at the odometry interpolated to their time.
  std::vector<std::pair<double, LogMessage>> messages;
  std::optional<kernel::Pose2> base_T_laser = options.base_T_laser;
  for (std::size_t i = 0; i < bag.scans.size(); ++i) {
    const internal::RosScan& s = bag.scans[i];
    LaserMessage laser;
    laser.scan = ScanOf(s);
    if (kernel::Status problem = internal::ScanGeometryProblem(laser.scan); !problem.ok())
      return fail("scan " + std::to_string(i + 1) + " on " + scan_topic + ": " + problem.message());
    if (!base_T_laser) {
      const std::string frame = Frame(s.frame);
      const Result<kernel::Pose2> mounting =
          frame == options.base_frame || frame.empty()
              ? Result<kernel::Pose2>::Ok(kernel::Pose2())
              : Mounting(static_transforms, options.base_frame, frame);
      if (!mounting.ok()) return fail(mounting.error);
      if (kernel::Status problem = internal::PoseProblem(
              *mounting.value, "the laser mounting " + OneLine(options.base_frame) + " -> " +
                                   OneLine(frame) + " (a chain of /tf_static)");
          !problem.ok())
        return fail(problem.message());
      base_T_laser = *mounting.value;
    }
    const std::optional<OdometrySample> at = Interpolate(odometry, s.time_s);
    if (!at) {
      ++stats.scans_outside_odometry;
      continue;
    }
    laser.robot_pose = at->pose;
    laser.laser_pose = at->pose * *base_T_laser;
    laser.tv_mps = at->tv_mps;
    laser.rv_radps = at->rv_radps;
    laser.stamp = Stamp(s.time_s);
    messages.emplace_back(s.time_s, std::move(laser));
    ++stats.scans;
  }
  for (const OdometrySample& s : odometry) {
    messages.emplace_back(s.time_s,
                          OdometryMessage{s.pose, s.tv_mps, s.rv_radps, 0.0, Stamp(s.time_s)});
    ++stats.odometry;
  }
  for (const internal::RosPose& p : bag.truth) {
    const kernel::Pose2 pose(p.x, p.y, p.yaw);
    if (kernel::Status problem = internal::PoseProblem(pose, "true pose"); !problem.ok())
      return fail(problem.message());
    const std::optional<OdometrySample> at = Interpolate(odometry, p.time_s);
    messages.emplace_back(p.time_s, TruePoseMessage{pose, at ? at->pose : pose, Stamp(p.time_s)});
    ++stats.true_poses;
  }
  // In time order; at one time odometry first, then the truth, then the scan (as the simulator
  // writes them).
  const auto rank = [](const LogMessage& m) {
    return std::holds_alternative<OdometryMessage>(m)   ? 0
           : std::holds_alternative<TruePoseMessage>(m) ? 1
                                                        : 2;
  };
  std::stable_sort(messages.begin(), messages.end(), [&](const auto& a, const auto& b) {
    return a.first != b.first ? a.first < b.first : rank(a.second) < rank(b.second);
  });
  CarmenLog log;
  log.comments.push_back(" converted from the ROS bag " + path + " (scans " + scan_topic +
                         ", odometry " + odom_topic.value_or("/tf") + ")");
  for (auto& [t, message] : messages) log.messages.push_back(std::move(message));
  result.log = Result<CarmenLog>::Ok(std::move(log));
  return result;
}

kernel::Status WriteRosBag(const CarmenLog& log, const std::string& path,
                           const RosBagOptions& options, RosBagWriteStats* stats) {
  RosBagWriteStats counts;
  internal::RosBagMessages bag;
  const auto pose = [&](double t, const std::string& parent, const kernel::Pose2& p, double tv,
                        double rv) {
    return internal::RosPose{t, parent, options.base_frame, p.x(), p.y(), p.theta(), tv, rv};
  };
  for (const LogMessage& message : log.messages) {
    const double t = std::visit([](const auto& m) { return m.stamp.ipc_timestamp_s; }, message);
    if (!(t >= 0.0 && t < 4e9))
      return FileError(path, 0,
                       "timestamp " + FormatDouble(t) + " s is outside ROS time [0, 4e9) s");
    if (const auto* o = std::get_if<OdometryMessage>(&message)) {
      bag.odometry.push_back(pose(t, options.odom_frame, o->pose, o->tv_mps, o->rv_radps));
    } else if (const auto* l = std::get_if<LaserMessage>(&message)) {
      if (bag.tf_static.empty()) {  // the mounting of the first scan
        internal::RosPose mounting =
            pose(t, options.base_frame, l->robot_pose.Between(l->laser_pose), 0.0, 0.0);
        mounting.child = kLaserFrame;
        bag.tf_static.push_back(mounting);
      }
      // Its odometric pose joins the odometry stream.
      bag.odometry.push_back(pose(t, options.odom_frame, l->robot_pose, l->tv_mps, l->rv_radps));
      const kernel::Scan& scan = l->scan;
      internal::RosScan s{t,
                          kLaserFrame,
                          scan.start_angle_rad,
                          scan.angular_step_rad,
                          scan.min_range_m,
                          scan.max_range_m,
                          {}};
      for (const double r : scan.ranges_m) s.ranges.push_back(static_cast<float>(r));
      bag.scans.push_back(std::move(s));
      ++counts.scans;
    } else if (const auto* p = std::get_if<TruePoseMessage>(&message)) {
      bag.truth.push_back(pose(t, kMapFrame, p->true_pose, 0.0, 0.0));
      ++counts.true_poses;
    } else {
      ++counts.sonar_skipped;
    }
  }
  // One odometry pose per time, in time order.
  const auto earlier = [](const internal::RosPose& a, const internal::RosPose& b) {
    return a.time_s < b.time_s;
  };
  std::stable_sort(bag.odometry.begin(), bag.odometry.end(), earlier);
  bag.odometry.erase(std::unique(bag.odometry.begin(), bag.odometry.end(),
                                 [](const internal::RosPose& a, const internal::RosPose& b) {
                                   return a.time_s == b.time_s;
                                 }),
                     bag.odometry.end());
  counts.odometry = static_cast<int>(bag.odometry.size());
  try {
    const std::string scan_topic = options.scan_topic.empty() ? "/scan" : options.scan_topic;
    const std::string odom_topic = options.odom_topic.empty() ? "/odom" : options.odom_topic;
    if (path.ends_with(".mcap") || path.ends_with(".db3")) {
      internal::WriteRos2Bag(
          path,
          path.ends_with(".mcap") ? internal::Ros2Storage::kMcap : internal::Ros2Storage::kSqlite3,
          scan_topic, odom_topic, options.truth_topic, bag);
    } else {
      internal::WriteMessages(path, scan_topic, odom_topic, options.truth_topic, bag);
    }
  } catch (const std::exception& e) {
    if (stats) stats->write_failed = true;
    return FileError(path, 0, std::string("cannot write the bag: ") + e.what());
  }
  if (stats) *stats = counts;
  return {};
}

}  // namespace splam::io
