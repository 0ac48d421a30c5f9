#include "io/log_split.h"

#include <fmt/core.h>

#include <cmath>
#include <type_traits>
#include <utility>

#include "kernel/angle.h"
#include "kernel/random.h"

namespace splam::io {
namespace {

constexpr int kMinScansPerSession = 10;

// The message's time stamp, for the session's first and last scan.
double TimeOf(const LaserMessage& m) { return m.stamp.ipc_timestamp_s; }

// Moves every odometric pose of `message` by `s` (session_T_log); ground truth stays.
void Move(const kernel::Pose2& s, LogMessage* message) {
  std::visit(
      [&s](auto& m) {
        using M = std::decay_t<decltype(m)>;
        if constexpr (std::is_same_v<M, LaserMessage>) {
          m.laser_pose = s * m.laser_pose;
          m.robot_pose = s * m.robot_pose;
        } else if constexpr (std::is_same_v<M, OdometryMessage>) {
          m.pose = s * m.pose;
        } else if constexpr (std::is_same_v<M, TruePoseMessage>) {
          m.odometry_pose = s * m.odometry_pose;
        }
      },
      *message);
}

}  // namespace

kernel::Status LogSplitOptions::Validate() const {
  if (sessions < 2 || sessions > 10) return kernel::Status::Error("sessions must be in [2, 10]");
  if (!(min_offset_m >= 0 && max_offset_m >= min_offset_m && max_offset_m <= 1e6))
    return kernel::Status::Error(
        "the offsets must satisfy 0 <= min_offset_m <= max_offset_m <= 1e6 m");
  return kernel::Status::Ok();
}

Result<std::vector<LogSession>> SplitLog(const CarmenLog& log, const LogSplitOptions& options) {
  using R = Result<std::vector<LogSession>>;
  if (kernel::Status s = options.Validate(); !s.ok()) return R::Fail(s);
  // The indices of the laser messages; session k starts at scan k * n / sessions.
  std::vector<std::size_t> scans;
  for (std::size_t i = 0; i < log.messages.size(); ++i)
    if (std::holds_alternative<LaserMessage>(log.messages[i])) scans.push_back(i);
  const auto n = static_cast<long>(scans.size());
  if (n < static_cast<long>(options.sessions) * kMinScansPerSession)
    return R::Fail(fmt::format("{} scans make no {} sessions of at least {} scans", n,
                               options.sessions, kMinScansPerSession));
  kernel::Random random(options.seed);
  std::vector<LogSession> sessions;
  for (int k = 0; k < options.sessions; ++k) {
    const std::size_t first_scan = static_cast<std::size_t>(k * n / options.sessions);
    const std::size_t last_scan = static_cast<std::size_t>((k + 1) * n / options.sessions) - 1;
    const std::size_t begin = k == 0 ? 0 : scans[first_scan];
    const std::size_t end = k + 1 == options.sessions ? log.messages.size() : scans[last_scan + 1];
    const auto& first = std::get<LaserMessage>(log.messages[scans[first_scan]]);
    const auto& last = std::get<LaserMessage>(log.messages[scans[last_scan]]);
    // The session's first pose, moved offset metres in a uniform direction, a uniform heading.
    const double offset_m = random.Uniform(options.min_offset_m, options.max_offset_m);
    const double direction = random.Uniform(-kernel::kPi, kernel::kPi);
    const double heading = random.Uniform(-kernel::kPi, kernel::kPi);
    const kernel::Pose2 moved(
        first.robot_pose.translation() +
            offset_m * Eigen::Vector2d(std::cos(direction), std::sin(direction)),
        heading);
    const kernel::Pose2 session_T_log = moved * first.robot_pose.Inverse();

    LogSession session;
    session.name = fmt::format("session{}", k + 1);
    session.log.comments = log.comments;
    session.log.comments.push_back(
        fmt::format(" {} of {}: scans {} to {} of the log, odometry moved by a rigid motion",
                    session.name, options.sessions, first_scan + 1, last_scan + 1));
    for (std::size_t i = begin; i < end; ++i) {
      session.log.messages.push_back(log.messages[i]);
      Move(session_T_log, &session.log.messages.back());
    }
    session.log_T_session = session_T_log.Inverse();
    session.scans = static_cast<int>(last_scan - first_scan + 1);
    session.first_time_s = TimeOf(first);
    session.last_time_s = TimeOf(last);
    sessions.push_back(std::move(session));
  }
  return R::Ok(std::move(sessions));
}

}  // namespace splam::io
