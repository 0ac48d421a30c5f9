#include "io/trajectory.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include "kernel/angle.h"
#include "kernel/random.h"

namespace splam::io {
namespace {

TEST(Trajectory, PropertyWriteThenReadIsExact) {
  kernel::Random random(41);
  Trajectory t;
  double time = 0;
  for (int i = 0; i < 500; ++i) {
    time += random.Uniform(0, 0.2);
    t.push_back(
        {time, kernel::Pose2(random.Gaussian(10), random.Gaussian(10), random.Uniform(-3, 3))});
  }
  const Result<Trajectory> back = ParseTrajectory(FormatTrajectory(t, "test"), "mem");
  ASSERT_TRUE(back.ok()) << back.error;
  ASSERT_EQ(back.value->size(), t.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    EXPECT_EQ((*back.value)[i].time_s, t[i].time_s);
    EXPECT_EQ((*back.value)[i].pose.ToVector(), t[i].pose.ToVector());
  }
  EXPECT_EQ(Poses(t).size(), t.size());
}

TEST(Trajectory, BadLinesNameFileAndLine) {
  EXPECT_EQ(ParseTrajectory("# c\n0 1 2\n", "t.txt").error,
            "t.txt:2: expected 4 values 'time x y theta' (or 8 of TUM, 12 of KITTI), found 3");
  // Every line has the first pose's format.
  EXPECT_EQ(ParseTrajectory("0 1 2 3\n0 1 2 0 0 0 0 1\n", "t.txt").error,
            "t.txt:2: expected 4 values (splam 'time x y theta', as the first pose), found 8");
  EXPECT_EQ(ParseTrajectory("0 1 2 0 0 0 0 0\n", "t.tum").error,
            "t.tum:1: the quaternion (qx qy qz qw) is zero");
  EXPECT_EQ(ParseTrajectory("0 0 0 0 0 0 0 0 0 0 1 0\n", "t.kitti").error,
            "t.kitti:1: the rotation's first column (r00, r10) is zero: no heading in the plane");
  // A quaternion whose squares overflow still has its yaw (it gave a NaN heading).
  const auto huge = ParseTrajectory("0 1 2 0 0 0 1e300 1e300\n", "t.tum");
  ASSERT_TRUE(huge.ok()) << huge.error;
  EXPECT_NEAR(huge->at(0).pose.theta(), kernel::kPi / 2, 1e-12);
  EXPECT_EQ(ParseTrajectory("0 1 2 x\n", "t.txt").error, "t.txt:1: 'x' is not a finite number");
  EXPECT_EQ(ParseTrajectory("0 1 2 nan\n", "t.txt").error, "t.txt:1: 'nan' is not a finite number");
  // Out-of-order times (real logs jitter) are kept as they are.
  const auto jitter = ParseTrajectory("1 0 0 0\n0.995 1 0 0\n", "t.txt");
  ASSERT_TRUE(jitter.ok());
  EXPECT_EQ(jitter.value->at(1).time_s, 0.995);
  EXPECT_FALSE(ReadTrajectory("/nonexistent.txt").ok());
}

// TUM and KITTI, as evo writes and reads them: the same poses back to rounding (times exact in
// TUM; KITTI numbers its poses 0, 1, 2, ... as their times).
TEST(Trajectory, PropertyTumAndKittiRoundTrip) {
  kernel::Random random(43);
  Trajectory t;
  for (int i = 0; i < 300; ++i) {
    const double x = random.Gaussian(50), y = random.Gaussian(50);
    const double theta = random.Uniform(-3.14159, 3.14159);
    t.push_back({0.1 * i + 1e4, kernel::Pose2(x, y, theta)});
  }
  for (const TrajectoryFormat format : {TrajectoryFormat::kTum, TrajectoryFormat::kKitti}) {
    const Result<Trajectory> back = ParseTrajectory(FormatTrajectory(t, "c", format), "mem");
    ASSERT_TRUE(back.ok()) << back.error;
    ASSERT_EQ(back->size(), t.size());
    for (std::size_t i = 0; i < t.size(); ++i) {
      const kernel::StampedPose& b = (*back)[i];
      EXPECT_EQ(b.time_s, format == TrajectoryFormat::kTum ? t[i].time_s : static_cast<double>(i));
      EXPECT_NEAR(b.pose.x(), t[i].pose.x(), 1e-12);
      EXPECT_NEAR(b.pose.y(), t[i].pose.y(), 1e-12);
      EXPECT_NEAR(kernel::WrapAngle(b.pose.theta() - t[i].pose.theta()), 0.0, 1e-12);
    }
  }
}

// A TUM line of a 3-D trajectory (tilted, z and a non-unit quaternion): the heading is the yaw.
TEST(Trajectory, TumYawOfAGeneralQuaternion) {
  // Yaw 30 deg, then pitch 10 deg (rotation z-y-x), scaled by 2: q = 2 (qz(30) * qy(10)).
  const double cz = std::cos(kernel::DegToRad(15)), sz = std::sin(kernel::DegToRad(15));
  const double cy = std::cos(kernel::DegToRad(5)), sy = std::sin(kernel::DegToRad(5));
  const double qw = 2 * cz * cy, qx = -2 * sz * sy, qy = 2 * cz * sy, qz = 2 * sz * cy;
  const std::string line = "5 1 2 0.7 " + std::to_string(qx) + " " + std::to_string(qy) + " " +
                           std::to_string(qz) + " " + std::to_string(qw) + "\n";
  const Result<Trajectory> t = ParseTrajectory(line, "t.tum");
  ASSERT_TRUE(t.ok()) << t.error;
  EXPECT_NEAR(kernel::RadToDeg(t->at(0).pose.theta()), 30.0, 1e-4);
  EXPECT_EQ(t->at(0).pose.x(), 1.0);
  EXPECT_EQ(t->at(0).time_s, 5.0);
}

TEST(Trajectory, FileRoundTrip) {
  const std::string path = ::testing::TempDir() + "/trajectory_test.txt";
  ASSERT_EQ(WriteTrajectory(path, {{0.0, kernel::Pose2(1, 2, 3)}}).message(), "");
  const auto back = ReadTrajectory(path);
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back.value->at(0).pose.x(), 1.0);
  // The extension picks the format.
  EXPECT_EQ(TrajectoryFormatOf("a/b.tum"), TrajectoryFormat::kTum);
  EXPECT_EQ(TrajectoryFormatOf("b.kitti"), TrajectoryFormat::kKitti);
  const std::string tum = ::testing::TempDir() + "/trajectory_test.tum";
  ASSERT_EQ(WriteTrajectory(tum, {{2.5, kernel::Pose2(1, 2, 0)}}).message(), "");
  std::ifstream in(tum);
  std::string comment, first;
  std::getline(in, comment);
  std::getline(in, first);
  EXPECT_EQ(first, "2.5 1 2 0 0 0 0 1");
}

// A result file linked to /dev/full, read back for the report, grew to 24 GB
// (killed). A device is no text file, and no text file is read past its bound, which holds
// byte for byte up to it, through a pipe too.
TEST(ReadTextFile, DevicesAreRefusedAndFilesAreBounded) {
  std::string text = "left over";
  for (const char* device : {"/dev/zero", "/dev/full", "/dev/null"}) {
    if (!std::filesystem::exists(device)) continue;
    EXPECT_EQ(ReadTextFile(device, &text).message(),
              std::string(device) + ": is a device, not a file");
  }
  const std::string path = ::testing::TempDir() + "/read_text_file_test.txt";
  ASSERT_EQ(WriteTextFile(path, std::string(3'000'000, 'x') + "end").message(), "");
  ASSERT_EQ(ReadTextFile(path, &text, 3'000'003).message(), "");
  EXPECT_EQ(text.size(), 3'000'003u);
  EXPECT_TRUE(text.ends_with("xend"));
  EXPECT_EQ(ReadTextFile(path, &text, 3'000'002).message(),
            path + ": holds more than 3000002 bytes, the most a text file may hold");
  EXPECT_TRUE(text.empty());
  const std::string fifo = ::testing::TempDir() + "/read_text_file_test.fifo";
  std::filesystem::remove(fifo);
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  std::thread writer([&] { std::ofstream(fifo) << "0 1 2 3\n"; });
  EXPECT_EQ(ReadTextFile(fifo, &text).message(), "");
  writer.join();
  EXPECT_EQ(text, "0 1 2 3\n");
}

}  // namespace
}  // namespace splam::io
