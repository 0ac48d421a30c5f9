// ROS 2 bags: fixtures written by libraries independent of splam (tests/data/ros2/
// make_fixtures.mjs: @mcap/core, @foxglove/rosmsg2-serialization, sql.js, zstd and lz4 from npm)
// read as the script's formulas say, and damaged bags refused with what is wrong.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>

#include "io/internal/ros2_bag_file.h"
#include "io/ros_bag.h"
#include "io/trajectory.h"

namespace splam::io {
namespace {

std::string Fixture(const std::string& name) {
  return std::string(SPLAM_TEST_DATA_DIR) + "/ros2/" + name;
}

class Ros2Fixture : public ::testing::TestWithParam<const char*> {};

TEST_P(Ros2Fixture, ReadsWhatTheIndependentWriterWrote) {
  const std::string name = GetParam();
  ASSERT_TRUE(IsRosBagPath(Fixture(name)));
  const RosBagReadResult read = ReadRosBag(Fixture(name));
  ASSERT_TRUE(read.log.ok()) << read.log.error;
  const CarmenLog& log = *read.log.value;
  const auto lasers = log.Lasers();
  ASSERT_EQ(lasers.size(), 30u);
  const bool with_truth = name != "tf_zstd.mcap";  // that one has odometry on /tf, no truth
  EXPECT_EQ(log.TruePoses().size(), with_truth ? 31u : 0u);
  EXPECT_EQ(read.stats.odometry, 31);
  const double t0 = 1700000000.5;
  const kernel::Pose2 base_T_laser(0.2, 0.0, 0.1);
  for (int i = 0; i < 30; ++i) {
    const LaserMessage& m = *lasers[static_cast<std::size_t>(i)];
    EXPECT_NEAR(m.scan.timestamp_s, t0 + 0.1 * i, 1e-6) << i;
    EXPECT_NEAR(m.scan.start_angle_rad, -2.0, 1e-6);
    EXPECT_NEAR(m.scan.angular_step_rad, 0.5, 1e-6);
    EXPECT_NEAR(m.scan.max_range_m, 8.0, 1e-6);
    ASSERT_EQ(m.scan.size(), 9u);
    for (std::size_t j = 0; j < 9; ++j) {
      if (j == 4) {
        EXPECT_TRUE(m.scan.IsNoReturn(j)) << i;
      } else if (i == 0 && j == 7) {
        EXPECT_TRUE(std::isnan(m.scan.ranges_m[j])) << "NaN reads as an invalid beam";
      } else {
        EXPECT_NEAR(m.scan.ranges_m[j], 1 + 0.25 * static_cast<double>(j) + 0.01 * i, 1e-5);
      }
    }
    // Odometry k at t0 - 0.05 + 0.1 k: the scan lies halfway between k = i and i + 1 (times
    // near 1.7e9 s carry 2e-7 s in a double: the halfway point to 1e-6).
    const double k = i + 0.5;
    EXPECT_NEAR(m.robot_pose.x(), 0.05 * k, 1e-6) << i;
    EXPECT_NEAR(m.robot_pose.y(), 0.02 * k, 1e-6) << i;
    EXPECT_NEAR(m.robot_pose.theta(), 0.01 * k, 1e-6) << i;
    const kernel::Pose2 mounting = m.robot_pose.Between(m.laser_pose);
    EXPECT_NEAR((mounting.translation() - base_T_laser.translation()).norm(), 0.0, 1e-9);
    EXPECT_NEAR(mounting.theta(), 0.1, 1e-9);
  }
}

INSTANTIATE_TEST_SUITE_P(Ros2Bag, Ros2Fixture,
                         ::testing::Values("odom.db3", "tf_zstd.mcap", "odom_lz4.mcap", "bag_dir"),
                         [](const auto& fixture) {
                           std::string n = fixture.param;
                           for (char& c : n)
                             c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                           return n;
                         });

std::string Bytes(const std::string& path) {
  std::string bytes;
  EXPECT_EQ(ReadTextFile(path, &bytes).message(), "");
  return bytes;
}

std::string Damaged(const std::string& name, const std::string& bytes) {
  const std::string path = ::testing::TempDir() + "/" + name;
  EXPECT_EQ(WriteTextFile(path, bytes).message(), "");
  return path;
}

std::string ErrorOf(const std::string& path) {
  const RosBagReadResult read = ReadRosBag(path);
  EXPECT_FALSE(read.log.ok()) << path;
  return read.log.ok() ? std::string() : read.log.error;
}

// Where the first record with `opcode` starts in an MCAP file's bytes (after the magic).
std::size_t FirstRecord(const std::string& bytes, std::uint8_t opcode) {
  std::size_t at = 8;
  while (at + 9 <= bytes.size() && static_cast<std::uint8_t>(bytes[at]) != opcode) {
    std::uint64_t length = 0;
    std::memcpy(&length, bytes.data() + at + 1, 8);
    at += 9 + length;
  }
  return at;
}

TEST(Ros2Bag, DamagedMcapFilesAreRefusedSayingWhy) {
  const std::string good = Bytes(Fixture("tf_zstd.mcap"));
  EXPECT_NE(ErrorOf(Damaged("junk.mcap", "not an mcap file at all"))
                .find("not a readable ROS 2 bag: not an MCAP file (no MCAP magic at its start)"),
            std::string::npos);
  EXPECT_NE(ErrorOf(Damaged("cut.mcap", good.substr(0, good.size() / 2))).find("runs past the end"),
            std::string::npos);
  // A chunk's CRC (after opcode, length and three 8-byte fields) that does not match.
  std::string bytes = good;
  const std::size_t chunk = FirstRecord(bytes, 0x06);
  ASSERT_LT(chunk, bytes.size());
  bytes[chunk + 9 + 24] ^= 0x5a;
  EXPECT_NE(ErrorOf(Damaged("crc.mcap", bytes)).find("a chunk's CRC does not match its records"),
            std::string::npos);
  // An unknown compression (the name after the CRC: 4-byte length, then "zstd").
  bytes = good;
  ASSERT_EQ(bytes.substr(chunk + 9 + 28 + 4, 4), "zstd");
  bytes[chunk + 9 + 28 + 4 + 3] = 'x';
  EXPECT_NE(ErrorOf(Damaged("zstx.mcap", bytes))
                .find("chunk compression 'zstx' is not supported (known: none, zstd, lz4)"),
            std::string::npos);
  // A chunk claiming gigabytes from a few bytes.
  bytes = good;
  const std::uint64_t huge = std::uint64_t{1} << 40;
  std::memcpy(bytes.data() + chunk + 9 + 16, &huge, 8);
  EXPECT_NE(ErrorOf(Damaged("bomb.mcap", bytes)).find("a chunk claims 1099511627776 bytes"),
            std::string::npos);
  // Compressed bytes that are not zstd.
  bytes = good;
  bytes[chunk + 9 + 28 + 8 + 8 + 4] ^= 0x77;
  EXPECT_NE(ErrorOf(Damaged("badzstd.mcap", bytes)).find("a zstd chunk does not decompress"),
            std::string::npos);
}

TEST(Ros2Bag, DamagedSqliteBagsAndDirectoriesAreRefusedSayingWhy) {
  EXPECT_NE(ErrorOf(Damaged("junk.db3", std::string(2000, 'x'))).find("not a readable ROS 2 bag"),
            std::string::npos);
  EXPECT_NE(ErrorOf(Damaged("empty.db3", "")).find("not a rosbag2 database: no such table: topics"),
            std::string::npos);
  // A message that is not the CDR its topic's type says.
  const std::string path = ::testing::TempDir() + "/garbled.db3";
  std::filesystem::remove(path);
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(
      sqlite3_exec(db,
                   "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT, type TEXT, "
                   "serialization_format TEXT, offered_qos_profiles TEXT);"
                   "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER, "
                   "timestamp INTEGER, data BLOB);"
                   "INSERT INTO topics VALUES (1, '/scan', 'sensor_msgs/msg/LaserScan', "
                   "'cdr', '');"
                   "INSERT INTO topics VALUES (2, '/odom', 'nav_msgs/msg/Odometry', 'cdr', '');"
                   "INSERT INTO messages VALUES (1, 1, 5, x'00010000ffffffff');",
                   nullptr, nullptr, nullptr),
      SQLITE_OK);
  sqlite3_close(db);
  EXPECT_NE(ErrorOf(path).find("a message on /scan does not decode as sensor_msgs/msg/LaserScan"),
            std::string::npos)
      << ErrorOf(path);
  // A directory without metadata.yaml is no bag; one whose files are compressed is named.
  const std::filesystem::path dir = ::testing::TempDir() + "/ros2_dir";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  EXPECT_NE(ErrorOf(dir.string()).find("is a directory, not a bag"), std::string::npos);
  ASSERT_EQ(WriteTextFile((dir / "metadata.yaml").string(),
                          "rosbag2_bagfile_information:\n  relative_file_paths: [a.db3.zstd]\n"
                          "  compression_format: zstd\n")
                .message(),
            "");
  EXPECT_NE(ErrorOf(dir.string()).find("files compressed with zstd are not supported"),
            std::string::npos);
}

}  // namespace
}  // namespace splam::io
