#include "io/trajectory.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <thread>

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
            "t.txt:2: expected 4 values 'time x y theta', found 3");
  EXPECT_EQ(ParseTrajectory("0 1 2 x\n", "t.txt").error, "t.txt:1: 'x' is not a finite number");
  EXPECT_EQ(ParseTrajectory("0 1 2 nan\n", "t.txt").error, "t.txt:1: 'nan' is not a finite number");
  // Out-of-order times (real logs jitter) are kept as they are.
  const auto jitter = ParseTrajectory("1 0 0 0\n0.995 1 0 0\n", "t.txt");
  ASSERT_TRUE(jitter.ok());
  EXPECT_EQ(jitter.value->at(1).time_s, 0.995);
  EXPECT_FALSE(ReadTrajectory("/nonexistent.txt").ok());
}

TEST(Trajectory, FileRoundTrip) {
  const std::string path = ::testing::TempDir() + "/trajectory_test.txt";
  ASSERT_EQ(WriteTrajectory(path, {{0.0, kernel::Pose2(1, 2, 3)}}).message(), "");
  const auto back = ReadTrajectory(path);
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back.value->at(0).pose.x(), 1.0);
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
