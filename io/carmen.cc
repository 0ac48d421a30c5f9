#include "io/carmen.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "io/internal/plausible.h"
#include "io/text.h"
#include "io/trajectory.h"

namespace splam::io {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
using internal::kMaxCoordinateM;
using internal::kMaxHeadingRad;
using internal::kMaxRangeM;

// Reads the tokens of one message in order; the first failure records what was expected.
class Cursor {
 public:
  explicit Cursor(std::vector<std::string_view> tokens) : tokens_(std::move(tokens)) {}

  bool Double(double* out, const char* what) {
    if (!Available(what)) return false;
    const auto value = ParseDouble(tokens_[next_]);
    if (!value)
      return Fail(std::string("expected a number for ") + what + ", found " +
                  Quoted(tokens_[next_]));
    ++next_;
    *out = *value;
    return true;
  }
  // A finite number: poses, angles and timestamps must not be NaN or infinite.
  bool Finite(double* out, const char* what) {
    if (!Double(out, what)) return false;
    if (!std::isfinite(*out)) return Fail(std::string(what) + " is not finite");
    return true;
  }
  bool Count(int* out, const char* what, long max = 1 << 20) {
    if (!Available(what)) return false;
    const auto value = ParseInteger(tokens_[next_]);
    if (!value || *value < 0 || *value > max) {
      return Fail(std::string("expected a count for ") + what + ", found " +
                  Quoted(tokens_[next_]));
    }
    ++next_;
    *out = static_cast<int>(*value);
    return true;
  }
  // A number of magnitude at most `limit`.
  bool Bounded(double* out, const char* what, double limit, const char* unit) {
    if (!Finite(out, what)) return false;
    if (std::abs(*out) > limit)
      return Fail(std::string(what) + " " + FormatDouble(*out) + " is beyond +-" +
                  FormatDouble(limit) + (*unit ? std::string(" ") + unit : ""));
    return true;
  }
  bool Pose(kernel::Pose2* out, const char* what) {
    double x = 0, y = 0, th = 0;
    if (!Bounded(&x, what, kMaxCoordinateM, "m") || !Bounded(&y, what, kMaxCoordinateM, "m") ||
        !Bounded(&th, what, kMaxHeadingRad, "rad"))
      return false;
    *out = kernel::Pose2(x, y, th);
    return true;
  }
  bool ScanGeometry(const kernel::Scan& s) {
    if (kernel::Status problem = internal::ScanGeometryProblem(s); !problem.ok())
      return Fail(problem.message());
    return true;
  }
  bool Stamp(LogStamp* out) {
    if (!Finite(&out->ipc_timestamp_s, "ipc_timestamp")) return false;
    if (!Available("hostname")) return false;
    out->hostname = std::string(tokens_[next_++]);
    return Finite(&out->logger_timestamp_s, "logger_timestamp");
  }
  bool End() {
    if (next_ != tokens_.size()) {
      return Fail(std::to_string(tokens_.size() - next_) + " unexpected extra tokens");
    }
    return true;
  }
  const std::string& error() const { return error_; }
  bool Fail(std::string message) {
    if (error_.empty()) error_ = std::move(message);
    return false;
  }

 private:
  bool Available(const char* what) {
    if (next_ < tokens_.size()) return true;
    return Fail(std::string("line ends early: missing ") + what);
  }

  std::vector<std::string_view> tokens_;
  std::size_t next_ = 1;  // token 0 is the message name
  std::string error_;
};

// Applies the range conventions to a raw reading.
double NormaliseRange(double raw, double max_range, CarmenReadStats* stats) {
  if (std::isnan(raw) || raw <= 0.0) {
    ++stats->invalid_readings;
    return kNaN;
  }
  if (raw >= max_range) {
    ++stats->no_return_readings;
    return kernel::Scan::kNoReturn;
  }
  return raw;
}

double WrittenRange(double range, double max_range) {
  if (std::isnan(range) || range < 0.0) return 0.0;
  if (range >= max_range) return max_range;
  return range;
}

bool ReadRanges(Cursor* c, int n, double max_range, CarmenReadStats* stats,
                std::vector<double>* out) {
  out->resize(n);
  for (int i = 0; i < n; ++i) {
    double raw = 0.0;
    if (!c->Double(&raw, "range reading")) return false;
    (*out)[i] = NormaliseRange(raw, max_range, stats);
  }
  return true;
}

bool ParseFlaser(Cursor* c, const CarmenReadOptions& o, CarmenReadStats* stats, LaserMessage* m) {
  m->format = LaserMessage::Format::kFlaser;
  int n = 0;
  if (!c->Count(&n, "number of readings")) return false;
  kernel::Scan& s = m->scan;
  s.start_angle_rad = o.flaser_start_angle_rad;
  s.angular_step_rad = o.flaser_angular_step_rad > 0.0 ? o.flaser_angular_step_rad
                       : n % 2 == 0                    ? kernel::kPi / std::max(n, 1)
                                                       : kernel::kPi / std::max(n - 1, 1);
  s.min_range_m = o.flaser_min_range_m;
  s.max_range_m = o.flaser_max_range_m;
  return ReadRanges(c, n, s.max_range_m, stats, &s.ranges_m) && c->ScanGeometry(s) &&
         c->Pose(&m->laser_pose, "laser pose") && c->Pose(&m->robot_pose, "odometry pose") &&
         c->Stamp(&m->stamp) && c->End();
}

bool ParseRobotLaser(Cursor* c, CarmenReadStats* stats, LaserMessage* m) {
  m->format = LaserMessage::Format::kRobotLaser1;
  kernel::Scan& s = m->scan;
  double fov = 0.0, laser_type = 0.0, remission_mode = 0.0;
  int n = 0, num_remissions = 0;
  // laser_type and remission_mode are small codes: bounded before they become ints.
  if (!c->Bounded(&laser_type, "laser_type", 1e6, "") ||
      !c->Finite(&s.start_angle_rad, "start_angle") ||
      !c->Bounded(&fov, "field_of_view", 2.0 * kernel::kPi + 1e-9, "rad") ||
      !c->Finite(&s.angular_step_rad, "angular_resolution") ||
      !c->Finite(&s.max_range_m, "maximum_range") || !c->Finite(&m->accuracy_m, "accuracy") ||
      !c->Bounded(&remission_mode, "remission_mode", 1e6, "") ||
      !c->Count(&n, "number of readings")) {
    return false;
  }
  m->laser_type = static_cast<int>(laser_type);
  m->remission_mode = static_cast<int>(remission_mode);
  s.min_range_m = 0.0;
  if (!(fov >= 0.0)) return c->Fail("field of view " + FormatDouble(fov) + " rad is negative");
  if (!ReadRanges(c, n, s.max_range_m, stats, &s.ranges_m) || !c->ScanGeometry(s) ||
      !c->Count(&num_remissions, "number of remissions")) {
    return false;
  }
  m->remissions.resize(num_remissions);
  for (double& e : m->remissions) {
    if (!c->Double(&e, "remission")) return false;
  }
  return c->Pose(&m->laser_pose, "laser pose") && c->Pose(&m->robot_pose, "robot pose") &&
         c->Finite(&m->tv_mps, "tv") && c->Finite(&m->rv_radps, "rv") &&
         c->Finite(&m->forward_safety_dist_m, "forward_safety_dist") &&
         c->Finite(&m->side_safety_dist_m, "side_safety_dist") &&
         c->Finite(&m->turn_axis, "turn_axis") && c->Stamp(&m->stamp) && c->End();
}

bool ParseSonar(Cursor* c, CarmenReadStats* stats, SonarMessage* m) {
  int n = 0, num_poses = 0;
  if (!c->Finite(&m->cone_angle_rad, "cone_angle") || !c->Count(&n, "number of sonars") ||
      !ReadRanges(c, n, kMaxRangeM, stats, &m->ranges_m) ||
      !c->Count(&num_poses, "number of sonar poses")) {
    return false;
  }
  m->robot_T_sonar.resize(num_poses);
  for (kernel::Pose2& p : m->robot_T_sonar) {
    if (!c->Pose(&p, "sonar pose")) return false;
  }
  return c->Stamp(&m->stamp) && c->End();
}

template <class T>
std::vector<const T*> OfType(const std::vector<LogMessage>& messages) {
  std::vector<const T*> out;
  for (const LogMessage& m : messages) {
    if (const T* p = std::get_if<T>(&m)) out.push_back(p);
  }
  return out;
}

void Append(std::string* out, double value) {
  out->push_back(' ');
  out->append(FormatDouble(value));
}
void Append(std::string* out, const kernel::Pose2& p) {
  Append(out, p.x());
  Append(out, p.y());
  Append(out, p.theta());
}
void Append(std::string* out, const LogStamp& s) {
  Append(out, s.ipc_timestamp_s);
  out->push_back(' ');
  out->append(s.hostname);
  Append(out, s.logger_timestamp_s);
}

// A CARMEN message type is a name (FLASER, ROBOTLASER1, PARAM, ...): a letter, then letters,
// digits and underscores. Anything else starting a line is not a message (binary junk).
bool IsMessageType(std::string_view token) {
  const auto letter = [](char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); };
  if (token.empty() || !letter(token.front())) return false;
  return std::all_of(token.begin(), token.end(),
                     [&](char c) { return letter(c) || (c >= '0' && c <= '9') || c == '_'; });
}

}  // namespace

std::vector<const LaserMessage*> CarmenLog::Lasers() const {
  return OfType<LaserMessage>(messages);
}
std::vector<const OdometryMessage*> CarmenLog::Odometry() const {
  return OfType<OdometryMessage>(messages);
}
std::vector<const TruePoseMessage*> CarmenLog::TruePoses() const {
  return OfType<TruePoseMessage>(messages);
}

CarmenReadResult ParseCarmenLog(const std::string& text, const std::string& name,
                                const CarmenReadOptions& options) {
  CarmenReadResult result;
  CarmenLog log;
  CarmenReadStats& stats = result.stats;
  std::size_t pos = TextStart(text);
  int line_number = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    const std::string_view line(text.data() + pos, end - pos);
    pos = end + 1;
    ++line_number;
    ++stats.lines;
    std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string_view::npos) continue;
    if (line[first] == '#') {
      std::string_view comment = line.substr(first + 1);
      if (!comment.empty() && comment.back() == '\r') comment.remove_suffix(1);
      log.comments.emplace_back(comment);
      continue;
    }
    std::vector<std::string_view> tokens = SplitTokens(line);
    const std::string_view type = tokens[0];
    Cursor cursor(tokens);
    bool ok = true;
    if (type == "FLASER") {
      LaserMessage m;
      ok = ParseFlaser(&cursor, options, &stats, &m);
      m.scan.timestamp_s = m.stamp.ipc_timestamp_s;
      if (ok) log.messages.push_back(std::move(m));
    } else if (type == "ROBOTLASER1") {
      LaserMessage m;
      ok = ParseRobotLaser(&cursor, &stats, &m);
      m.scan.timestamp_s = m.stamp.ipc_timestamp_s;
      if (ok) log.messages.push_back(std::move(m));
    } else if (type == "ODOM") {
      OdometryMessage m;
      ok = cursor.Pose(&m.pose, "pose") && cursor.Finite(&m.tv_mps, "tv") &&
           cursor.Finite(&m.rv_radps, "rv") && cursor.Finite(&m.accel_mps2, "accel") &&
           cursor.Stamp(&m.stamp) && cursor.End();
      if (ok) log.messages.push_back(std::move(m));
    } else if (type == "TRUEPOS") {
      TruePoseMessage m;
      ok = cursor.Pose(&m.true_pose, "true pose") &&
           cursor.Pose(&m.odometry_pose, "odometry pose") && cursor.Stamp(&m.stamp) && cursor.End();
      if (ok) log.messages.push_back(std::move(m));
    } else if (type == "SONAR") {
      SonarMessage m;
      ok = ParseSonar(&cursor, &stats, &m);
      if (ok) log.messages.push_back(std::move(m));
    } else if (IsMessageType(type)) {
      ++stats.skipped_messages[std::string(type)];
    } else {
      ok = cursor.Fail("not a CARMEN message: it starts with " + Quoted(type));
    }
    if (!ok) {
      if (options.skip_malformed_lines) {
        ++stats.malformed_lines;
        continue;
      }
      const std::string what = IsMessageType(type) ? std::string(type) + ": " : "";
      result.log = Result<CarmenLog>::Fail(FileError(name, line_number, what + cursor.error()));
      result.before_error = std::move(log);
      return result;
    }
  }
  result.log = Result<CarmenLog>::Ok(std::move(log));
  return result;
}

CarmenReadResult ReadCarmenLog(const std::string& path, const CarmenReadOptions& options) {
  std::string text;
  const kernel::Status read = std::filesystem::is_directory(path)
                                  ? FileError(path, 0, "is a directory, not a log")
                                  : ReadTextFile(path, &text);
  if (!read.ok()) {
    CarmenReadResult result;
    result.log = Result<CarmenLog>::Fail(read);
    return result;
  }
  return ParseCarmenLog(text, path, options);
}

std::string FormatCarmenLog(const CarmenLog& log) {
  std::string out;
  for (const std::string& c : log.comments) out += "#" + OneLine(c) + "\n";
  for (const LogMessage& message : log.messages) {
    if (const auto* m = std::get_if<OdometryMessage>(&message)) {
      out += "ODOM";
      Append(&out, m->pose);
      Append(&out, m->tv_mps);
      Append(&out, m->rv_radps);
      Append(&out, m->accel_mps2);
      Append(&out, m->stamp);
    } else if (const auto* t = std::get_if<TruePoseMessage>(&message)) {
      out += "TRUEPOS";
      Append(&out, t->true_pose);
      Append(&out, t->odometry_pose);
      Append(&out, t->stamp);
    } else if (const auto* s = std::get_if<SonarMessage>(&message)) {
      out += "SONAR";
      Append(&out, s->cone_angle_rad);
      out += " " + std::to_string(s->ranges_m.size());
      for (double r : s->ranges_m)
        Append(&out, std::isinf(r) ? std::numeric_limits<double>::max() : r);
      out += " " + std::to_string(s->robot_T_sonar.size());
      for (const kernel::Pose2& p : s->robot_T_sonar) Append(&out, p);
      Append(&out, s->stamp);
    } else if (const auto* l = std::get_if<LaserMessage>(&message)) {
      const kernel::Scan& scan = l->scan;
      if (l->format == LaserMessage::Format::kFlaser) {
        out += "FLASER " + std::to_string(scan.size());
        for (double r : scan.ranges_m) Append(&out, WrittenRange(r, scan.max_range_m));
        Append(&out, l->laser_pose);
        Append(&out, l->robot_pose);
      } else {
        out += "ROBOTLASER1 " + std::to_string(l->laser_type);
        Append(&out, scan.start_angle_rad);
        Append(&out, scan.FieldOfView());
        Append(&out, scan.angular_step_rad);
        Append(&out, scan.max_range_m);
        Append(&out, l->accuracy_m);
        out += " " + std::to_string(l->remission_mode) + " " + std::to_string(scan.size());
        for (double r : scan.ranges_m) Append(&out, WrittenRange(r, scan.max_range_m));
        out += " " + std::to_string(l->remissions.size());
        for (double e : l->remissions) Append(&out, e);
        Append(&out, l->laser_pose);
        Append(&out, l->robot_pose);
        Append(&out, l->tv_mps);
        Append(&out, l->rv_radps);
        Append(&out, l->forward_safety_dist_m);
        Append(&out, l->side_safety_dist_m);
        Append(&out, l->turn_axis);
      }
      Append(&out, l->stamp);
    }
    out += "\n";
  }
  return out;
}

kernel::Status WriteCarmenLog(const std::string& path, const CarmenLog& log) {
  return WriteTextFile(path, FormatCarmenLog(log));
}

}  // namespace splam::io
