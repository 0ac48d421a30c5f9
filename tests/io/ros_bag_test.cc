#include "io/ros_bag.h"

#include <gtest/gtest.h>
#include <link.h>
#include <sys/stat.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>

#include "io/internal/ros2_bag_file.h"
#include "io/internal/rosbag_file.h"
#include "io/text.h"
#include "io/trajectory.h"
#include "kernel/angle.h"
#include "kernel/random.h"

namespace splam::io {
namespace {

std::string TempBag(const std::string& name, const std::string& extension = ".bag") {
  return ::testing::TempDir() + "/" + name + extension;
}

// Writes messages as a ROS 1 bag (.bag) or a ROS 2 bag (.mcap, .db3): the checks after reading
// are the same for all three.
void WriteBag(const std::string& path, const internal::RosBagMessages& bag) {
  if (path.ends_with(".bag"))
    internal::WriteMessages(path, "/scan", "/odom", "/ground_truth", bag);
  else
    internal::WriteRos2Bag(
        path,
        path.ends_with(".mcap") ? internal::Ros2Storage::kMcap : internal::Ros2Storage::kSqlite3,
        "/scan", "/odom", "/ground_truth", bag);
}
constexpr const char* kBagExtensions[] = {".bag", ".mcap", ".db3"};

// A short log as the simulator writes one: at every step ODOM, TRUEPOS and a scan taken by a
// laser 0.1 m ahead of the robot, with a no-return and an invalid beam.
CarmenLog ShortLog(int steps) {
  kernel::Random random(7);
  CarmenLog log;
  const kernel::Pose2 robot_T_laser(0.1, 0.0, 0.0);
  for (int i = 0; i < steps; ++i) {
    const double t = 10.0 + 0.1 * i;
    const kernel::Pose2 odometry(0.05 * i, 0.01 * i, 0.03 * i);
    log.messages.push_back(OdometryMessage{odometry, 0.5, 0.3, 0.0, {t, "sim", t}});
    log.messages.push_back(
        TruePoseMessage{kernel::Pose2(0.05 * i + 0.01, 0.0, 0.02 * i), odometry, {t, "sim", t}});
    LaserMessage laser;
    laser.scan.timestamp_s = t;
    laser.scan.start_angle_rad = -kernel::kPi / 2;
    laser.scan.angular_step_rad = kernel::kPi / 180;
    laser.scan.max_range_m = 8.0;
    for (int b = 0; b < 181; ++b) laser.scan.ranges_m.push_back(0.5 + 7.0 * random.Uniform());
    laser.scan.ranges_m[3] = kernel::Scan::kNoReturn;
    laser.scan.ranges_m[4] = std::numeric_limits<double>::quiet_NaN();
    laser.robot_pose = odometry;
    laser.laser_pose = odometry * robot_T_laser;
    laser.stamp = {t, "sim", t};
    log.messages.push_back(laser);
  }
  return log;
}

TEST(RosBag, WriteThenReadGivesTheSameScansPosesAndMounting) {
  const CarmenLog log = ShortLog(20);
  const std::string path = TempBag("round_trip");
  RosBagWriteStats written;
  ASSERT_EQ(WriteRosBag(log, path, {}, &written).message(), "");
  EXPECT_EQ(written.scans, 20);
  EXPECT_EQ(written.odometry, 20);  // ODOM and the scans' poses share their times
  EXPECT_EQ(written.true_poses, 20);
  const RosBagReadResult read = ReadRosBag(path);
  ASSERT_TRUE(read.log.ok()) << read.log.error;
  EXPECT_EQ(read.stats.topics.at("/scan"), 20);
  EXPECT_EQ(read.stats.topics.at("/tf_static"), 1);
  const auto in = log.Lasers();
  const auto out = read.log.value->Lasers();
  ASSERT_EQ(out.size(), in.size());
  for (std::size_t i = 0; i < in.size(); ++i) {
    EXPECT_EQ(out[i]->scan.timestamp_s, in[i]->scan.timestamp_s);
    EXPECT_NEAR(out[i]->scan.start_angle_rad, in[i]->scan.start_angle_rad, 1e-7);  // float32
    EXPECT_NEAR(out[i]->scan.angular_step_rad, in[i]->scan.angular_step_rad, 1e-9);
    EXPECT_EQ(out[i]->scan.max_range_m, 8.0);
    ASSERT_EQ(out[i]->scan.size(), 181u);
    for (std::size_t b = 0; b < 181; ++b) {
      if (b == 3) {
        EXPECT_TRUE(out[i]->scan.IsNoReturn(b));
      } else if (b == 4) {
        EXPECT_TRUE(std::isnan(out[i]->scan.ranges_m[b]));
      } else {
        EXPECT_EQ(out[i]->scan.ranges_m[b], static_cast<float>(in[i]->scan.ranges_m[b]));
      }
    }
    EXPECT_LT((out[i]->robot_pose.ToVector() - in[i]->robot_pose.ToVector()).norm(), 1e-12);
    EXPECT_LT((out[i]->laser_pose.ToVector() - in[i]->laser_pose.ToVector()).norm(), 1e-12);
  }
  const auto truth = read.log.value->TruePoses();
  ASSERT_EQ(truth.size(), 20u);
  EXPECT_NEAR(truth[5]->true_pose.x(), 0.26, 1e-12);
  EXPECT_NEAR(truth[5]->odometry_pose.theta(), 0.15, 1e-12);
}

// A bag as a robot records one: odometry only in /tf (odom -> base_link), the laser mounted
// through a chain in /tf_static (base_link -> mount -> laser), scans before the odometry starts.
TEST(RosBag, OdometryFromTfAndTheMountingThroughAChainOfStaticTransforms) {
  internal::RosBagMessages bag;
  for (int i = 0; i < 10; ++i) {
    const double t = 5.0 + i;
    bag.tf.push_back({t, "odom", "base_link", 1.0 * i, 0.0, 0.0, 0.0, 0.0});
    bag.tf.push_back({t, "odom", "other", 9.0, 9.0, 0.0, 0.0, 0.0});  // not the robot
    bag.scans.push_back({t - 0.5, "laser", -1.0, 0.01, 0.05, 30.0, std::vector<float>(201, 2.0f)});
  }
  bag.tf_static.push_back({0.0, "base_link", "mount", 0.2, 0.0, 0.0, 0.0, 0.0});
  bag.tf_static.push_back({0.0, "mount", "laser", 0.0, 0.1, kernel::kPi / 2, 0.0, 0.0});
  const std::string path = TempBag("tf");
  internal::WriteMessages(path, "/base_scan", "/odom", "/ground_truth", bag);
  const RosBagReadResult read = ReadRosBag(path);
  ASSERT_TRUE(read.log.ok()) << read.log.error;
  // The first scan (t 4.5) comes before the odometry: dropped and counted.
  EXPECT_EQ(read.stats.scans_outside_odometry, 1);
  const auto lasers = read.log.value->Lasers();
  ASSERT_EQ(lasers.size(), 9u);
  // t 5.5: halfway between x 0 and x 1.
  EXPECT_NEAR(lasers[0]->robot_pose.x(), 0.5, 1e-12);
  const kernel::Pose2 mounting = lasers[0]->robot_pose.Between(lasers[0]->laser_pose);
  EXPECT_NEAR(mounting.x(), 0.2, 1e-6);
  EXPECT_NEAR(mounting.y(), 0.1, 1e-6);
  EXPECT_NEAR(mounting.theta(), kernel::kPi / 2, 1e-6);
  EXPECT_EQ(read.log.value->Odometry().size(), 10u);
  // Below range_min is invalid (REP 117).
  EXPECT_EQ(lasers[0]->scan.min_range_m, static_cast<float>(0.05));
}

// A LaserScan whose range_min lies above its range_max, or without ranges:
// refused, naming the scan and the topic, instead of running as if valid.
TEST(RosBag, ScansWithoutBeamsOrWithRangesUpsideDownAreRefused) {
  for (const char* extension : kBagExtensions)
    for (const bool empty : {false, true}) {
      internal::RosBagMessages bag;
      for (int i = 0; i < 3; ++i) {
        bag.odometry.push_back({1.0 + i, "odom", "base_link", 0.1 * i, 0.0, 0.0, 0.0, 0.0});
        bag.scans.push_back({1.5 + i, "base_link", -1.0, 0.01, i == 1 && !empty ? 40.0 : 0.05, 30.0,
                             std::vector<float>(i == 1 && empty ? 0 : 201, 2.0f)});
      }
      const std::string path = TempBag(empty ? "no_beams" : "range_min", extension);
      WriteBag(path, bag);
      const RosBagReadResult read = ReadRosBag(path);
      ASSERT_FALSE(read.log.ok());
      EXPECT_NE(
          read.log.error.find(empty ? "scan 2 on /scan: a scan without beams"
                                    : "scan 2 on /scan: minimum range 40 m is not in [0, 30)"),
          std::string::npos)
          << read.log.error;
    }
}

// Issue 70, item 3: a LaserScan of one beam whose angle_increment is NaN or infinite passed the
// checks (the step was checked with two beams or more only) and crashed every SLAM method in the
// occupancy grid (SIGSEGV); `convert` wrote it into a log that splam then refused.
TEST(RosBag, AOneBeamScanWithAStepThatIsNotFiniteIsRefused) {
  for (const char* extension : kBagExtensions)
    for (const double step :
         {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
      internal::RosBagMessages bag;
      for (int i = 0; i < 3; ++i) {
        bag.odometry.push_back({1.0 + i, "odom", "base_link", 0.1 * i, 0.0, 0.0, 0.0, 0.0});
        bag.scans.push_back({1.5 + i, "base_link", -1.0, i == 1 ? step : 0.01, 0.05, 30.0,
                             std::vector<float>(i == 1 ? 1 : 201, 2.0f)});
      }
      const std::string path = TempBag("one_beam", extension);
      WriteBag(path, bag);
      const RosBagReadResult read = ReadRosBag(path);
      ASSERT_FALSE(read.log.ok()) << extension;
      EXPECT_NE(read.log.error.find("scan 2 on /scan: angular resolution "), std::string::npos)
          << read.log.error;
      EXPECT_NE(read.log.error.find(" rad is not a finite angle of 0 or more"), std::string::npos)
          << read.log.error;
    }
}

// Issue 70, item 4: the laser mounting from /tf_static was not checked: a NaN or 1e300 transform
// ran to exit 4 ("keyframes spread over 2.7e69 m") instead of naming the bag and the frame.
TEST(RosBag, AStaticTransformThatIsNotFiniteOrBeyondAMillionMetresIsRefused) {
  for (const char* extension : kBagExtensions)
    for (const double x : {std::numeric_limits<double>::quiet_NaN(), 1e300}) {
      internal::RosBagMessages bag;
      for (int i = 0; i < 3; ++i) {
        bag.odometry.push_back({1.0 + i, "odom", "base_link", 0.1 * i, 0.0, 0.0, 0.0, 0.0});
        bag.scans.push_back({1.5 + i, "laser", -1.0, 0.01, 0.05, 30.0, std::vector<float>(201, 2)});
      }
      bag.tf_static.push_back({0.0, "base_link", "laser", x, 0.0, 0.0, 0.0, 0.0});
      const std::string path = TempBag("mounting", extension);
      WriteBag(path, bag);
      const RosBagReadResult read = ReadRosBag(path);
      ASSERT_FALSE(read.log.ok()) << extension;
      EXPECT_EQ(read.log.error.find(path + ": "), 0u) << read.log.error;
      EXPECT_NE(read.log.error.find("/tf_static: the transform base_link -> laser " +
                                    FormatDouble(x) + " is not finite or beyond +-1e+06 m"),
                std::string::npos)
          << read.log.error;
    }
}

// Issue 70, item 5: a newline in a topic name (chosen by whoever wrote the bag) or in the bag's
// path went unchanged into the converted log's comment, where the line after it became data.
TEST(RosBag, ANewlineInATopicOrPathIsNoLineOfTheConvertedLog) {
  for (const char* extension : {".bag", ".mcap", ".db3"}) {
    internal::RosBagMessages bag;
    for (int i = 0; i < 3; ++i) {
      bag.odometry.push_back({1.0 + i, "odom", "base_link", 0.1 * i, 0.0, 0.0, 0.0, 0.0});
      bag.scans.push_back(
          {1.5 + i, "base_link", -1.0, 0.01, 0.05, 30.0, std::vector<float>(201, 2.0f)});
    }
    const std::string injected = "\nODOM 5 5 0 0 0 0 1e9 h 1e9\r\nROBOTLASER1";
    const std::string path = TempBag("inject" + injected, extension);
    const std::string topic = "/scan" + injected;
    if (std::string(extension) == ".bag")
      internal::WriteMessages(path, topic, "/odom", "/ground_truth", bag);
    else
      internal::WriteRos2Bag(path,
                             std::string(extension) == ".mcap" ? internal::Ros2Storage::kMcap
                                                               : internal::Ros2Storage::kSqlite3,
                             topic, "/odom", "/ground_truth", bag);
    const RosBagReadResult read = ReadRosBag(path);
    ASSERT_TRUE(read.log.ok()) << read.log.error;
    const std::size_t messages = read.log.value->messages.size();
    const std::string text = FormatCarmenLog(*read.log.value);
    EXPECT_EQ(text.find("\nODOM 5 5"), std::string::npos) << extension;
    EXPECT_NE(text.find("\\x0aODOM 5 5 0 0 0 0 1e9 h 1e9\\x0d\\x0aROBOTLASER1"), std::string::npos)
        << text.substr(0, 300);
    const CarmenReadResult again = ParseCarmenLog(text, "converted.clf");
    ASSERT_TRUE(again.log.ok()) << again.log.error;
    EXPECT_EQ(again.log.value->messages.size(), messages) << extension;
  }
}

// Issue 70, item 10: a FIFO given as a bag blocked for ever, a device never ended.
TEST(RosBag, AFifoOrADeviceIsNoBag) {
  for (const char* extension : kBagExtensions) {
    const std::string fifo = TempBag("fifo", extension);
    std::filesystem::remove(fifo);
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    const RosBagReadResult from_fifo = ReadRosBag(fifo);
    ASSERT_FALSE(from_fifo.log.ok());
    EXPECT_NE(from_fifo.log.error.find("is not a regular file (a FIFO or a device)"),
              std::string::npos)
        << from_fifo.log.error;
    const std::string device = TempBag("zero", extension);
    std::filesystem::remove(device);
    std::filesystem::create_symlink("/dev/zero", device);
    const RosBagReadResult from_device = ReadRosBag(device);
    ASSERT_FALSE(from_device.log.ok());
    EXPECT_NE(from_device.log.error.find("is not a regular file"), std::string::npos)
        << from_device.log.error;
  }
}

class RosBagTopics : public ::testing::TestWithParam<const char*> {};

TEST_P(RosBagTopics, TopicsAndMountingThatCannotBeChosenAreNamed) {
  internal::RosBagMessages bag;
  bag.scans.push_back({1.0, "laser", -1.0, 0.01, 0.05, 30.0, std::vector<float>(201, 2.0f)});
  bag.odometry.push_back({1.0, "odom", "base_link", 0.0, 0.0, 0.0, 0.0, 0.0});
  const std::string path = TempBag("no_mounting", GetParam());
  WriteBag(path, bag);
  // The scans' frame "laser" is not the base frame, and nothing says where it is mounted.
  RosBagReadResult read = ReadRosBag(path);
  ASSERT_FALSE(read.log.ok());
  EXPECT_NE(read.log.error.find("no transform from base_link to the scans' frame laser"),
            std::string::npos)
      << read.log.error;
  RosBagOptions options;
  options.base_T_laser = kernel::Pose2(0.1, 0.0, 0.0);
  EXPECT_TRUE(ReadRosBag(path, options).log.ok());
  // A topic that is not there, or of another type, is named with the bag's topics.
  options.scan_topic = "/laser";
  read = ReadRosBag(path, options);
  ASSERT_FALSE(read.log.ok());
  EXPECT_NE(read.log.error.find("no topic /laser; the bag's topics: /odom (nav_msgs/Odometry, 1 "
                                "messages), /scan (sensor_msgs/LaserScan, 1 messages)"),
            std::string::npos)
      << read.log.error;
  options.scan_topic = "/odom";
  EXPECT_NE(ReadRosBag(path, options).log.error.find("holds nav_msgs/Odometry"), std::string::npos);
  // No odometry and no /tf.
  internal::RosBagMessages scans_only;
  scans_only.scans = bag.scans;
  const std::string lonely = TempBag("scans_only", GetParam());
  WriteBag(lonely, scans_only);
  read = ReadRosBag(lonely);
  ASSERT_FALSE(read.log.ok());
  EXPECT_NE(read.log.error.find("no nav_msgs/Odometry topic (choose one with --odom-topic)"),
            std::string::npos)
      << read.log.error;
  EXPECT_NE(read.log.error.find("and no /tf to read it from"), std::string::npos);
}

INSTANTIATE_TEST_SUITE_P(RosBag, RosBagTopics, ::testing::ValuesIn(kBagExtensions),
                         [](const auto& format) { return std::string(format.param + 1); });

// Whether a shared object whose file name contains `name` is loaded in this process.
bool SharedObjectLoaded(const char* name) {
  return dl_iterate_phdr(
             [](dl_phdr_info* info, std::size_t, void* data) {
               return std::strstr(info->dlpi_name, static_cast<const char*>(data)) ? 1 : 0;
             },
             const_cast<char*>(name)) != 0;
}

// rosbag::Bag loads its encryptor plugins (and gpgme) and unloads them when it is destroyed; the
// reader keeps them loaded, so that a process reading many bags (a fuzzer: 5x the bags per
// second) does not load and unload four libraries for each.
TEST(RosBag, TheEncryptorPluginsAreLoadedOncePerProcess) {
  const std::string path = TempBag("plugins");
  ASSERT_EQ(WriteRosBag(ShortLog(2), path, {}, nullptr).message(), "");
  ASSERT_TRUE(ReadRosBag(path).log.ok());
  EXPECT_TRUE(SharedObjectLoaded("rosbag_default_encryption_plugins"));
}

TEST(RosBag, WhatIsNotABagIsRefused) {
  const std::string junk = ::testing::TempDir() + "/junk.bag";
  ASSERT_EQ(WriteTextFile(junk, "#ROSBAG V2.0\nnot really\n").message(), "");
  RosBagReadResult read = ReadRosBag(junk);
  ASSERT_FALSE(read.log.ok());
  EXPECT_EQ(read.log.error.rfind(junk + ": not a readable ROS bag", 0), 0u) << read.log.error;
  read = ReadRosBag("/nonexistent.bag");
  EXPECT_FALSE(read.log.ok());
  read = ReadRosBag(::testing::TempDir());
  EXPECT_NE(read.log.error.find("is a directory, not a bag"), std::string::npos);
  // Found by fuzz_bag: a header field longer than its header made Debian's rosbag read past its
  // buffer (ASan). The framing is checked before rosbag reads the file.
  const std::string good = TempBag("good");
  ASSERT_EQ(WriteRosBag(ShortLog(3), good).message(), "");
  std::string bytes;
  ASSERT_EQ(ReadTextFile(good, &bytes).message(), "");
  EXPECT_EQ(RosBagFramingProblem(good).message(), "");
  bytes[13 + 4] = '\x7f';  // the first field's length, past the first record's header
  const std::string broken = TempBag("broken");
  ASSERT_EQ(WriteTextFile(broken, bytes).message(), "");
  read = ReadRosBag(broken);
  ASSERT_FALSE(read.log.ok());
  EXPECT_NE(read.log.error.find("record 1: a header field runs past its header"), std::string::npos)
      << read.log.error;
  // Found by fuzz_bag: an index entry whose offset is not a message of its chunk made rosbag's
  // Bag::readHeaderFromBuffer read outside the chunk (ASan). Walk the records to the first
  // index data record (op 4) and move its first entry's offset by one byte.
  ASSERT_EQ(ReadTextFile(good, &bytes).message(), "");
  const auto u32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(bytes[at + i]);
    return v;
  };
  // Where the data of the first top-level record with op `op` starts (after the 13-byte magic:
  // header length, header, data length); npos when there is none.
  const auto data_of_first = [&](char op) {
    std::size_t at = 13;
    while (at < bytes.size() &&
           bytes.substr(at + 4, u32(at)).find(std::string("op=") + op) == std::string::npos)
      at += 4 + u32(at) + 4 + u32(at + 4 + u32(at));
    return at < bytes.size() ? at + 4 + u32(at) + 4 : std::string::npos;
  };
  std::size_t data = data_of_first('\x04');
  ASSERT_NE(data, std::string::npos) << "no index data record in the bag";
  ++bytes[data + 8];
  ASSERT_EQ(WriteTextFile(broken, bytes).message(), "");
  read = ReadRosBag(broken);
  ASSERT_FALSE(read.log.ok());
  EXPECT_NE(read.log.error.find(": an index entry that is not a message of its chunk"),
            std::string::npos)
      << read.log.error;
  // A bzip2 chunk claiming 4 GiB uncompressed made rosbag allocate it (an
  // abort where the allocation failed). The size field of the first chunk gets 0xf0000000.
  {
    internal::RosBagMessages small;
    small.scans.push_back(
        {1.0, "base_link", -1.0, 0.01, 0.05, 30.0, std::vector<float>(181, 2.0f)});
    small.odometry.push_back({1.0, "odom", "base_link", 0.0, 0.0, 0.0, 0.0, 0.0});
    const std::string compressed = TempBag("bz2");
    internal::WriteMessages(compressed, "/scan", "/odom", "/ground_truth", small, true);
    ASSERT_TRUE(ReadRosBag(compressed).log.ok());
    std::string raw;
    ASSERT_EQ(ReadTextFile(compressed, &raw).message(), "");
    const std::size_t bz2 = raw.find("compression=bz2");
    ASSERT_NE(bz2, std::string::npos);
    const std::size_t size = raw.find("size=", bz2 > 40 ? bz2 - 40 : 0);
    ASSERT_LT(size, bz2 + 40);
    raw.replace(size + 5, 4, std::string("\x00\x00\x00\xf0", 4));
    ASSERT_EQ(WriteTextFile(broken, raw).message(), "");
    read = ReadRosBag(broken);
    ASSERT_FALSE(read.log.ok());
    EXPECT_NE(read.log.error.find("a compressed chunk claiming 4026531840 bytes uncompressed"),
              std::string::npos)
        << read.log.error;
  }
  // A scan whose beams wrap the circle (a resolution in degrees) is refused at the reader.
  internal::RosBagMessages bag;
  bag.scans.push_back({1.0, "base_link", -1.0, 0.36, 0.05, 30.0, std::vector<float>(181, 2.0f)});
  bag.odometry.push_back({1.0, "odom", "base_link", 0.0, 0.0, 0.0, 0.0, 0.0});
  const std::string wrapping = TempBag("wrapping");
  internal::WriteMessages(wrapping, "/scan", "/odom", "/ground_truth", bag);
  read = ReadRosBag(wrapping);
  ASSERT_FALSE(read.log.ok());
  EXPECT_NE(read.log.error.find("scan 1 on /scan: 181 beams"), std::string::npos) << read.log.error;
  // Found by fuzz_bag (in CI): a connection record's own header with a field past its end made
  // ros::Header::parse read past its buffer (ASan). The first connection record (op 7) of the
  // good bag gets a first field of 0x7f7f7f7f bytes in its data, the connection's header.
  ASSERT_EQ(ReadTextFile(good, &bytes).message(), "");
  data = data_of_first('\x07');
  ASSERT_NE(data, std::string::npos) << "no connection record in the bag";
  bytes.replace(data, 4, "\x7f\x7f\x7f\x7f");
  ASSERT_EQ(WriteTextFile(broken, bytes).message(), "");
  read = ReadRosBag(broken);
  ASSERT_FALSE(read.log.ok());
  EXPECT_NE(read.log.error.find(": its connection header: a header field runs past its header"),
            std::string::npos)
      << read.log.error;
  // Found by fuzz_bag: ROS deserialization sized a vector by the length in the message before
  // reading it (a 580 GB request). A scan's range count past its message is refused.
  bag.scans.front().angle_increment = 0.01;
  const std::string lying = TempBag("lying");
  internal::WriteMessages(lying, "/scan", "/odom", "/ground_truth", bag);
  ASSERT_EQ(ReadTextFile(lying, &bytes).message(), "");
  const std::string count("\xb5\0\0\0\0\0\0\x40", 8);  // 181 ranges, the first 2.0f
  const std::size_t ranges = bytes.find(count);
  ASSERT_NE(ranges, std::string::npos);
  bytes.replace(ranges, 4, "\xff\xff\xff\x7f");
  ASSERT_EQ(WriteTextFile(lying, bytes).message(), "");
  read = ReadRosBag(lying);
  ASSERT_FALSE(read.log.ok());
  EXPECT_NE(read.log.error.find("a sensor_msgs/LaserScan message on /scan whose array lengths run "
                                "past its"),
            std::string::npos)
      << read.log.error;
  // Negative times have no ROS time.
  CarmenLog log = ShortLog(2);
  std::get<OdometryMessage>(log.messages[0]).stamp.ipc_timestamp_s = -1.0;
  EXPECT_NE(WriteRosBag(log, TempBag("negative")).message().find("outside ROS time"),
            std::string::npos);
}

}  // namespace
}  // namespace splam::io
