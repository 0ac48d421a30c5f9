#include "io/internal/cdr.h"

#include <bit>
#include <cmath>
#include <cstring>
#include <vector>

namespace splam::io::internal {
namespace {

class CdrReader {
 public:
  explicit CdrReader(std::string_view bytes) {
    if (bytes.size() < 4 || bytes[0] != 0 || (bytes[1] != 0 && bytes[1] != 1)) {
      ok_ = false;
      return;
    }
    little_ = bytes[1] == 1;
    data_ = bytes.substr(4);
  }
  bool ok() const { return ok_; }
  std::size_t remaining() const { return ok_ ? data_.size() - at_ : 0; }

  template <class T>
  T Read() {
    at_ = (at_ + sizeof(T) - 1) / sizeof(T) * sizeof(T);
    if (!ok_ || at_ > data_.size() || data_.size() - at_ < sizeof(T)) {
      ok_ = false;
      return T{};
    }
    unsigned char raw[sizeof(T)];
    std::memcpy(raw, data_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    if (little_ != (std::endian::native == std::endian::little))
      for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(raw[i], raw[sizeof(T) - 1 - i]);
    T value;
    std::memcpy(&value, raw, sizeof(T));
    return value;
  }
  std::string String() {
    const std::uint32_t n = Read<std::uint32_t>();
    if (!ok_ || n > data_.size() - at_) {
      ok_ = false;
      return {};
    }
    std::string s(data_.substr(at_, n));
    at_ += n;
    if (!s.empty() && s.back() == '\0') s.pop_back();
    return s;
  }
  // A sequence's count, refused when its elements of `element_bytes` could not fit.
  std::uint32_t Count(std::size_t element_bytes) {
    const std::uint32_t n = Read<std::uint32_t>();
    if (ok_ && n > remaining() / element_bytes) ok_ = false;
    return ok_ ? n : 0;
  }
  double Time() {  // builtin_interfaces/Time
    const auto sec = Read<std::int32_t>();
    const auto nanosec = Read<std::uint32_t>();
    return sec + 1e-9 * nanosec;
  }

 private:
  std::string_view data_;
  std::size_t at_ = 0;
  bool little_ = true;
  bool ok_ = true;
};

class CdrWriter {
 public:
  CdrWriter() : bytes_{'\0', '\1', '\0', '\0'} {}
  template <class T>
  void Write(T value) {
    while ((bytes_.size() - 4) % sizeof(T) != 0) bytes_.push_back('\0');
    char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    if (std::endian::native != std::endian::little)
      for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(raw[i], raw[sizeof(T) - 1 - i]);
    bytes_.append(raw, sizeof(T));
  }
  void String(const std::string& s) {
    Write(static_cast<std::uint32_t>(s.size() + 1));
    bytes_ += s;
    bytes_.push_back('\0');
  }
  void Time(double t) {
    const double sec = std::floor(t);
    auto nanosec = static_cast<std::uint32_t>(std::llround((t - sec) * 1e9));
    auto whole = static_cast<std::int32_t>(sec);
    if (nanosec >= 1000000000u) {
      nanosec -= 1000000000u;
      ++whole;
    }
    Write(whole);
    Write(nanosec);
  }
  void Header(double t, const std::string& frame) {
    Time(t);
    String(frame);
  }
  void Yaw(double yaw) {  // a quaternion about z
    for (double q : {0.0, 0.0, std::sin(0.5 * yaw), std::cos(0.5 * yaw)}) Write(q);
  }
  std::string& bytes() { return bytes_; }

 private:
  std::string bytes_;
};

double YawOf(double x, double y, double z, double w) {
  return std::atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z));
}

// geometry_msgs/Pose (Point, Quaternion) or Transform (Vector3, Quaternion) into *out.
void ReadPlanarPose(CdrReader* r, RosPose* out) {
  out->x = r->Read<double>();
  out->y = r->Read<double>();
  r->Read<double>();  // z
  const double qx = r->Read<double>(), qy = r->Read<double>(), qz = r->Read<double>(),
               qw = r->Read<double>();
  out->yaw = YawOf(qx, qy, qz, qw);
}

}  // namespace

bool DecodeLaserScan(std::string_view cdr, RosScan* out) {
  CdrReader r(cdr);
  out->time_s = r.Time();
  out->frame = r.String();
  out->angle_min = r.Read<float>();
  r.Read<float>();  // angle_max
  out->angle_increment = r.Read<float>();
  r.Read<float>();  // time_increment
  r.Read<float>();  // scan_time
  out->range_min = r.Read<float>();
  out->range_max = r.Read<float>();
  const std::uint32_t n = r.Count(4);
  out->ranges.resize(n);
  for (float& v : out->ranges) v = r.Read<float>();
  const std::uint32_t intensities = r.Count(4);
  for (std::uint32_t i = 0; i < intensities; ++i) r.Read<float>();
  return r.ok();
}

bool DecodeOdometry(std::string_view cdr, RosPose* out) {
  CdrReader r(cdr);
  out->time_s = r.Time();
  out->parent = r.String();
  out->child = r.String();
  ReadPlanarPose(&r, out);
  for (int i = 0; i < 36; ++i) r.Read<double>();  // pose covariance
  out->tv_mps = r.Read<double>();
  r.Read<double>();
  r.Read<double>();
  r.Read<double>();
  r.Read<double>();
  out->rv_radps = r.Read<double>();
  for (int i = 0; i < 36; ++i) r.Read<double>();  // twist covariance
  return r.ok();
}

bool DecodeTransforms(std::string_view cdr, std::vector<RosPose>* out) {
  CdrReader r(cdr);
  // A TransformStamped takes at least 8 (stamp) + 4 + 4 (strings) + 56 (transform) bytes.
  const std::uint32_t n = r.Count(72);
  for (std::uint32_t i = 0; i < n && r.ok(); ++i) {
    RosPose p;
    p.time_s = r.Time();
    p.parent = r.String();
    p.child = r.String();
    ReadPlanarPose(&r, &p);
    out->push_back(std::move(p));
  }
  return r.ok();
}

std::string EncodeLaserScan(const RosScan& scan) {
  CdrWriter w;
  w.Header(scan.time_s, scan.frame);
  const double n = static_cast<double>(scan.ranges.size());
  for (double v : {scan.angle_min, scan.angle_min + (n - 1) * scan.angle_increment,
                   scan.angle_increment, 0.0, 0.0, scan.range_min, scan.range_max})
    w.Write(static_cast<float>(v));
  w.Write(static_cast<std::uint32_t>(scan.ranges.size()));
  for (float r : scan.ranges) w.Write(r);
  w.Write(std::uint32_t{0});  // intensities
  return std::move(w.bytes());
}

std::string EncodeOdometry(const RosPose& pose) {
  CdrWriter w;
  w.Header(pose.time_s, pose.parent);
  w.String(pose.child);
  for (double v : {pose.x, pose.y, 0.0}) w.Write(v);
  w.Yaw(pose.yaw);
  for (int i = 0; i < 36; ++i) w.Write(0.0);
  for (double v : {pose.tv_mps, 0.0, 0.0, 0.0, 0.0, pose.rv_radps}) w.Write(v);
  for (int i = 0; i < 36; ++i) w.Write(0.0);
  return std::move(w.bytes());
}

std::string EncodeTransforms(const std::vector<RosPose>& transforms) {
  CdrWriter w;
  w.Write(static_cast<std::uint32_t>(transforms.size()));
  for (const RosPose& p : transforms) {
    w.Header(p.time_s, p.parent);
    w.String(p.child);
    for (double v : {p.x, p.y, 0.0}) w.Write(v);
    w.Yaw(p.yaw);
  }
  return std::move(w.bytes());
}

#define SPLAM_SEPARATOR \
  "\n================================================================================\nMSG: "
#define SPLAM_HEADER                                                                \
  SPLAM_SEPARATOR                                                                   \
  "std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id" SPLAM_SEPARATOR \
  "builtin_interfaces/Time\nint32 sec\nuint32 nanosec"
#define SPLAM_VECTOR3 SPLAM_SEPARATOR "geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z"
#define SPLAM_QUATERNION \
  SPLAM_SEPARATOR "geometry_msgs/Quaternion\nfloat64 x\nfloat64 y\nfloat64 z\nfloat64 w"

const char kLaserScanDefinition[] =
    "std_msgs/Header header\nfloat32 angle_min\nfloat32 angle_max\nfloat32 angle_increment\n"
    "float32 time_increment\nfloat32 scan_time\nfloat32 range_min\nfloat32 range_max\n"
    "float32[] ranges\nfloat32[] intensities" SPLAM_HEADER;
const char kOdometryDefinition[] =
    "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance pose\n"
    "geometry_msgs/TwistWithCovariance twist" SPLAM_HEADER SPLAM_SEPARATOR
    "geometry_msgs/PoseWithCovariance\ngeometry_msgs/Pose pose\nfloat64[36] "
    "covariance" SPLAM_SEPARATOR
    "geometry_msgs/Pose\ngeometry_msgs/Point position\ngeometry_msgs/Quaternion "
    "orientation" SPLAM_SEPARATOR
    "geometry_msgs/Point\nfloat64 x\nfloat64 y\nfloat64 z" SPLAM_QUATERNION SPLAM_SEPARATOR
    "geometry_msgs/TwistWithCovariance\ngeometry_msgs/Twist twist\nfloat64[36] "
    "covariance" SPLAM_SEPARATOR
    "geometry_msgs/Twist\ngeometry_msgs/Vector3 linear\ngeometry_msgs/Vector3 "
    "angular" SPLAM_VECTOR3;
const char kTfMessageDefinition[] =
    "geometry_msgs/TransformStamped[] transforms" SPLAM_SEPARATOR
    "geometry_msgs/TransformStamped\nstd_msgs/Header header\nstring child_frame_id\n"
    "geometry_msgs/Transform transform" SPLAM_HEADER SPLAM_SEPARATOR
    "geometry_msgs/Transform\ngeometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion "
    "rotation" SPLAM_VECTOR3 SPLAM_QUATERNION;

}  // namespace splam::io::internal
