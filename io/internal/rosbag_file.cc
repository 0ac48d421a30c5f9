#include "io/internal/rosbag_file.h"

#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace splam::io::internal {
namespace {

double Yaw(const geometry_msgs::Quaternion& q) {
  return std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
}
geometry_msgs::Quaternion Quaternion(double yaw) {
  geometry_msgs::Quaternion q;
  q.z = std::sin(0.5 * yaw);
  q.w = std::cos(0.5 * yaw);
  return q;
}
ros::Time Time(double time_s) {
  ros::Time t;
  t.fromSec(time_s);
  return t;
}
// rosbag refuses record times before ros::TIME_MIN (1 ns); the header keeps the stamp.
ros::Time RecordTime(double time_s) { return std::max(Time(time_s), ros::TIME_MIN); }

RosPose FromOdometry(const nav_msgs::Odometry& o) {
  RosPose p;
  p.time_s = o.header.stamp.toSec();
  p.parent = o.header.frame_id;
  p.child = o.child_frame_id;
  p.x = o.pose.pose.position.x;
  p.y = o.pose.pose.position.y;
  p.yaw = Yaw(o.pose.pose.orientation);
  p.tv_mps = o.twist.twist.linear.x;
  p.rv_radps = o.twist.twist.angular.z;
  return p;
}
nav_msgs::Odometry ToOdometry(const RosPose& p) {
  nav_msgs::Odometry o;
  o.header.stamp = Time(p.time_s);
  o.header.frame_id = p.parent;
  o.child_frame_id = p.child;
  o.pose.pose.position.x = p.x;
  o.pose.pose.position.y = p.y;
  o.pose.pose.orientation = Quaternion(p.yaw);
  o.twist.twist.linear.x = p.tv_mps;
  o.twist.twist.angular.z = p.rv_radps;
  return o;
}
void AddTransforms(const tf2_msgs::TFMessage& tf, std::vector<RosPose>* out) {
  for (const geometry_msgs::TransformStamped& t : tf.transforms) {
    RosPose p;
    p.time_s = t.header.stamp.toSec();
    p.parent = t.header.frame_id;
    p.child = t.child_frame_id;
    p.x = t.transform.translation.x;
    p.y = t.transform.translation.y;
    p.yaw = Yaw(t.transform.rotation);
    out->push_back(p);
  }
}

// A read position in a message's serialized bytes (ROS 1 serialization: little-endian
// integers, a string or an array as a uint32 length and its elements).
class Cursor {
 public:
  Cursor(const std::uint8_t* data, std::size_t size) : data_(data), left_(size) {}
  bool Skip(std::uint64_t n) {
    if (n > left_) return false;
    data_ += n;
    left_ -= n;
    return true;
  }
  bool U32(std::uint32_t* v) {
    if (left_ < 4) return false;
    std::memcpy(v, data_, 4);
    return Skip(4);
  }
  // An array of `n` elements of `element_bytes` each, or a string (1 byte each).
  bool Array(std::uint64_t element_bytes) {
    std::uint32_t n = 0;
    return U32(&n) && Skip(n * element_bytes);
  }
  bool Header() { return Skip(12) && Array(1); }  // seq, stamp, frame_id

 private:
  const std::uint8_t* data_;
  std::size_t left_;
};

// Whether the array lengths of a message fit in its bytes. ros::serialization resizes a vector to
// the length it reads before reading its elements, so a corrupt length allocated without bound
// (a 580 GB request, found by fuzz_bag). nav_msgs/Odometry holds no variable-length array.
bool LaserScanFits(Cursor c) { return c.Header() && c.Skip(7 * 4) && c.Array(4) && c.Array(4); }
bool TfMessageFits(Cursor c) {
  std::uint32_t n = 0;
  if (!c.U32(&n)) return false;
  for (std::uint32_t i = 0; i < n; ++i)  // header, child_frame_id, translation and rotation
    if (!(c.Header() && c.Array(1) && c.Skip(7 * 8))) return false;
  return true;
}
bool AlwaysFits(Cursor) { return true; }

// The message, or null if it is of another type. Throws std::runtime_error when its array
// lengths run past its bytes.
template <class Message>
boost::shared_ptr<Message> Instantiate(const rosbag::MessageInstance& m, bool (*fits)(Cursor)) {
  if (!m.isType<Message>()) return nullptr;
  std::vector<std::uint8_t> bytes(m.size());
  ros::serialization::OStream out(bytes.data(), static_cast<std::uint32_t>(bytes.size()));
  m.write(out);
  if (!fits(Cursor(bytes.data(), bytes.size())))
    throw std::runtime_error("a " + m.getDataType() + " message on " + m.getTopic() +
                             " whose array lengths run past its " + std::to_string(bytes.size()) +
                             " bytes");
  auto message = boost::make_shared<Message>();
  ros::serialization::IStream in(bytes.data(), static_cast<std::uint32_t>(bytes.size()));
  ros::serialization::deserialize(in, *message);
  return message;
}

// rosbag::Bag loads its encryptor plugins (librosbag_default_encryption_plugins, which pulls in
// gpgme) through a pluginlib loader of its own and unloads them with the Bag: a dlopen and a
// dlclose of four libraries per bag. class_loader unloads a library only when no loader holds it,
// so one loader kept for the life of the process keeps them loaded once. If it cannot load them,
// each Bag tries (and reports) as before.
void KeepEncryptorPluginsLoaded() {
  static pluginlib::ClassLoader<rosbag::EncryptorBase>* const kLoader = [] {
    auto* loader = new pluginlib::ClassLoader<rosbag::EncryptorBase>("rosbag_storage",
                                                                     "rosbag::EncryptorBase");
    try {
      loader->loadLibraryForClass("rosbag/NoEncryptor");
    } catch (const std::exception&) {
    }
    return loader;
  }();
  (void)kLoader;
}

// The messages into an open bag (WriteMessages).
void WriteAll(rosbag::Bag* out, const std::string& scan_topic, const std::string& odom_topic,
              const std::string& truth_topic, const RosBagMessages& messages, bool bz2) {
  rosbag::Bag& bag = *out;
  if (bz2) bag.setCompression(rosbag::compression::BZ2);
  const auto write_transform = [&](const char* topic, const RosPose& p) {
    tf2_msgs::TFMessage tf;
    geometry_msgs::TransformStamped t;
    t.header.stamp = Time(p.time_s);
    t.header.frame_id = p.parent;
    t.child_frame_id = p.child;
    t.transform.translation.x = p.x;
    t.transform.translation.y = p.y;
    t.transform.rotation = Quaternion(p.yaw);
    tf.transforms.push_back(t);
    bag.write(topic, RecordTime(p.time_s), tf);
  };
  for (const RosPose& p : messages.tf_static) write_transform("/tf_static", p);
  for (const RosPose& p : messages.tf) write_transform("/tf", p);
  for (const RosScan& scan : messages.scans) {
    sensor_msgs::LaserScan s;
    s.header.stamp = Time(scan.time_s);
    s.header.frame_id = scan.frame;
    s.angle_min = static_cast<float>(scan.angle_min);
    s.angle_increment = static_cast<float>(scan.angle_increment);
    s.angle_max = static_cast<float>(
        scan.angle_min + scan.angle_increment *
                             static_cast<double>(std::max<std::size_t>(scan.ranges.size(), 1) - 1));
    s.range_min = static_cast<float>(scan.range_min);
    s.range_max = static_cast<float>(scan.range_max);
    s.ranges = scan.ranges;
    bag.write(scan_topic, RecordTime(scan.time_s), s);
  }
  for (const RosPose& p : messages.odometry)
    bag.write(odom_topic, RecordTime(p.time_s), ToOdometry(p));
  for (const RosPose& p : messages.truth)
    bag.write(truth_topic, RecordTime(p.time_s), ToOdometry(p));
}

}  // namespace

RosBagFile::RosBagFile(const std::string& path) {
  KeepEncryptorPluginsLoaded();
  bag_ = std::make_unique<rosbag::Bag>(path, rosbag::bagmode::Read);
}
RosBagFile::~RosBagFile() = default;

RosBagTopics RosBagFile::Topics() const {
  const rosbag::Bag& bag = *bag_;
  RosBagTopics topics;
  rosbag::View all(bag);
  for (const rosbag::ConnectionInfo* c : all.getConnections()) topics.types[c->topic] = c->datatype;
  for (const auto& entry : topics.types)
    topics.counts[entry.first] =
        static_cast<int>(rosbag::View(bag, rosbag::TopicQuery(entry.first)).size());
  return topics;
}

RosBagMessages RosBagFile::Messages(const std::string& scan_topic, const std::string& odom_topic,
                                    const std::string& truth_topic, bool read_tf) const {
  const rosbag::Bag& bag = *bag_;
  RosBagMessages out;
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    const std::string& topic = m.getTopic();
    if (!scan_topic.empty() && topic == scan_topic) {
      const auto s = Instantiate<sensor_msgs::LaserScan>(m, LaserScanFits);
      if (!s) continue;
      RosScan scan;
      scan.time_s = s->header.stamp.toSec();
      scan.frame = s->header.frame_id;
      scan.angle_min = s->angle_min;
      scan.angle_increment = s->angle_increment;
      scan.range_min = s->range_min;
      scan.range_max = s->range_max;
      scan.ranges = s->ranges;
      out.scans.push_back(std::move(scan));
    } else if (!odom_topic.empty() && topic == odom_topic) {
      if (const auto o = Instantiate<nav_msgs::Odometry>(m, AlwaysFits))
        out.odometry.push_back(FromOdometry(*o));
    } else if (!truth_topic.empty() && topic == truth_topic) {
      if (const auto o = Instantiate<nav_msgs::Odometry>(m, AlwaysFits))
        out.truth.push_back(FromOdometry(*o));
    } else if (topic == "/tf_static" || (read_tf && topic == "/tf")) {
      if (const auto tf = Instantiate<tf2_msgs::TFMessage>(m, TfMessageFits))
        AddTransforms(*tf, topic == "/tf" ? &out.tf : &out.tf_static);
    }
  }
  return out;
}

void WriteMessages(const std::string& path, const std::string& scan_topic,
                   const std::string& odom_topic, const std::string& truth_topic,
                   const RosBagMessages& messages, bool bz2) {
  KeepEncryptorPluginsLoaded();
  // rosbag::Bag's destructor closes the file, which writes the index: after a write that failed
  // (a full disk, a file-size limit) that write throws again, and a destructor that throws ends
  // the process (std::terminate: the uncaught rosbag::BagIOException). So the bag is closed
  // here, and on failure it is left undestroyed (its memory and descriptor are given up) and the
  // first exception goes on.
  auto owned = std::make_unique<rosbag::Bag>(path, rosbag::bagmode::Write);
  rosbag::Bag& bag = *owned;
  try {
    WriteAll(&bag, scan_topic, odom_topic, truth_topic, messages, bz2);
    bag.close();
  } catch (...) {
    static_cast<void>(owned.release());  // left undestroyed: see above
    throw;
  }
}

}  // namespace splam::io::internal
