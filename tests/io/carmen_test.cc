#include "io/carmen.h"
#include "io/no_return_pile.h"

#include <gtest/gtest.h>

#include <functional>
#include <random>

#include <cmath>
#include <filesystem>

#include "kernel/random.h"

namespace splam::io {
namespace {

using kernel::Pose2;
using kernel::Random;

Pose2 RandomPose(Random* r) {
  return Pose2(r->Uniform(-100, 100), r->Uniform(-100, 100), r->Uniform(-4, 4));
}
LogStamp RandomStamp(Random* r) {
  return {r->Uniform(0, 1e9), "host" + std::to_string(r->Index(3)), r->Uniform(0, 3000)};
}

kernel::Scan RandomScan(Random* r, double max_range) {
  kernel::Scan s;
  s.start_angle_rad = r->Uniform(-2.5, 0);
  s.angular_step_rad = r->Uniform(0.001, 0.008);  // 701 beams within one turn
  s.max_range_m = max_range;
  s.ranges_m.resize(1 + r->Index(700));
  for (double& v : s.ranges_m) {
    const double u = r->Uniform();
    v = u < 0.1 ? kernel::Scan::kNoReturn : u < 0.15 ? NAN : r->Uniform(0.001, max_range * 0.999);
  }
  return s;
}

CarmenLog RandomLog(Random* r, const CarmenReadOptions& flaser) {
  CarmenLog log;
  log.comments = {" generated", " second comment with   spaces"};
  for (int i = 0; i < 30; ++i) {
    switch (r->Index(5)) {
      case 0:
        log.messages.push_back(OdometryMessage{RandomPose(r), r->Uniform(-1, 1), r->Uniform(-1, 1),
                                               0.0, RandomStamp(r)});
        break;
      case 1:
        log.messages.push_back(TruePoseMessage{RandomPose(r), RandomPose(r), RandomStamp(r)});
        break;
      case 2: {
        SonarMessage m{0.5,
                       {1.0, kernel::Scan::kNoReturn, 2.5},
                       {RandomPose(r), RandomPose(r)},
                       RandomStamp(r)};
        log.messages.push_back(m);
        break;
      }
      case 3: {
        LaserMessage m;
        m.format = LaserMessage::Format::kFlaser;
        m.scan = RandomScan(r, flaser.flaser_max_range_m);
        m.scan.start_angle_rad = flaser.flaser_start_angle_rad;
        m.scan.angular_step_rad = flaser.flaser_angular_step_rad;
        m.laser_pose = RandomPose(r);
        m.robot_pose = RandomPose(r);
        m.stamp = RandomStamp(r);
        m.scan.timestamp_s = m.stamp.ipc_timestamp_s;
        log.messages.push_back(m);
        break;
      }
      default: {
        LaserMessage m;
        m.scan = RandomScan(r, r->Uniform(1, 80));
        m.laser_type = 3;
        m.accuracy_m = 0.01;
        m.remission_mode = 1;
        m.remissions = {0.5, 0.25};
        m.laser_pose = RandomPose(r);
        m.robot_pose = RandomPose(r);
        m.tv_mps = 0.3;
        m.rv_radps = -0.1;
        m.forward_safety_dist_m = 0.2;
        m.side_safety_dist_m = 0.1;
        m.turn_axis = 1e6;
        m.stamp = RandomStamp(r);
        m.scan.timestamp_s = m.stamp.ipc_timestamp_s;
        log.messages.push_back(m);
      }
    }
  }
  return log;
}

// Exact equality, NaN equal to NaN.
void ExpectSameRanges(const std::vector<double>& a, const std::vector<double>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::isnan(a[i]))
      EXPECT_TRUE(std::isnan(b[i])) << i;
    else
      EXPECT_EQ(a[i], b[i]) << i;
  }
}

void ExpectSamePose(const Pose2& a, const Pose2& b) { EXPECT_EQ(a.ToVector(), b.ToVector()); }

TEST(CarmenLog, PropertyWriteThenReadIsExact) {
  Random random(31);
  CarmenReadOptions options;
  options.flaser_start_angle_rad = -1.5;
  options.flaser_angular_step_rad = 0.008;
  options.flaser_max_range_m = 50.0;
  for (int trial = 0; trial < 20; ++trial) {
    const CarmenLog log = RandomLog(&random, options);
    const CarmenReadResult read = ParseCarmenLog(FormatCarmenLog(log), "mem", options);
    ASSERT_TRUE(read.log.ok()) << read.log.error;
    const CarmenLog& back = *read.log.value;
    EXPECT_EQ(back.comments, log.comments);
    ASSERT_EQ(back.messages.size(), log.messages.size());
    for (std::size_t i = 0; i < log.messages.size(); ++i) {
      ASSERT_EQ(back.messages[i].index(), log.messages[i].index());
      if (const auto* a = std::get_if<OdometryMessage>(&log.messages[i])) {
        const auto& b = std::get<OdometryMessage>(back.messages[i]);
        ExpectSamePose(a->pose, b.pose);
        EXPECT_EQ(a->tv_mps, b.tv_mps);
        EXPECT_EQ(a->stamp, b.stamp);
      } else if (const auto* t = std::get_if<TruePoseMessage>(&log.messages[i])) {
        const auto& b = std::get<TruePoseMessage>(back.messages[i]);
        ExpectSamePose(t->true_pose, b.true_pose);
        ExpectSamePose(t->odometry_pose, b.odometry_pose);
        EXPECT_EQ(t->stamp, b.stamp);
      } else if (const auto* s = std::get_if<SonarMessage>(&log.messages[i])) {
        const auto& b = std::get<SonarMessage>(back.messages[i]);
        EXPECT_EQ(s->cone_angle_rad, b.cone_angle_rad);
        ExpectSameRanges(s->ranges_m, b.ranges_m);
        ASSERT_EQ(s->robot_T_sonar.size(), b.robot_T_sonar.size());
        EXPECT_EQ(s->stamp, b.stamp);
      } else {
        const auto& a_l = std::get<LaserMessage>(log.messages[i]);
        const auto& b_l = std::get<LaserMessage>(back.messages[i]);
        EXPECT_EQ(a_l.format, b_l.format);
        ExpectSameRanges(a_l.scan.ranges_m, b_l.scan.ranges_m);
        EXPECT_EQ(a_l.scan.start_angle_rad, b_l.scan.start_angle_rad);
        EXPECT_EQ(a_l.scan.angular_step_rad, b_l.scan.angular_step_rad);
        EXPECT_EQ(a_l.scan.max_range_m, b_l.scan.max_range_m);
        EXPECT_EQ(a_l.scan.timestamp_s, b_l.scan.timestamp_s);
        ExpectSamePose(a_l.laser_pose, b_l.laser_pose);
        ExpectSamePose(a_l.robot_pose, b_l.robot_pose);
        EXPECT_EQ(a_l.remissions, b_l.remissions);
        EXPECT_EQ(a_l.turn_axis, b_l.turn_axis);
        EXPECT_EQ(a_l.stamp, b_l.stamp);
      }
    }
    // And the text itself is a fixed point.
    EXPECT_EQ(FormatCarmenLog(back), FormatCarmenLog(log));
  }
}

TEST(CarmenLog, FlaserGeometryDefaultsFollowTheBeamCount) {
  auto step_for = [](int n) {
    std::string line = "FLASER " + std::to_string(n);
    for (int i = 0; i < n; ++i) line += " 1.0";
    line += " 0 0 0 0 0 0 1.0 host 1.0\n";
    const CarmenReadResult r = ParseCarmenLog(line, "mem");
    EXPECT_TRUE(r.log.ok()) << r.log.error;
    return r.log.value->Lasers()[0]->scan.angular_step_rad;
  };
  EXPECT_NEAR(step_for(180), M_PI / 180, 1e-15);  // intel: 1 deg from -90
  EXPECT_NEAR(step_for(361), M_PI / 360, 1e-15);  // mit-csail: 0.5 deg over 180 deg
  EXPECT_NEAR(step_for(181), M_PI / 180, 1e-15);
}

TEST(CarmenLog, RangeConventionsOnReading) {
  const std::string line = "FLASER 6 1.5 81.8 90.0 nan -1 0 0 0 0 0 0 0 1.0 host 1.0\n";
  const CarmenReadResult r = ParseCarmenLog(line, "mem");
  ASSERT_TRUE(r.log.ok()) << r.log.error;
  const kernel::Scan& s = r.log.value->Lasers()[0]->scan;
  EXPECT_EQ(s.ranges_m[0], 1.5);
  EXPECT_EQ(s.ranges_m[1], kernel::Scan::kNoReturn);  // >= 81.8
  EXPECT_EQ(s.ranges_m[2], kernel::Scan::kNoReturn);
  EXPECT_TRUE(std::isnan(s.ranges_m[3]));  // nan
  EXPECT_TRUE(std::isnan(s.ranges_m[4]));  // negative
  EXPECT_TRUE(std::isnan(s.ranges_m[5]));  // zero
  EXPECT_EQ(r.stats.no_return_readings, 2);
  EXPECT_EQ(r.stats.invalid_readings, 3);
  EXPECT_TRUE(s.IsHit(0));
  EXPECT_EQ(s.HitPoints().size(), 1u);
}

TEST(CarmenLog, UnknownMessagesAndCommentsAreKeptApart) {
  const std::string text =
      "# header\nPARAM robot_length 0.5\n\nSYNC 1\nODOM 1 2 0.5 0 0 0 1.0 h 1.0\nPARAM x y\n";
  const CarmenReadResult r = ParseCarmenLog(text, "mem");
  ASSERT_TRUE(r.log.ok()) << r.log.error;
  EXPECT_EQ(r.log.value->comments, std::vector<std::string>{" header"});
  EXPECT_EQ(r.log.value->Odometry().size(), 1u);
  EXPECT_EQ(r.stats.skipped_messages.at("PARAM"), 2);
  EXPECT_EQ(r.stats.skipped_messages.at("SYNC"), 1);
  EXPECT_EQ(r.stats.lines, 6);
}

struct BadLine {
  std::string text;
  std::string expected;  // part of the message
};

void PrintTo(const BadLine& b, std::ostream* os) { *os << b.text; }

class MalformedLineTest : public ::testing::TestWithParam<BadLine> {};

TEST_P(MalformedLineTest, FailsNamingFileAndLine) {
  const std::string text = "# ok\nODOM 1 2 0.5 0 0 0 1.0 h 1.0\n" + GetParam().text + "\n";
  const CarmenReadResult r = ParseCarmenLog(text, "test.clf");
  ASSERT_FALSE(r.log.ok());
  EXPECT_EQ(r.log.error.rfind("test.clf:3: ", 0), 0u) << r.log.error;
  EXPECT_NE(r.log.error.find(GetParam().expected), std::string::npos) << r.log.error;
  // With skipping, the rest of the log is still read.
  CarmenReadOptions skip;
  skip.skip_malformed_lines = true;
  const CarmenReadResult s =
      ParseCarmenLog(text + "ODOM 1 2 0.5 0 0 0 2.0 h 2.0\n", "test.clf", skip);
  ASSERT_TRUE(s.log.ok());
  EXPECT_EQ(s.stats.malformed_lines, 1);
  EXPECT_EQ(s.log.value->Odometry().size(), 2u);
}

INSTANTIATE_TEST_SUITE_P(
    Cases, MalformedLineTest,
    ::testing::Values(
        BadLine{"ODOM 1 2", "line ends early"},
        BadLine{"ODOM 1 2 x 0 0 0 1 h 1", "expected a number"},
        BadLine{"ODOM 1 2 0.5 0 0 0 1.0 h 1.0 extra", "unexpected extra"},
        BadLine{"ODOM nan 2 0.5 0 0 0 1.0 h 1.0", "not finite"},
        BadLine{"FLASER 3 1 2", "line ends early"}, BadLine{"FLASER -3 1 2", "expected a count"},
        BadLine{"FLASER 2 1 2 0 0 inf 0 0 0 1 h 1", "not finite"},
        BadLine{"ROBOTLASER1 0 -1.5 3 0.01 8 0.01 0 2 1 1 0 0 0 0 0 0 0 0 0 0 0 0 1 h",
                "line ends early"},
        BadLine{"TRUEPOS 1 2 3 4 5 6 7 h", "line ends early"},
        BadLine{"SONAR 0.5 2 1 1 2 0 0 0 1 h 1", "expected a number for sonar pose"},
        // Physically meaningless values: refused at the reader.
        BadLine{"ODOM 1e300 2 0.5 0 0 0 1.0 h 1.0", "pose 1e+300 is beyond +-1e+06 m"},
        BadLine{"ODOM 1 2 1e300 0 0 0 1.0 h 1.0", "is beyond +-10000 rad"},
        BadLine{"FLASER 2 1 2 1e300 0 0 0 0 0 1 h 1", "laser pose 1e+300"},
        BadLine{"ROBOTLASER1 0 -1.5 3 0 8 0.01 0 2 1 1 0 0 0 0 0 0 0 0 0 0 0 0 1 h 1",
                "angular resolution 0 rad is not positive"},
        // Passed, every beam at one bearing.
        BadLine{"ROBOTLASER1 0 -1.5 3 1e-30 8 0.01 0 2 1 1 0 0 0 0 0 0 0 0 0 0 0 0 1 h 1",
                "angular resolution 1e-30 rad is below 1e-4 rad"},
        BadLine{"ROBOTLASER1 0 -1.5 3 0.01 0 0.01 0 2 1 1 0 0 0 0 0 0 0 0 0 0 0 0 1 h 1",
                "maximum range 0 m"},
        BadLine{"ROBOTLASER1 0 -1.5 3 0.01 8 0.01 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 1 h 1",
                "a scan without beams"},
        BadLine{"FLASER 0 0 0 0 0 0 0 1 h 1", "a scan without beams"},
        BadLine{[] {
                  std::string line = "FLASER 20001";
                  for (int i = 0; i < 20001; ++i) line += " 1";
                  return line + " 0 0 0 0 0 0 1 h 1";
                }(),
                "20001 beams: more than the 20000 of any 2-D laser"},
        BadLine{"ROBOTLASER1 0 1e300 3 0.01 8 0.01 0 2 1 1 0 0 0 0 0 0 0 0 0 0 0 0 1 h 1",
                "start angle 1e+300"},
        BadLine{"ROBOTLASER1 0 -1.5 -3 0.01 8 0.01 0 2 1 1 0 0 0 0 0 0 0 0 0 0 0 0 1 h 1",
                "field of view -3 rad is negative"},
        BadLine{"ROBOTLASER1 0 -1.5 3 7 8 0.01 0 2 1 1 0 0 0 0 0 0 0 0 0 0 0 0 1 h 1",
                "more than a full turn"},
        // Binary junk was skipped as an unknown message type, uncounted; control
        // bytes are escaped in the message.
        BadLine{"\x7f\x01"
                "ELF\x02 1 2",
                "not a CARMEN message: it starts with '\\x7f\\x01ELF\\x02'"},
        BadLine{"1.5 2 3", "not a CARMEN message: it starts with '1.5'"},
        // Found by fuzz_carmen: a laser type of 5e9 overflowed its int (UBSan).
        BadLine{"ROBOTLASER1 5.3e9 -1.5 3 0.01 8 0.01 0 2 1 1 0 0 0 0 0 0 0 0 0 0 0 0 1 h 1",
                "laser_type 5.3e+09 is beyond +-1e+06"}));

TEST(CarmenLog, AByteOrderMarkIsSkipped) {
  const CarmenReadResult r = ParseCarmenLog("\xEF\xBB\xBFODOM 1 2 0.5 0 0 0 1.0 h 1.0\n", "b.clf");
  ASSERT_TRUE(r.log.ok()) << r.log.error;
  EXPECT_EQ(r.log.value->Odometry().size(), 1u);
}

TEST(CarmenLog, ADirectoryIsNotALog) {
  const CarmenReadResult r = ReadCarmenLog(::testing::TempDir());
  ASSERT_FALSE(r.log.ok());
  EXPECT_NE(r.log.error.find("is a directory, not a log"), std::string::npos) << r.log.error;
}

// A FLASER step given in the options that wraps the scan (--flaser-step-deg 10 on intel's 180
// beams: 1790 deg) is refused at the first scan, naming its line.
TEST(CarmenLog, FlaserStepThatWrapsTheScanIsRefused) {
  CarmenReadOptions options;
  options.flaser_angular_step_rad = 10.0 * kernel::kPi / 180.0;
  std::string ranges;
  for (int i = 0; i < 180; ++i) ranges += " 1";
  const CarmenReadResult r =
      ParseCarmenLog("# c\nFLASER 180" + ranges + " 0 0 0 0 0 0 1 h 1\n", "w.clf", options);
  ASSERT_FALSE(r.log.ok());
  EXPECT_EQ(r.log.error.rfind("w.clf:2: FLASER: 180 beams", 0), 0u) << r.log.error;
  options.flaser_angular_step_rad = 1.0 * kernel::kPi / 180.0;
  EXPECT_TRUE(ParseCarmenLog("# c\nFLASER 180" + ranges + " 0 0 0 0 0 0 1 h 1\n", "w.clf", options)
                  .log.ok());
}

TEST(CarmenLog, MissingFileIsAnError) {
  const CarmenReadResult r = ReadCarmenLog("/nonexistent/log.clf");
  ASSERT_FALSE(r.log.ok());
  EXPECT_EQ(r.log.error, "/nonexistent/log.clf: cannot open for reading");
}

TEST(CarmenLog, WritesAndReadsFiles) {
  const std::string path = ::testing::TempDir() + "/carmen_test.clf";
  CarmenLog log;
  log.messages.push_back(OdometryMessage{Pose2(1, 2, 0.5), 0, 0, 0, {}});
  ASSERT_EQ(WriteCarmenLog(path, log).message(), "");
  const CarmenReadResult r = ReadCarmenLog(path);
  ASSERT_TRUE(r.log.ok());
  EXPECT_EQ(r.log.value->Odometry()[0]->pose.ToVector(), Pose2(1, 2, 0.5).ToVector());
  EXPECT_NE(WriteCarmenLog("/nonexistent/dir/x.clf", log).message(), "");
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace splam::io

namespace splam::io {
namespace {

// A FLASER log of `scans` scans of 180 beams, each beam's range from `range`.
std::string FlaserLog(int scans, const std::function<double()>& range) {
  std::string text;
  for (int s = 0; s < scans; ++s) {
    text += "FLASER 180";
    for (int b = 0; b < 180; ++b) text += " " + std::to_string(range());
    const std::string stamp = std::to_string(100.0 + s);
    text += " 0 0 0 0 0 0 " + stamp + " host " + stamp + "\n";
  }
  return text;
}

// Ranges drawn from 0.5-20 m, except a share of beams written as `no_return` (plus up to
// 0.07 m, as MIT Killian's SICK writes them).
std::string LogWithPile(int scans, double pile_share, double no_return, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  return FlaserLog(
      scans, [&] { return u(gen) < pile_share ? no_return + 0.07 * u(gen) : 0.5 + 19.5 * u(gen); });
}

// Property: over random logs (fixed seeds), a pile of 0.5-5 % of the beams at 51.05 m is found
// from 51.05 m up and every piled reading becomes a no-return; the same logs without the pile,
// and a log whose every beam reads one range (a robot parked facing a wall), have none.
TEST(NoReturnPile, PropertyAPileAtTheTopIsFoundAndNothingElse) {
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const double share = 0.005 + 0.045 * (seed - 1) / 19.0;
    CarmenReadResult piled = ParseCarmenLog(LogWithPile(100, share, 51.05, seed), "mem");
    ASSERT_TRUE(piled.log.ok()) << piled.log.error;
    const std::optional<NoReturnPile> pile = FindNoReturnPile(*piled.log.value);
    ASSERT_TRUE(pile.has_value()) << "seed " << seed;
    EXPECT_NEAR(pile->from_m, 51.05, 0.01);
    EXPECT_NEAR(pile->share, share, 0.5 * share + 0.002);
    MarkNoReturns(pile->from_m, &*piled.log.value);
    for (const LaserMessage* m : piled.log.value->Lasers()) {
      for (std::size_t i = 0; i < m->scan.size(); ++i) {
        if (m->scan.IsHit(i)) {
          EXPECT_LT(m->scan.ranges_m[i], 20.0 + 1e-9);
        }
      }
    }
    const CarmenReadResult clean = ParseCarmenLog(LogWithPile(100, 0.0, 51.05, seed), "mem");
    EXPECT_FALSE(FindNoReturnPile(*clean.log.value).has_value()) << "seed " << seed;
  }
  const std::string wall = FlaserLog(50, [] { return 3.0; });
  EXPECT_FALSE(FindNoReturnPile(*ParseCarmenLog(wall, "mem").log.value).has_value());
}

}  // namespace
}  // namespace splam::io
