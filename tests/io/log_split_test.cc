// A log cut into sessions (io::SplitLog): every message in one session, in order; within a
// session every relative motion of the odometry as in the log, its first pose moved as far as
// asked; the motion recorded undoes it; ground truth and time stamps untouched.
#include "io/log_split.h"

#include <gtest/gtest.h>

#include <cmath>

#include "kernel/angle.h"
#include "kernel/random.h"

namespace splam::io {
namespace {

// A log of `scans` laser messages along a random walk, an ODOM and a TRUEPOS message beside
// each scan, a sonar message every tenth; the truth is the odometry slightly bent.
CarmenLog RandomWalkLog(int scans, std::uint64_t seed) {
  kernel::Random random(seed);
  CarmenLog log;
  log.comments = {" a random walk"};
  log.messages.reserve(static_cast<std::size_t>(4 * scans));
  kernel::Pose2 odometry(random.Uniform(-20, 20), random.Uniform(-20, 20), random.Uniform(-3, 3));
  kernel::Pose2 truth = odometry;
  for (int i = 0; i < scans; ++i) {
    const kernel::Pose2 step(random.Uniform(0, 0.3), random.Uniform(-0.05, 0.05),
                             random.Uniform(-0.3, 0.3));
    odometry = odometry * step;
    truth = truth * step * kernel::Pose2(0.0, 0.0, 0.001);
    const LogStamp stamp{0.1 * i, "test", 0.1 * i};
    // Made in place: a message copied into the variant set off GCC 12's maybe-uninitialized.
    auto& odom = std::get<OdometryMessage>(log.messages.emplace_back(OdometryMessage{}));
    odom.pose = odometry;
    odom.stamp = stamp;
    auto& laser = std::get<LaserMessage>(log.messages.emplace_back(LaserMessage{}));
    laser.robot_pose = odometry;
    laser.laser_pose = odometry * kernel::Pose2(0.1, 0.0, 0.0);
    laser.scan.ranges_m = {1.0, 2.0, 3.0};
    laser.scan.timestamp_s = stamp.ipc_timestamp_s;
    laser.stamp = stamp;
    log.messages.push_back(TruePoseMessage{truth, odometry, stamp});
    if (i % 10 == 0) log.messages.push_back(SonarMessage{0.2, {1.5}, {kernel::Pose2()}, stamp});
  }
  return log;
}

double PoseGap(const kernel::Pose2& a, const kernel::Pose2& b) {
  return (a.translation() - b.translation()).norm() +
         std::abs(kernel::WrapAngle(a.theta() - b.theta()));
}

// 50 random logs and splits: the invariants of a split.
TEST(SplitLog, SessionsPartitionTheLogAndKeepEveryRelativeMotion) {
  for (std::uint64_t trial = 0; trial < 50; ++trial) {
    const int scans = 40 + static_cast<int>(trial) * 7;
    const CarmenLog log = RandomWalkLog(scans, trial);
    LogSplitOptions options;
    options.sessions = 2 + static_cast<int>(trial % 4);
    options.seed = trial;
    const auto sessions = SplitLog(log, options);
    ASSERT_TRUE(sessions.ok()) << sessions.error;
    ASSERT_EQ(static_cast<int>(sessions->size()), options.sessions);
    std::size_t next = 0;  // the log's next message
    int total_scans = 0;
    for (const LogSession& s : *sessions) {
      EXPECT_GE(s.scans, scans / options.sessions);
      EXPECT_LE(s.scans, scans / options.sessions + 1);
      EXPECT_EQ(static_cast<int>(s.log.Lasers().size()), s.scans);
      total_scans += s.scans;
      const kernel::Pose2 session_T_log = s.log_T_session.Inverse();
      const auto lasers = s.log.Lasers();
      const double offset_m = (lasers.front()->robot_pose.translation() -
                               (s.log_T_session * lasers.front()->robot_pose).translation())
                                  .norm();
      EXPECT_GE(offset_m, options.min_offset_m - 1e-9);
      EXPECT_LE(offset_m, options.max_offset_m + 1e-9);
      EXPECT_EQ(s.first_time_s, lasers.front()->stamp.ipc_timestamp_s);
      EXPECT_EQ(s.last_time_s, lasers.back()->stamp.ipc_timestamp_s);
      for (const LogMessage& m : s.log.messages) {
        ASSERT_LT(next, log.messages.size());
        const LogMessage& original = log.messages[next++];
        ASSERT_EQ(m.index(), original.index());
        if (const auto* l = std::get_if<LaserMessage>(&m)) {
          const auto& o = std::get<LaserMessage>(original);
          EXPECT_LT(PoseGap(l->robot_pose, session_T_log * o.robot_pose), 1e-9);
          EXPECT_LT(PoseGap(s.log_T_session * l->laser_pose, o.laser_pose), 1e-9);
          EXPECT_EQ(l->scan.ranges_m, o.scan.ranges_m);
          EXPECT_EQ(l->stamp, o.stamp);
        } else if (const auto* t = std::get_if<TruePoseMessage>(&m)) {
          const auto& o = std::get<TruePoseMessage>(original);
          EXPECT_EQ(t->true_pose.ToVector(), o.true_pose.ToVector());
          EXPECT_LT(PoseGap(t->odometry_pose, session_T_log * o.odometry_pose), 1e-9);
        } else if (const auto* d = std::get_if<OdometryMessage>(&m)) {
          EXPECT_LT(PoseGap(s.log_T_session * d->pose, std::get<OdometryMessage>(original).pose),
                    1e-9);
        }
      }
      // Relative motions between consecutive scans, as the log had them.
      for (std::size_t i = 1; i < lasers.size(); ++i) {
        const kernel::Pose2 moved = lasers[i - 1]->robot_pose.Between(lasers[i]->robot_pose);
        const kernel::Pose2 original = (s.log_T_session * lasers[i - 1]->robot_pose)
                                           .Between(s.log_T_session * lasers[i]->robot_pose);
        EXPECT_LT(PoseGap(moved, original), 1e-9);
      }
    }
    EXPECT_EQ(next, log.messages.size());
    EXPECT_EQ(total_scans, scans);
  }
}

TEST(SplitLog, TheSameSeedGivesTheSameSessionsAnotherSeedOthers) {
  const CarmenLog log = RandomWalkLog(100, 3);
  LogSplitOptions options;
  const auto a = SplitLog(log, options), b = SplitLog(log, options);
  options.seed = 2;
  const auto c = SplitLog(log, options);
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  for (std::size_t k = 0; k < a->size(); ++k) {
    EXPECT_EQ((*a)[k].log_T_session.ToVector(), (*b)[k].log_T_session.ToVector());
    EXPECT_GT(PoseGap((*a)[k].log_T_session, (*c)[k].log_T_session), 1.0);
  }
}

TEST(SplitLog, BadRequestsAreClearErrors) {
  const CarmenLog log = RandomWalkLog(25, 1);
  LogSplitOptions options;
  EXPECT_EQ(SplitLog(log, options).error, "25 scans make no 3 sessions of at least 10 scans");
  options.sessions = 1;
  EXPECT_EQ(SplitLog(log, options).error, "sessions must be in [2, 10]");
  options.sessions = 2;
  options.min_offset_m = 10;
  options.max_offset_m = 5;
  EXPECT_FALSE(SplitLog(log, options).ok());
  options.max_offset_m = 20;
  EXPECT_TRUE(SplitLog(log, options).ok());
}

}  // namespace
}  // namespace splam::io
